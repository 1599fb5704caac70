// Diagnostic "energy": energy changes H_n − H_0 on the scale S_H(z_0) and, with a reference on the
// output grid, errors H_exact − H_n on S_H(z_ref(t_n)) (F Figs 4.2–4.5, HLW Table 2.1).
#pragma once

#include "core/problem_concepts.hpp"
#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"
#include "diagnostics/series.hpp"

#include <functional>
#include <string_view>

namespace dampsym {

struct EnergyDiagnostic {
    static constexpr std::string_view name = "energy";
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = HasEnergy<P>;
    // Its metrics of one run from the run's view (harness/run/view.hpp: the problem, the case's
    // facts, the recorder and grid, the method, h, the final state, the counters).
    template <class V>
    static json produce(const V& run);
    // With --figures: its series on the measured run's output grid (harness/figures/series.hpp
    // GridSeries: the problem, the case, the grid and its times, the reference on the grid).
    template <class G>
    static void grid_series(const G& g, nlohmann::json& s);
};
DAMPSYM_DIAGNOSTIC(EnergyDiagnostic, 40);

// A scalar function of the state (the problem's energy, energy scale or temperature), passed to
// the compiled-once producers by the typed runner.
using StateFunction = std::function<double(const Vec&)>;

json energy_metrics(const CaseFacts& c, const Mat& grid, const StateFunction& energy,
                    const StateFunction& energy_scale);

template <class V>
json EnergyDiagnostic::produce(const V& run) {
    const auto& p = run.problem;
    return energy_metrics(
        run.facts, run.grid(), [&p](const Vec& v) { return p.energy(v); },
        [&p](const Vec& v) { return p.energy_scale(v); });
}

// energy: H on the grid, its change relative to the scale (the residual) and its error.
template <class G>
void EnergyDiagnostic::grid_series(const G& g, nlohmann::json& s) {
    using P = typename G::Problem;
    if constexpr (P::has_energy) {
        const std::string key(name);
        const double e0 = g.problem.energy(g.grid.col(0));
        const double s0 = g.problem.energy_scale(g.grid.col(0));
        MinMaxDecimator change(g.cols()), err(g.cols()), raw(g.cols());
        for (Eigen::Index i = 0; i < g.cols(); ++i) {
            const double en = g.problem.energy(g.grid.col(i));
            raw.push(g.t(i), en);
            change.push(g.t(i), scale_defined(s0) ? (en - e0) / s0 : 0.0);
            if (g.ref_on_grid) err.push(g.t(i), g.problem.energy(g.ref.col(i)) - en);
        }
        s[key + ".value"] = raw.to_json();
        s[key + ".change_res"] = change.to_json();
        if (g.ref_on_grid) s[key + ".error"] = err.to_json();
    }
}

} // namespace dampsym
