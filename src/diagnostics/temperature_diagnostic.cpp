#include "diagnostics/temperature_diagnostic.hpp"

#include <algorithm>
#include <cmath>

namespace dampsym {

DiagnosticInfo TemperatureDiagnostic::info() {
    return {.name = std::string(name),
            .what = "HLW(3.8) temperature on the output grid: fluctuation and error",
            .requirement = "a temperature",
            .needs = {.grid = true, .ok_run = true},
            .metrics = {"initial", "mean", "min", "max", "max_abs_dev_initial", "max_abs_error"}};
}

json temperature_metrics(const CaseFacts& c, const Mat& g, const StateFunction& temperature) {
    if (!temperature) return {{"reason", "problem declares no temperature"}};
    const double T0 = temperature(g.col(0));
    double lo = T0, hi = T0, sum = 0.0, max_err = 0.0;
    const bool with_ref = c.reference_ok && c.ref.cols() == g.cols();
    for (Eigen::Index i = 0; i < g.cols(); ++i) {
        const double T = temperature(g.col(i));
        lo = std::min(lo, T);
        hi = std::max(hi, T);
        sum += T;
        if (with_ref) max_err = std::max(max_err, std::abs(T - temperature(c.ref.col(i))));
    }
    json out = {{"initial", T0},
                {"mean", sum / static_cast<double>(g.cols())},
                {"min", lo},
                {"max", hi},
                {"max_abs_dev_initial", std::max(hi - T0, T0 - lo)}};
    if (with_ref) out["max_abs_error"] = max_err;
    return out;
}

} // namespace dampsym
