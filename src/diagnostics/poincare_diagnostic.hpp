// Diagnostic "poincare": Poincaré sections at t = t0 + kT, T the forcing period (B §3.2.2), against
// the reference's sections, pointwise and as sets. The output grid must be the section times.
#pragma once

#include "diagnostics/capabilities.hpp"
#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"

#include <optional>

namespace dampsym {

struct PoincareDiagnostic {
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = HasForcingPeriod<P>;
};

// period: the problem's forcing period (none: the problem has no periodic forcing).
json poincare_metrics(const CaseFacts& c, const Mat& grid, std::optional<double> period);

} // namespace dampsym
