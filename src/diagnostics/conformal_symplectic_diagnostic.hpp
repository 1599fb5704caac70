// Diagnostic "conformal-symplectic": the defect E_n = ‖Ψᵀ J⁻¹ Ψ − e^{−2ΔΓ} J⁻¹‖ of the exact step
// Jacobian Ψ (docs/conventions.md §5), in a separate pass with its own stepper and counters
// (conformal_symplectic.hpp), so the run's cost and timing stay those of the bare step.
#pragma once

#include "core/any_stepper.hpp"
#include "core/method.hpp"
#include "diagnostics/conformal_symplectic.hpp"
#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"
#include "diagnostics/series.hpp"

#include <memory>
#include <optional>
#include <string_view>

namespace dampsym {

struct ConformalSymplecticDiagnostic {
    static constexpr std::string_view name = "conformal-symplectic";
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = true; // not canonical: a reason, not a rejection
    // Its metrics of one run from a separate pass of the run's kernel (harness/run/view.hpp).
    template <class V>
    static json produce_pass(const V& run);
};
DAMPSYM_DIAGNOSTIC(ConformalSymplecticDiagnostic, 140);

json conformal_symplectic_json(const ConformalSymplecticStats& st);

// The Jacobian pass over n steps from (t0, z0) with steppers of the run's kernel (`make`), with the
// check of its step Jacobian against central differences of the step (conformal_symplectic.hpp).
// Typed on the problem only; a kernel without a step Jacobian, or a problem without a canonical
// or Poisson structure, reports why without a pass. series (figures): when given, set to the
// per-step relative defect of the pass (left empty when there is no pass).
template <class P>
json conformal_symplectic_metrics(const P& problem, const MethodInfo& info, double t0, double h,
                                  std::int64_t n, const StepperMaker<P>& make,
                                  std::optional<MinMaxDecimator>* series = nullptr) {
    ConformalSymplecticStats st;
    if constexpr (!has_conformal_structure<P>()) {
        st.applicability = ConformalSymplecticApplicability::not_canonical;
    } else if (!make.has_step_jacobian) {
        st.applicability = ConformalSymplecticApplicability::no_step_jacobian;
    } else {
        Counters counters, checker_counters;
        const std::unique_ptr<AnyStepper> stepper = make(problem, info, h, counters);
        // the Jacobian check's steps
        const std::unique_ptr<AnyStepper> checker_stepper =
            make(problem, info, h, checker_counters);
        StepChecker checker{*checker_stepper, checker_counters};
        Vec z = problem.initial_state();
        if (series) series->emplace(n);
        st = conformal_symplectic_defect(*stepper, problem, z, t0, h, n,
                                         series ? &**series : nullptr, &checker);
    }
    return conformal_symplectic_json(st);
}

template <class V>
json ConformalSymplecticDiagnostic::produce_pass(const V& run) {
    return conformal_symplectic_metrics(run.problem, run.info, run.t0, run.h, run.n, run.stepper,
                                        run.cs_series);
}

} // namespace dampsym
