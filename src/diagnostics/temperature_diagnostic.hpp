// Diagnostic "temperature": the HLW(3.8) temperature on the output grid, its fluctuation and, with
// a reference, its error.
#pragma once

#include "diagnostics/capabilities.hpp"
#include "diagnostics/diagnostic.hpp"
#include "diagnostics/energy_diagnostic.hpp"
#include "diagnostics/metric_json.hpp"
#include "diagnostics/series.hpp"

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
    // With --figures: its series on the measured run's output grid (harness/figures/series.hpp
    // GridSeries: the problem, the case, the grid and its times, the reference on the grid).
    template <class G>
    static void grid_series(const G& g, nlohmann::json& s);
};
DAMPSYM_DIAGNOSTIC(TemperatureDiagnostic, 130);

// temperature: the problem's (empty: it declares none).
json temperature_metrics(const CaseFacts& c, const Mat& grid, const StateFunction& temperature);

template <class V>
json TemperatureDiagnostic::produce(const V& run) {
    const auto& p = run.problem;
    return temperature_metrics(run.facts, run.grid(),
                               [&p](const Vec& v) { return p.temperature(v); });
}

// temperature, HLW (3.8), on the grid.
template <class G>
void TemperatureDiagnostic::grid_series(const G& g, nlohmann::json& s) {
    using P = typename G::Problem;
    if constexpr (HasTemperature<P>) {
        MinMaxDecimator temp(g.cols());
        for (Eigen::Index i = 0; i < g.cols(); ++i)
            temp.push(g.t(i), g.problem.temperature(g.grid.col(i)));
        s[std::string(name)] = temp.to_json();
    }
}

} // namespace dampsym
