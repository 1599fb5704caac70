// Diagnostic "poincare": Poincaré sections at t = t0 + kT, T the forcing period (B §3.2.2), against
// the reference's sections, pointwise and as sets. The output grid must be the section times.
#pragma once

#include "diagnostics/capabilities.hpp"
#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"
#include "diagnostics/series.hpp"

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
    // With --figures: its series on the measured run's output grid (harness/figures/series.hpp
    // GridSeries: the problem, the case, the grid and its times, the reference on the grid).
    template <class G>
    static void grid_series(const G& g, nlohmann::json& s);
};
DAMPSYM_DIAGNOSTIC(PoincareDiagnostic, 120);

// period: the problem's forcing period (none: the problem has no periodic forcing).
json poincare_metrics(const CaseFacts& c, const Mat& grid, std::optional<double> period);

template <class V>
json PoincareDiagnostic::produce(const V& run) {
    return poincare_metrics(run.facts, run.grid(), run.problem.forcing_period());
}

// B §3.2.2: the Poincaré section's points (q mod 2π, p) of the run and of the reference.
template <class G>
void PoincareDiagnostic::grid_series(const G& g, nlohmann::json& s) {
    using json = nlohmann::json;
    auto section = [](const Mat& m) {
        json q = json::array(), p = json::array();
        for (Eigen::Index i = 0; i < m.cols(); ++i) {
            q.push_back(std::remainder(m(0, i), 2.0 * M_PI));
            p.push_back(m(1, i));
        }
        return json{{"q", q}, {"p", p}};
    };
    const std::string key(name);
    s[key] = section(g.grid);
    if (g.ref_on_grid) s[key + "_reference"] = section(g.ref);
}

} // namespace dampsym
