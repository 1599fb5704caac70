// Diagnostic "energy": energy changes H_n − H_0 on the scale S_H(z_0) and, with a reference on the
// output grid, errors H_exact − H_n on S_H(z_ref(t_n)) (F Figs 4.2–4.5, HLW Table 2.1).
#pragma once

#include "core/problem_concepts.hpp"
#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"

#include <functional>

namespace dampsym {

struct EnergyDiagnostic {
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = HasEnergy<P>;
};

// A scalar function of the state (the problem's energy, energy scale or temperature), passed to
// the compiled-once producers by the typed runner.
using StateFunction = std::function<double(const Vec&)>;

json energy_metrics(const CaseFacts& c, const Mat& grid, const StateFunction& energy,
                    const StateFunction& energy_scale);

} // namespace dampsym
