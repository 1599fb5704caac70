#include "diagnostics/poincare_diagnostic.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace dampsym {

DiagnosticInfo PoincareDiagnostic::info() {
    return {
        .name = std::string(name),
        .what = "Poincare sections at t0 + kT against the reference's (B 3.2.2)",
        .requirement = "a periodic forcing",
        .needs = {.grid = true, .reference = true, .ok_run = true},
        .metrics = {"sections", "pointwise_max", "pointwise_final", "set_mean", "set_hausdorff"}};
}

// The angle is compared on the circle. Pointwise distances to the reference's section, and set
// distances (nearest reference point, symmetric Hausdorff) after the first 10% of sections
// (transient), which stay meaningful where a chaotic orbit has separated from the reference
// pointwise.
json poincare_metrics(const CaseFacts& c, const Mat& g, std::optional<double> period) {
    if (!period) return {{"reason", "problem has no periodic forcing"}};
    const double T = *period;
    const double spacing = (c.t_end - c.t0) / static_cast<double>(c.points);
    if (std::abs(spacing - T) > 1e-9 * T)
        return {{"reason", "output_dt must equal the forcing period " + std::to_string(T)}};
    if (!c.reference_ok) return {{"reason", "reference failed"}};
    const Mat& ref = c.ref;
    auto dist = [](const Vec& a, const Vec& b) {
        double s = std::remainder(a[0] - b[0], 2.0 * M_PI);
        s *= s;
        for (Eigen::Index i = 1; i < a.size(); ++i) s += (a[i] - b[i]) * (a[i] - b[i]);
        return std::sqrt(s);
    };
    double pmax = 0.0;
    for (Eigen::Index k = 0; k < g.cols(); ++k) pmax = std::max(pmax, dist(g.col(k), ref.col(k)));
    const Eigen::Index skip = g.cols() / 10;
    auto nearest = [&](const Mat& from, const Mat& to, double& mean) {
        double worst = 0.0, sum = 0.0;
        for (Eigen::Index i = skip; i < from.cols(); ++i) {
            double best = std::numeric_limits<double>::infinity();
            for (Eigen::Index j = skip; j < to.cols(); ++j)
                best = std::min(best, dist(from.col(i), to.col(j)));
            worst = std::max(worst, best);
            sum += best;
        }
        mean = sum / static_cast<double>(std::max<Eigen::Index>(1, from.cols() - skip));
        return worst;
    };
    double mean_mr = 0.0, mean_rm = 0.0;
    const double h1 = nearest(g, ref, mean_mr), h2 = nearest(ref, g, mean_rm);
    return {{"sections", g.cols()},
            {"transient_skipped", skip},
            {"pointwise_max", pmax},
            {"pointwise_final", dist(g.col(g.cols() - 1), ref.col(ref.cols() - 1))},
            {"set_mean", 0.5 * (mean_mr + mean_rm)},
            {"set_hausdorff", std::max(h1, h2)}};
}

} // namespace dampsym
