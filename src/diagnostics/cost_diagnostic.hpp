// Diagnostic "cost": evaluations, Newton iterations and wall time per step of each run (F Table
// 4.1 counts force evaluations).
#pragma once

#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"

#include <string_view>

namespace dampsym {

struct CostDiagnostic {
    static constexpr std::string_view name = "cost";
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = true;
    // Its metrics of one run from the run's view (harness/run/view.hpp: the problem, the case's
    // facts, the recorder and grid, the method, h, the final state, the counters).
    template <class V>
    static json produce(const V& run);
};
DAMPSYM_DIAGNOSTIC(CostDiagnostic, 90);

json cost_metrics(const Counters& counters, std::int64_t steps_done, double wall_seconds);

template <class V>
json CostDiagnostic::produce(const V& run) {
    return cost_metrics(run.counters, run.steps_done, run.wall);
}

} // namespace dampsym
