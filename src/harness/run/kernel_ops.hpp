// What the runner, the matrix and the tests call of a (kernel, problem) pair: a small table of
// functions, compiled once per pair in the library's kernel shards (the generated
// kernel_shard_K.cpp, src/harness/run/kernel_shard.cpp.in). The typed case (typed_case.hpp) and
// the diagnostics are typed on the problem only and never instantiate a kernel: the measured run's
// step loop is in the pair's `run` (bare: no virtual call, no allocation per step; observed: one
// virtual StepSink call per step), the diagnostics' separate passes step AnyStepper
// (core/any_stepper.hpp). Adding a kernel or a problem touches neither this file nor the runner.
#pragma once

#include "core/any_stepper.hpp"
#include "core/integrate.hpp"
#include "core/method.hpp"

#include <cstdint>
#include <string_view>

namespace dampsym {

class CaseGuard;  // harness/run/limits.hpp
struct FaultPlan; // harness/run/limits.hpp

enum class KernelMatch { applied, not_applicable, unknown_kernel };

template <class P>
struct KernelOps {
    std::string_view kernel_id;
    // Fresh steppers for the diagnostics' separate passes.
    StepperMaker<P> stepper;
    // The measured run: n steps of size h from (t0, z) with a fresh stepper (its counts in
    // `counters`), in chunks with the case's stop state tested between them (integrate_guarded,
    // limits.hpp). Without observer, the kernel's bare loop (compiled here for the pair); with
    // one, the loop of observed_run below over the same stepper behind AnyStepper, calling the
    // observer after each step (bitwise the same states). wall: the seconds of the step loop.
    // The work-precision timing calls it without observer.
    IntegrateOutcome (*run)(const P& problem, const MethodInfo& info, double h, Counters& counters,
                            Vec& z, double t0, std::int64_t n, StepSink* observer,
                            const CaseGuard& guard, const FaultPlan* fault, double& wall) = nullptr;
};

// The observed step loop, compiled once for every kernel and problem (kernel_ops.cpp): the
// stepper's step and the observer are each one virtual call per step.
IntegrateOutcome observed_run(AnyStepper& stepper, Vec& z, double t0, double h, std::int64_t n,
                              StepSink& observer, const CaseGuard& guard, const FaultPlan* fault);

// The functions of the kernel that steps `info` on problem type P (the registry's choice,
// with_kernel in harness/registry.hpp), or null with `match` saying why (the kernel does not apply
// to P, or no kernel accepts the row). Defined in kernel_ops_impl.hpp and compiled in the kernel
// shards for every problem of ProblemList.
template <class P>
const KernelOps<P>* kernel_ops(const MethodInfo& info, KernelMatch& match);

} // namespace dampsym
