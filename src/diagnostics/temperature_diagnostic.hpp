// Diagnostic "temperature": the HLW(3.8) temperature on the output grid, its fluctuation and, with
// a reference, its error.
#pragma once

#include "diagnostics/capabilities.hpp"
#include "diagnostics/diagnostic.hpp"
#include "diagnostics/energy_diagnostic.hpp"
#include "diagnostics/metric_json.hpp"

#include <string_view>

namespace dampsym {

struct TemperatureDiagnostic {
    static constexpr std::string_view name = "temperature";
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = HasTemperature<P>;
    // Its metrics of one run from the run's view (harness/run/view.hpp: the problem, the case's
    // facts, the recorder and grid, the method, h, the final state, the counters).
    template <class V>
    static json produce(const V& run);
};

// temperature: the problem's (empty: it declares none).
json temperature_metrics(const CaseFacts& c, const Mat& grid, const StateFunction& temperature);

template <class V>
json TemperatureDiagnostic::produce(const V& run) {
    const auto& p = run.problem;
    return temperature_metrics(run.facts, run.grid(),
                               [&p](const Vec& v) { return p.temperature(v); });
}

} // namespace dampsym
