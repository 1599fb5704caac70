#include "diagnostics/pde_error_diagnostic.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

namespace dampsym {

DiagnosticInfo PdeErrorDiagnostic::info() {
    return {.name = std::string(name),
            .what = "max-norm error against the PDE's own solution on the grid (space + time "
                    "error), at the output times",
            .requirement = "a PDE solution on the grid (pde_solution(): B's modified Burgers)",
            .needs = {.grid = true, .ok_run = true},
            .metrics = {"max_abs", "final_abs", "max_rel", "points"}};
}

json pde_error_metrics(const CaseFacts& c, const Mat& g,
                       const std::function<bool(double, Vec&)>& solution) {
    if (g.cols() < 2) return {{"reason", "needs an output grid of at least two points"}};
    double max_abs = 0.0, max_rel = 0.0, last = 0.0;
    std::int64_t points = 0;
    Vec u;
    for (Eigen::Index i = 1; i < g.cols(); ++i) { // t0 is exact: left out, as elsewhere
        const double t = c.grid_time(i);
        const bool has = solution(t, u);
        if (!has || u.size() > g.rows()) {
            json out = {{"points", points}};
            const std::string why =
                has ? "the PDE's solution has more components than the state"
                    : "the PDE has no solution to compare with at t = " + std::to_string(t) +
                          " (a shock: characteristics cross)";
            for (const char* k : {"max_abs", "final_abs", "max_rel"}) set_undefined(out, k, why);
            return out;
        }
        const double e = (g.col(i).head(u.size()) - u).cwiseAbs().maxCoeff();
        const double scale = u.cwiseAbs().maxCoeff();
        max_abs = std::max(max_abs, e);
        if (scale > 0.0) max_rel = std::max(max_rel, e / scale);
        last = e;
        ++points;
    }
    return {{"max_abs", max_abs}, {"final_abs", last}, {"max_rel", max_rel}, {"points", points}};
}

} // namespace dampsym
