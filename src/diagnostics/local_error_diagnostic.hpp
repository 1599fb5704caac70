// Diagnostic "local-error": one step from the initial state against the exact solution at t0 + h
// (B Fig 3.2's local error, O(h^{p+1})), with a separate stepper so the run is untouched.
#pragma once

#include "core/any_stepper.hpp"
#include "core/method.hpp"
#include "core/problem_concepts.hpp"
#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"

#include <memory>
#include <string_view>

namespace dampsym {

struct LocalErrorDiagnostic {
    static constexpr std::string_view name = "local-error";
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = HasExactSolution<P>;
    // Its metrics of one run from a separate pass of the run's kernel (harness/run/view.hpp).
    template <class V>
    static json produce_pass(const V& run);
};
DAMPSYM_DIAGNOSTIC(LocalErrorDiagnostic, 150);

// The metrics from the one-step state z and the exact state at t0 + h (null z: the solve failed).
json local_error_json(const Vec* z, const Vec& exact);

// One step of the run's kernel (a fresh stepper from `make`) from (t0, z0) of `problem`.
template <class P>
json local_error_metrics(const P& problem, const MethodInfo& info, double t0, double h,
                         const StepperMaker<P>& make) {
    if constexpr (HasExactSolution<P>) {
        Counters scratch;
        const std::unique_ptr<AnyStepper> stepper = make(problem, info, h, scratch);
        Vec z = problem.initial_state();
        Vec exact(z.size());
        problem.exact(t0, problem.initial_state(), t0 + h, exact);
        if (stepper->step(t0, z) != StepStatus::ok) return local_error_json(nullptr, exact);
        return local_error_json(&z, exact);
    } else {
        return json::object();
    }
}

template <class V>
json LocalErrorDiagnostic::produce_pass(const V& run) {
    return local_error_metrics(run.problem, run.info, run.t0, run.h, run.stepper);
}

} // namespace dampsym
