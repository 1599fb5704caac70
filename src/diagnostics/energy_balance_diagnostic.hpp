// Diagnostic "energy-balance": R(t_n) = |D_t H_n − Ḣ_n|, the 8th-order central difference of the
// energy against the exact rate Ḣ = −2γ(t) p·∇T(p) (B(3.4)). The per-step hook is the Recorder's
// "energy-balance" part (diagnostics/recorder.hpp).
#pragma once

#include "diagnostics/capabilities.hpp"
#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"
#include "diagnostics/recorder.hpp"

#include <string_view>

namespace dampsym {

struct EnergyBalanceDiagnostic {
    static constexpr std::string_view name = "energy-balance";
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = HasEnergyBalance<P>;
    // Its metrics of one run from the run's view (harness/run/view.hpp: the problem, the case's
    // facts, the recorder and grid, the method, h, the final state, the counters).
    template <class V>
    static json produce(const V& run);
};

json energy_balance_metrics(const EnergyBalanceStats& e);

template <class V>
json EnergyBalanceDiagnostic::produce(const V& run) {
    return energy_balance_metrics(run.rec.energy_balance_stats());
}

} // namespace dampsym
