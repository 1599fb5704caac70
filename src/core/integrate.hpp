// The fixed-step integration loop. With NoObserver it is the bare step loop: no virtual call and no
// allocation per step; an observer is attached only when a case asks for a diagnostic that needs
// the trajectory.
#pragma once

#include "core/types.hpp"

#include <cmath>
#include <cstdint>
#include <type_traits>

namespace dampsym {

struct NoObserver {};

// An observer behind a virtual call: the measured run's loop of each (kernel, problem) pair calls
// it after every step, so that what observes (the diagnostics' per-step parts, the figure series)
// is compiled once per problem rather than inlined into every kernel's loop. Only observed runs
// pay the call; the bare loop (NoObserver) has none.
class StepSink {
public:
    virtual void operator()(std::int64_t n, double t, const Vec& z) = 0;

protected:
    ~StepSink() = default;
};

// timeout and interrupted: stopped at a step boundary by the case's time budget or by
// SIGINT/SIGTERM (src/harness/run/limits.hpp); z is the state at the step reached.
enum class RunStatus { ok, diverged, solve_failed, timeout, interrupted };

inline const char* to_string(RunStatus s) {
    switch (s) {
    case RunStatus::ok:
        return "ok";
    case RunStatus::diverged:
        return "diverged";
    case RunStatus::solve_failed:
        return "solve-failed";
    case RunStatus::timeout:
        return "timeout";
    case RunStatus::interrupted:
        return "interrupted";
    }
    return "?";
}

struct IntegrateOutcome {
    RunStatus status = RunStatus::ok;
    // Steps whose result is in z. A diverged step counts (z holds the diverged state, so z is the
    // state at t0 + steps_done·h); a failed nonlinear solve does not (z is the last good state).
    std::int64_t steps_done = 0;
    std::int64_t failed_step = 0; // 1-based index of the step that diverged or failed; 0 if ok
};

// A state is "diverged" when any component is NaN/inf or exceeds 1e100 in magnitude.
inline bool state_diverged(const Vec& z) {
    for (Eigen::Index i = 0; i < z.size(); ++i)
        if (!(std::abs(z[i]) <= 1e100)) return true;
    return false;
}

// The loop of integrate_steps on a step callable StepFn: StepStatus(double t, Vec& z).
template <class StepFn, class Observer>
[[gnu::always_inline]] inline IntegrateOutcome step_loop(StepFn& step, Vec& z, double t0, double h,
                                                         std::int64_t k_begin, std::int64_t k_end,
                                                         Observer* observer) {
    for (std::int64_t k = k_begin; k < k_end; ++k) {
        if (step(time_at(t0, h, k), z) != StepStatus::ok)
            return {RunStatus::solve_failed, k, k + 1};
        if (state_diverged(z)) return {RunStatus::diverged, k + 1, k + 1};
        if constexpr (!std::is_same_v<Observer, NoObserver>)
            (*observer)(k + 1, time_at(t0, h, k + 1), z);
    }
    return {RunStatus::ok, k_end, 0};
}

// stepper.step as a callable, inlined into the loop (a lambda's call operator may not be).
template <class Stepper>
struct StepOf {
    Stepper& stepper;
    [[gnu::always_inline]] inline StepStatus operator()(double t, Vec& z) const {
        return stepper.step(t, z);
    }
};

// A stepper whose step branches on a mode that is fixed for a run (the partitioned engine: which
// compiled shape its coefficients have) can declare `static constexpr bool specialised_steps =
// true` and provide `with_specialised_step(f)`, which calls f with a step callable specialised for
// the current mode. The bare loop (no observer) is then compiled once per mode with the mode's
// branch outside it (what a compiler's loop unswitching would do), and the stepper stays free to
// fall back inside the callable when its mode changes during the run. With an observer the loop
// calls step(), which must give the same numbers.
template <class Stepper>
constexpr bool has_specialised_steps() {
    if constexpr (requires { Stepper::specialised_steps; })
        return Stepper::specialised_steps;
    else
        return false;
}

// Advances z from step k_begin (z is the state at t0 + k_begin·h) to step k_end. Stepper:
// StepStatus step(double t, Vec& z). Observer (if any): void operator()(std::int64_t n, double t_n,
// const Vec& z_n) after each step. Steps are numbered from t0 whatever k_begin, so integrating
// 0..n in one call or in consecutive ranges gives bitwise the same states.
template <class Stepper, class Observer = NoObserver>
IntegrateOutcome integrate_steps(Stepper& stepper, Vec& z, double t0, double h,
                                 std::int64_t k_begin, std::int64_t k_end,
                                 Observer* observer = nullptr) {
    if constexpr (has_specialised_steps<Stepper>() && std::is_same_v<Observer, NoObserver>) {
        return stepper.with_specialised_step(
            [&](auto&& step) { return step_loop(step, z, t0, h, k_begin, k_end, observer); });
    } else {
        StepOf<Stepper> step{stepper};
        return step_loop(step, z, t0, h, k_begin, k_end, observer);
    }
}

// Advances z from t0 by n steps of size h (integrate_steps from 0 to n).
template <class Stepper, class Observer = NoObserver>
IntegrateOutcome integrate(Stepper& stepper, Vec& z, double t0, double h, std::int64_t n,
                           Observer* observer = nullptr) {
    return integrate_steps(stepper, z, t0, h, 0, n, observer);
}

} // namespace dampsym
