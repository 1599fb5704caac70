#include "diagnostics/cost_diagnostic.hpp"

#include <algorithm>

namespace dampsym {

DiagnosticInfo CostDiagnostic::info() {
    return {.name = std::string(name),
            .what = "evaluations, Newton iterations and wall time per step",
            .metrics = {"rhs_evals_per_step", "jac_evals_per_step", "newton_iters_per_step",
                        "max_newton_iters", "wall_seconds"},
            .report_columns = {{.key = "newton_iters_per_step", .label = "Newton its/step"}}};
}

json cost_metrics(const Counters& counters, std::int64_t steps_done, double wall) {
    const double steps = static_cast<double>(std::max<std::int64_t>(steps_done, 1));
    return {{"rhs_evals_per_step", static_cast<double>(counters.rhs_evals) / steps},
            {"jac_evals_per_step", static_cast<double>(counters.jac_evals) / steps},
            {"newton_iters_per_step", static_cast<double>(counters.newton_iters) / steps},
            {"max_newton_iters", counters.max_newton_iters_per_step},
            {"wall_seconds", wall}};
}

} // namespace dampsym
