// Diagnostic "poincare": Poincaré sections at t = t0 + kT, T the forcing period (B §3.2.2), against
// the reference's sections, pointwise and as sets. The output grid must be the section times.
#pragma once

#include "diagnostics/capabilities.hpp"
#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"

#include <optional>
#include <string_view>

namespace dampsym {

struct PoincareDiagnostic {
    static constexpr std::string_view name = "poincare";
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = HasForcingPeriod<P>;
    // Its metrics of one run from the run's view (harness/run/view.hpp: the problem, the case's
    // facts, the recorder and grid, the method, h, the final state, the counters).
    template <class V>
    static json produce(const V& run);
};

// period: the problem's forcing period (none: the problem has no periodic forcing).
json poincare_metrics(const CaseFacts& c, const Mat& grid, std::optional<double> period);

template <class V>
json PoincareDiagnostic::produce(const V& run) {
    return poincare_metrics(run.facts, run.grid(), run.problem.forcing_period());
}

} // namespace dampsym
