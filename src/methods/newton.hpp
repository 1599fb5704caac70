// The one stage-Newton solver of the method kernels (cimp, the RK engine behind implicit RK, IFRK
// and exponential RK, the partitioned engine behind PRK and PERK, general linear methods).
//
// It solves R(X) = 0 for the stacked stage values X by Newton's method, X ← X − S⁻¹R(X), with the
// caller's residual R and Newton matrix S = ∂R/∂X (analytic Jacobians, never finite differences):
//   full policy        S formed and factorised (LU, partial pivoting) at every iteration;
//   simplified policy  S formed once, at the predictor (first iteration), and kept for the later
//                      iterations of the solve (HW II §IV.8): the iteration still converges to
//                      round-off, linearly with a rate O(h·‖X − X₀‖·‖∂²g‖).
// Convergence test (newton_converged), run to round-off: with θ = ‖ΔX_k‖/‖ΔX_{k−1}‖ the observed
// contraction, the iteration stops when
//   the update is within a few ulps of the iterate's scale, ‖ΔX‖ ≤ 4ε‖X‖ (error left
//   ≤ θ/(1−θ)·4ε‖X‖: below ε for fast contraction, 13.5ε measured at θ = 0.8);
//   or the error left, estimated as θ/(1−θ)·‖ΔX‖ (HW II §IV.8, with tol = ε), is ≤ ε‖X‖;
//   or the update stopped decreasing (θ ≥ 1) once below 1e-10‖X‖: the round-off floor of the
//   residual, where further iterations only exchange round-off.
// (The stagnation clause used to fire at θ ≥ 0.5, which stops a linearly convergent simplified
// Newton at θ ∈ [0.5, 1) up to θ/(1−θ)·1e-10‖X‖ short of the solution.)
// A NaN update or a non-finite iterate ends the solve as failed, as does no convergence within
// max_iterations; the caller then returns StepStatus::solve_failed and leaves its state unchanged.
// A failed solve leaves its iterations, residual and last update in the counters
// (failed_solve_*), so that the run's solve-failed record says how far it got.
// Counters: newton_iters counts every iteration; the caller counts its own evaluations and the
// iterations of a step (max_newton_iters_per_step), since a step may hold several solves.
#pragma once

#include "core/types.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace dampsym {

inline bool newton_converged(double step_norm, double scale, double previous_step_norm) {
    constexpr double eps = std::numeric_limits<double>::epsilon();
    if (step_norm <= 4.0 * eps * scale) return true;
    if (!std::isfinite(previous_step_norm)) return false; // first iteration: θ not known yet
    const double theta = step_norm / previous_step_norm;
    if (theta < 1.0) return theta / (1.0 - theta) * step_norm <= eps * scale;
    return step_norm <= 1e-10 * scale; // stopped decreasing: at the round-off floor
}

enum class NewtonPolicy { full, simplified };

class StageNewton {
public:
    static constexpr int max_iterations = 50;

    explicit StageNewton(Eigen::Index n) : X(n), R(n), dX(n), S(n, n), lu_(n) {}

    Vec X;  // the iterate: set to the predictor before solve(), the solution after it
    Vec R;  // residual R(X), written by the caller's eval
    Vec dX; // the last update
    Mat S;  // Newton matrix ∂R/∂X, written by the caller's eval when asked to

    // eval(refresh) writes R at the current X and, when refresh is true, S at the current X.
    // Returns the number of iterations on convergence, 0 on failure.
    template <class Eval>
    int solve(NewtonPolicy policy, Counters& counters, Eval&& eval) {
        double previous = std::numeric_limits<double>::infinity();
        for (int it = 1; it <= max_iterations; ++it) {
            const bool refresh = policy == NewtonPolicy::full || it == 1;
            eval(refresh);
            counters.newton_iters += 1;
            if (refresh) lu_.compute(S);
            dX = lu_.solve(R);
            X -= dX;
            const double step_norm = dX.cwiseAbs().maxCoeff();
            const double scale = std::max(X.cwiseAbs().maxCoeff(), 1e-300);
            if (!(step_norm == step_norm) || !std::isfinite(scale)) // NaN / inf
                return failed(counters, it, step_norm);
            if (newton_converged(step_norm, scale, previous)) return it;
            previous = step_norm;
        }
        return failed(counters, max_iterations, previous);
    }

    // A step whose nonlinear work is this one solve (cimp, the RK and partitioned engines, the
    // partitioned symplectic Euler): true on convergence, with the step's iterations recorded
    // (Counters::step_solved); false on failure, and the caller returns solve_failed.
    template <class Eval>
    bool solve_step(NewtonPolicy policy, Counters& counters, Eval&& eval) {
        const int iterations = solve(policy, counters, std::forward<Eval>(eval));
        if (iterations > 0) counters.step_solved(iterations);
        return iterations > 0;
    }

    // Factorises S as it stands (e.g. the Newton matrix at the converged stages, for the
    // implicit-function theorem of a step Jacobian) and solves S X = rhs.
    template <class Rhs, class Out>
    void factor_and_solve(const Rhs& rhs, Out& out) {
        lu_.compute(S);
        out = lu_.solve(rhs);
    }

private:
    // Records a failed solve in the counters (R: the residual at the last iterate evaluated).
    int failed(Counters& counters, int iterations, double update) const {
        constexpr double nan = std::numeric_limits<double>::quiet_NaN();
        counters.failed_solve_iterations = iterations;
        counters.failed_solve_residual = R.allFinite() ? R.cwiseAbs().maxCoeff() : nan;
        counters.failed_solve_update = std::isfinite(update) ? update : nan;
        return 0;
    }

    Eigen::PartialPivLU<Mat> lu_;
};

} // namespace dampsym
