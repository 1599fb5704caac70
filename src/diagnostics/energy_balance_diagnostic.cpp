#include "diagnostics/energy_balance_diagnostic.hpp"

namespace dampsym {

DiagnosticInfo EnergyBalanceDiagnostic::info() {
    return {.name = std::string(name),
            .what = "residual of the energy balance dH/dt = -2 gamma p.grad T(p) (B(3.4))",
            .requirement = "an energy, the separable form and an autonomous potential",
            .needs = {.observer = true, .ok_run = true},
            .observed_key = "energy_balance",
            .metrics = {"max", "last", "mean", "max_rel", "max_rate", "points"}};
}

json energy_balance_metrics(const EnergyBalanceStats& e) {
    json eb = {{"max", e.max},
               {"last", e.last},
               {"mean", e.count ? e.sum / static_cast<double>(e.count) : 0.0},
               {"max_rate", e.max_rate},
               {"points", e.count}};
    // R relative to the largest |Ḣ|: undefined when Ḣ ≡ 0 (γ = 0 or p ≡ 0)
    if (scale_defined(e.max_rate))
        eb["max_rel"] = e.max / e.max_rate;
    else
        set_undefined(eb, "max_rel", "max |dH/dt| is 0: no rate to compare with");
    return eb;
}

} // namespace dampsym
