// Diagnostic "cost": evaluations, Newton iterations and wall time per step of each run (F Table
// 4.1 counts force evaluations).
#pragma once

#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"

namespace dampsym {

struct CostDiagnostic {
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = true;
};

json cost_metrics(const Counters& counters, std::int64_t steps_done, double wall_seconds);

} // namespace dampsym
