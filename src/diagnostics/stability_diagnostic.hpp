// Diagnostics "stability", "trace-taylor" and "stability-sweep" on the linear oscillator (F ch. 3,
// docs/conventions.md §5): the method's own one-step matrix M (stability.hpp), against F's closed
// forms. "stability" is per run (M at the run's h); "trace-taylor" (the h⁴ coefficient of
// ½trM − e^{−γh}cos βh) and "stability-sweep" (a (γ, h) grid, stability_sweep_diagnostic.hpp) are
// per method. The typed part is only "M of kernel K at (ω, γ, h)", given to the compiled-once code
// below as a function.
#pragma once

#include "core/method.hpp"
#include "core/problem_concepts.hpp"
#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"
#include "diagnostics/stability.hpp"

#include <functional>
#include <string_view>

namespace dampsym {

struct StabilityDiagnostic {
    static constexpr std::string_view name = "stability";
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = LinearOscillator<P>;
    // Its metrics of one run from a separate pass of the run's kernel (harness/run/view.hpp).
    template <class V>
    static json produce_pass(const V& run);
};
DAMPSYM_DIAGNOSTIC(StabilityDiagnostic, 60);

struct TraceTaylorDiagnostic {
    static constexpr std::string_view name = "trace-taylor";
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = LinearOscillator<P>;
};
DAMPSYM_DIAGNOSTIC(TraceTaylorDiagnostic, 80);

// M at the run's step h on the oscillator (ω, γ).
json stability_metrics(const Mat& M, double omega, double gamma, double h, const MethodInfo& info);

// ½ tr M of the method at step h (NaN where the kernel does not apply).
using HalfTraceAt = std::function<double(double h)>;
json trace_taylor_metrics(const MethodInfo& info, double omega, double gamma,
                          const HalfTraceAt& half_trace);

template <class V>
json StabilityDiagnostic::produce_pass(const V& run) {
    return stability_metrics(one_step_matrix(run.problem, run.info, run.h, run.stepper),
                             run.problem.omega, run.problem.gamma_at(0.0), run.h, run.info);
}

} // namespace dampsym
