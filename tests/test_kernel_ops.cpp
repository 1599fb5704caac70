// The compiled (kernel, problem) pairs the runner calls (harness/run/kernel_ops.hpp): for every
// catalog method that applies to the pendulum, the N-body problem and the rigid body,
//  - the observed run (observed_run: the stepper behind AnyStepper, the observer behind StepSink,
//    one virtual call each per step) ends bitwise at the bare run's state with the same counts,
//    and the observer sees every step n = 1..N at t0 + n·h with the state the step produced;
//  - a stepper of the pair's maker (the diagnostics' passes) steps bitwise as the run does.
// Negative control: an observer that is told a wrong step count is seen to disagree (the
// comparison can fail), and a row no kernel accepts gets no pair.
#include "harness/problem_list.hpp"
#include "harness/run/kernel_ops.hpp"
#include "harness/run/limits.hpp"

#include "support/helpers.hpp"

#include <catch2/catch.hpp>

#include <bit>
#include <cstdint>
#include <string>
#include <vector>

using dampsym::Counters;
using dampsym::IntegrateOutcome;
using dampsym::KernelMatch;
using dampsym::MethodInfo;
using dampsym::RunStatus;
using dampsym::Vec;

namespace {

bool bitwise_equal(const Vec& a, const Vec& b) {
    if (a.size() != b.size()) return false;
    for (Eigen::Index i = 0; i < a.size(); ++i)
        if (std::bit_cast<std::uint64_t>(a[i]) != std::bit_cast<std::uint64_t>(b[i])) return false;
    return true;
}

// Records the steps it is shown: their indices, times and the last state.
class StepLog final : public dampsym::StepSink {
public:
    void operator()(std::int64_t n, double t, const Vec& z) override {
        ns.push_back(n);
        ts.push_back(t);
        last = z;
    }
    std::vector<std::int64_t> ns;
    std::vector<double> ts;
    Vec last;
};

// The three ways of stepping `info` on `prob` (n steps of h from t0) agree bitwise; returns the
// number of methods checked.
template <class P>
int check_pairs(const P& prob, double t0, double h, std::int64_t n) {
    int checked = 0;
    const dampsym::CaseGuard no_budget;
    for (const MethodInfo& info : dampsym::method_catalog()) {
        KernelMatch match = KernelMatch::unknown_kernel;
        const dampsym::KernelOps<P>* ops = dampsym::kernel_ops<P>(info, match);
        if (ops == nullptr) continue;
        INFO(info.id << " on " << P::id);
        Counters cb, co, cs;
        Vec zb = prob.initial_state(), zo = zb, zs = zb;
        double wall = 0.0;
        const IntegrateOutcome rb =
            ops->run(prob, info, h, cb, zb, t0, n, nullptr, no_budget, nullptr, wall);
        StepLog log;
        const IntegrateOutcome ro =
            ops->run(prob, info, h, co, zo, t0, n, &log, no_budget, nullptr, wall);
        REQUIRE(rb.status == RunStatus::ok);
        CHECK(ro.status == RunStatus::ok);
        CHECK(ro.steps_done == n);
        CHECK(bitwise_equal(zb, zo));
        CHECK(cb.rhs_evals == co.rhs_evals);
        CHECK(cb.newton_iters == co.newton_iters);
        REQUIRE(log.ns.size() == static_cast<std::size_t>(n));
        CHECK(log.ns.back() == n);
        CHECK(log.ts.back() == dampsym::time_at(t0, h, n));
        CHECK(bitwise_equal(log.last, zo));
        const auto stepper = ops->stepper(prob, info, h, cs);
        for (std::int64_t k = 0; k < n; ++k)
            REQUIRE(stepper->step(dampsym::time_at(t0, h, k), zs) == dampsym::StepStatus::ok);
        CHECK(bitwise_equal(zs, zb));
        CHECK(stepper->has_step_jacobian() == ops->stepper.has_step_jacobian);
        ++checked;
    }
    return checked;
}

} // namespace

TEST_CASE("kernel pairs: the observed run, the bare run and a pass's stepper agree bitwise",
          "[kernel-ops]") {
    CHECK(check_pairs(dampsym::test::pendulum(0.1), 0.3, 0.05, 40) >= 25);
    CHECK(check_pairs(dampsym::NBody{}, 0.0, 0.01, 20) >= 20);
    CHECK(check_pairs(dampsym::RigidBody{}, 0.0, 0.05, 20) >= 10);
}

TEST_CASE("kernel pairs: negative controls", "[kernel-ops]") {
    // The comparison sees a difference: the bare run of 39 steps is not the observed run of 40.
    const dampsym::Pendulum prob = dampsym::test::pendulum(0.1);
    const MethodInfo& info = dampsym::test::method("csv1");
    const auto& ops = dampsym::test::kernel<dampsym::Pendulum>(info);
    const dampsym::CaseGuard no_budget;
    Counters ca, cb;
    Vec za = prob.initial_state(), zb = za;
    double wall = 0.0;
    StepLog log;
    ops.run(prob, info, 0.05, ca, za, 0.0, 39, nullptr, no_budget, nullptr, wall);
    ops.run(prob, info, 0.05, cb, zb, 0.0, 40, &log, no_budget, nullptr, wall);
    CHECK_FALSE(bitwise_equal(za, zb));
    // A state changed by 1e-7 relative in one component is not bitwise equal.
    Vec zc = zb;
    zc[0] *= 1.0 + 1e-7;
    CHECK_FALSE(bitwise_equal(zc, zb));
    // A row no kernel accepts (a hand-written scheme value without kernel) gets no pair.
    MethodInfo orphan = info;
    orphan.data = dampsym::HandWrittenScheme{static_cast<dampsym::Scheme>(-1)};
    KernelMatch match = KernelMatch::applied;
    CHECK(dampsym::kernel_ops<dampsym::Pendulum>(orphan, match) == nullptr);
    CHECK(match == KernelMatch::unknown_kernel);
    // A kernel that does not apply: csv1 needs the separable form, the rigid body has none.
    CHECK(dampsym::kernel_ops<dampsym::RigidBody>(info, match) == nullptr);
    CHECK(match == KernelMatch::not_applicable);
}
