// Diagnostic "energy": energy changes H_n − H_0 on the scale S_H(z_0) and, with a reference on the
// output grid, errors H_exact − H_n on S_H(z_ref(t_n)) (F Figs 4.2–4.5, HLW Table 2.1).
#pragma once

#include "core/problem_concepts.hpp"
#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"

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
};

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

} // namespace dampsym
