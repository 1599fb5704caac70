// Diagnostic "energy-balance": R(t_n) = |D_t H_n − Ḣ_n|, the 8th-order central difference of the
// energy against the exact rate Ḣ = −2γ(t) p·∇T(p) (B(3.4)). The per-step hook is the Recorder's
// "energy-balance" part (diagnostics/recorder.hpp).
#pragma once

#include "diagnostics/capabilities.hpp"
#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"
#include "diagnostics/recorder.hpp"

namespace dampsym {

struct EnergyBalanceDiagnostic {
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = HasEnergyBalance<P>;
};

json energy_balance_metrics(const EnergyBalanceStats& e);

} // namespace dampsym
