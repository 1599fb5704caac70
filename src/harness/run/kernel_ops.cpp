// The observed step loop of every (kernel, problem) pair (kernel_ops.hpp): one instantiation of
// integrate_guarded over AnyStepper and StepSink.
#include "harness/run/kernel_ops.hpp"

#include "harness/run/limits.hpp"

namespace dampsym {

IntegrateOutcome observed_run(AnyStepper& stepper, Vec& z, double t0, double h, std::int64_t n,
                              StepSink& observer, const CaseGuard& guard, const FaultPlan* fault) {
    return integrate_guarded(stepper, z, t0, h, n, &observer, guard, fault);
}

} // namespace dampsym
