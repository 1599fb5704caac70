// The definition of kernel_ops<P> (kernel_ops.hpp): included only by the generated kernel shards
// (src/harness/run/kernel_shard.cpp.in), so that each (kernel, problem) pair is compiled once, and
// by a test that steps a problem type of its own.
#pragma once

#include "harness/registry.hpp"
#include "harness/run/kernel_ops.hpp"
#include "harness/run/limits.hpp"

#include <chrono>

namespace dampsym {

namespace kernel_ops_detail {

template <class K, class P>
IntegrateOutcome run(const P& problem, const MethodInfo& info, double h, Counters& counters, Vec& z,
                     double t0, std::int64_t n, StepSink* observer, const CaseGuard& guard,
                     const FaultPlan* fault, double& wall) {
    using Clock = std::chrono::steady_clock;
    IntegrateOutcome res;
    if (observer) {
        StepperOf<K> stepper(problem, info, h, counters);
        const auto start = Clock::now();
        res = observed_run(stepper, z, t0, h, n, *observer, guard, fault);
        wall = std::chrono::duration<double>(Clock::now() - start).count();
    } else {
        K stepper(problem, info, h, counters);
        const auto start = Clock::now();
        res = integrate_guarded(stepper, z, t0, h, n, static_cast<NoObserver*>(nullptr), guard,
                                fault);
        wall = std::chrono::duration<double>(Clock::now() - start).count();
    }
    return res;
}

template <class K, class P>
inline constexpr KernelOps<P> ops{K::kernel_id, stepper_maker<K, P>(), &run<K, P>};

} // namespace kernel_ops_detail

template <class P>
const KernelOps<P>* kernel_ops(const MethodInfo& info, KernelMatch& match) {
    const KernelOps<P>* found = nullptr;
    match = with_kernel<P>(info, [&]<class K>() { found = &kernel_ops_detail::ops<K, P>; });
    return found;
}

} // namespace dampsym
