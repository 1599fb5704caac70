// Basic types shared by problems, methods, diagnostics and the harness.
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>

namespace dampsym {

using Vec = Eigen::VectorXd;
using Mat = Eigen::MatrixXd;

// Work counters filled by a stepper. "rhs_evals" counts evaluations of whatever the method calls
// (the force -grad V for split methods, N or f for the others), as F Table 4.1 does.
struct Counters {
    std::int64_t rhs_evals = 0;
    std::int64_t jac_evals = 0;
    std::int64_t newton_iters = 0;
    int max_newton_iters_per_step = 0;
    // The last nonlinear solve that failed (methods/newton.hpp), for the run's solve-failed
    // record: the iterations it made (0 = no solve failed), the max-norm of its residual at the
    // last iterate evaluated and of its last update (NaN when non-finite).
    int failed_solve_iterations = 0;
    double failed_solve_residual = 0.0;
    double failed_solve_update = 0.0;

    // A step's nonlinear solve(s) took `iterations` (newton_iters counts them as they happen:
    // methods/newton.hpp; a step may hold several solves, so the kernel reports the step's total).
    void step_solved(int iterations) {
        if (iterations > max_newton_iters_per_step) max_newton_iters_per_step = iterations;
    }
    // A step whose iterative solve is not newton.hpp's (B's PDE schemes): `iterations` iterations,
    // each one evaluation of the residual (and of its Jacobian when `with_jacobian`).
    void step_iterated(int iterations, bool with_jacobian) {
        rhs_evals += iterations;
        if (with_jacobian) jac_evals += iterations;
        newton_iters += iterations;
        step_solved(iterations);
    }
};

enum class StepStatus { ok, solve_failed };

// Compile-time list of types; the registries of problems and method kernels are such lists.
template <class... Ts>
struct TypeList {};

template <class... Ts, class F>
constexpr void for_each_type(TypeList<Ts...>, F&& f) {
    (f.template operator()<Ts>(), ...);
}

// As for_each_type, with each type's position in the list as a compile-time constant: calls
// f.template operator()<I, T>() for the I-th type T (lets a caller instantiate code for a
// subset of the list only, e.g. one shard of the problems).
template <class... Ts, class F>
constexpr void for_each_type_indexed(TypeList<Ts...>, F&& f) {
    [&]<std::size_t... Is>(std::index_sequence<Is...>) {
        (f.template operator()<Is, Ts>(), ...);
    }
    (std::index_sequence_for<Ts...>{});
}

// Exact time of step n: t0 + n*h, never accumulated.
inline double time_at(double t0, double h, std::int64_t n) {
    return t0 + static_cast<double>(n) * h;
}

} // namespace dampsym
