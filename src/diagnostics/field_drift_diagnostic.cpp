#include "diagnostics/field_drift_diagnostic.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace dampsym {

DiagnosticInfo FieldDriftDiagnostic::info() {
    return {.name = std::string(name),
            .what = "dissipation drift d(t) = ln max_x u + Gamma of a damped wave field, B (5.6)",
            .requirement = "a field on a grid (field_size(): the damped Klein-Gordon problem)",
            .needs = {.grid = true, .ok_run = true},
            .metrics = {"slope", "range", "first", "last", "points"}};
}

json field_drift_metrics(const CaseFacts& c, const Mat& g, int n,
                         const std::function<double(double)>& Gamma) {
    if (g.cols() < 3) return {{"reason", "needs an output grid of at least three points"}};
    if (n < 1 || n > g.rows()) return {{"reason", "the problem declares no field"}};
    const double gamma0 = Gamma(c.t0);
    std::vector<double> t, d;
    for (Eigen::Index i = 1; i < g.cols(); ++i) { // t0 is exact: left out, as elsewhere
        const double m = g.col(i).head(n).maxCoeff();
        if (!(m > 0.0)) {
            json out = {{"points", static_cast<std::int64_t>(t.size())}};
            const char* why = "max_x u <= 0 at an output time: ln max_x u undefined";
            set_undefined(out, "slope", why);
            set_undefined(out, "range", why);
            return out;
        }
        t.push_back(c.grid_time(i));
        d.push_back(std::log(m) + (Gamma(t.back()) - gamma0));
    }
    // least-squares slope of d against t
    const double k = static_cast<double>(t.size());
    double st = 0, sd = 0;
    for (std::size_t i = 0; i < t.size(); ++i) {
        st += t[i];
        sd += d[i];
    }
    const double tm = st / k, dm = sd / k;
    double num = 0, den = 0;
    for (std::size_t i = 0; i < t.size(); ++i) {
        num += (t[i] - tm) * (d[i] - dm);
        den += (t[i] - tm) * (t[i] - tm);
    }
    const auto [lo, hi] = std::minmax_element(d.begin(), d.end());
    return {{"slope", num / den},
            {"range", *hi - *lo},
            {"first", {t.front(), d.front()}},
            {"last", {t.back(), d.back()}},
            {"points", static_cast<std::int64_t>(t.size())}};
}

} // namespace dampsym
