// The diagnostic registry: one line per diagnostic (its file is
// src/diagnostics/<name>_diagnostic.*). The order is the order of `dampsym list` and of the
// "known:" list in validation messages.
#pragma once

#include "core/types.hpp"
#include "diagnostics/attractor_diagnostic.hpp"
#include "diagnostics/conformal_symplectic_diagnostic.hpp"
#include "diagnostics/cost_diagnostic.hpp"
#include "diagnostics/dissipation_drift_diagnostic.hpp"
#include "diagnostics/energy_balance_diagnostic.hpp"
#include "diagnostics/energy_diagnostic.hpp"
#include "diagnostics/error_diagnostic.hpp"
#include "diagnostics/field_drift_diagnostic.hpp"
#include "diagnostics/invariants_diagnostic.hpp"
#include "diagnostics/local_error_diagnostic.hpp"
#include "diagnostics/momentum_diagnostic.hpp"
#include "diagnostics/order_diagnostic.hpp"
#include "diagnostics/pde_error_diagnostic.hpp"
#include "diagnostics/poincare_diagnostic.hpp"
#include "diagnostics/precession_diagnostic.hpp"
#include "diagnostics/stability_diagnostic.hpp"
#include "diagnostics/stability_sweep_diagnostic.hpp"
#include "diagnostics/temperature_diagnostic.hpp"

#include <string>
#include <vector>

namespace dampsym {

using DiagnosticList =
    TypeList<ErrorDiagnostic, OrderDiagnostic, InvariantsDiagnostic, EnergyDiagnostic,
             DissipationDriftDiagnostic, StabilityDiagnostic, StabilitySweepDiagnostic,
             TraceTaylorDiagnostic, CostDiagnostic, MomentumDiagnostic, EnergyBalanceDiagnostic,
             PoincareDiagnostic, TemperatureDiagnostic, ConformalSymplecticDiagnostic,
             LocalErrorDiagnostic, LocalOrderDiagnostic, PrecessionDiagnostic, FieldDriftDiagnostic,
             PdeErrorDiagnostic, AttractorDiagnostic>;

// The names of the diagnostics problem type P supports (each diagnostic's `supports<P>` concept),
// for ProblemInfo (harness/registry.cpp).
template <class P>
std::vector<std::string> supported_diagnostics() {
    std::vector<std::string> out;
    for_each_type(DiagnosticList{}, [&]<class D>() {
        if constexpr (D::template supports<P>) out.push_back(D::info().name);
    });
    return out;
}

} // namespace dampsym
