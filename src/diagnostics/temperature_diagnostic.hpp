// Diagnostic "temperature": the HLW(3.8) temperature on the output grid, its fluctuation and, with
// a reference, its error.
#pragma once

#include "diagnostics/capabilities.hpp"
#include "diagnostics/diagnostic.hpp"
#include "diagnostics/energy_diagnostic.hpp"
#include "diagnostics/metric_json.hpp"

namespace dampsym {

struct TemperatureDiagnostic {
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = HasTemperature<P>;
};

// temperature: the problem's (empty: it declares none).
json temperature_metrics(const CaseFacts& c, const Mat& grid, const StateFunction& temperature);

} // namespace dampsym
