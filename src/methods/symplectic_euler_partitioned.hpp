// HLW's symplectic Euler method (1.8) for a partitioned system (1.7) u' = a(u, v), v' = b(u, v)
// given in the plain form z = (u, v), f = (a, b), such as the Lotka–Volterra problem HLW (1.1):
//   u₁ = u + h a(u₁, v),   v₁ = v + h b(u₁, v)
// (u by the implicit, v by the explicit Euler method; HLW Ψ^{ie} of I.3). For Lotka–Volterra
// a = u(v − 2), b = v(1 − u): u₁ = u/(1 − h(v − 2)), v₁ = v(1 + h(1 − u₁)).
// It applies to problems that declare their state as the two halves z = (u, v)
// (`partitioned_halves`, e.g. problems/lotka_volterra.hpp). The separable Rayleigh form has its own
// symplectic Euler rows (partitioned_rk.hpp); on such a system this scheme is their adjoint
// (HLW (1.9)) with the damping in the vector field.
// Time: t is a variable integrated with u's implicit Euler (c = 1), so both a and b are evaluated
// at t + h (as the partitioned engine does for HLW (1.9)).
// The u equation is solved by the stage-Newton solver (methods/newton.hpp, full policy) with the
// problem's analytic Jacobian: R(U) = U − u − h a(U, v), ∂R/∂U = I − h A, A = ∂a/∂u.
//
// step_jacobian(): Ψ = ∂z₁/∂z₀ by the implicit-function theorem at the converged U (never through
// the Newton iterations): with the blocks [A B; C D] of f' at (U, v),
//   ∂U/∂u = (I − hA)⁻¹,  ∂U/∂v = h (I − hA)⁻¹ B,
//   ∂v₁/∂u = h C ∂U/∂u,  ∂v₁/∂v = I + h (C ∂U/∂v + D).
#pragma once

#include "core/method.hpp"
#include "methods/hand_written.hpp"
#include "methods/newton.hpp"

#include <algorithm>
#include <string_view>

namespace dampsym {

template <class P>
class SymplecticEulerPartitioned : public OneCodePathKernel<SymplecticEulerPartitioned<P>,
                                                            Scheme::symplectic_euler_partitioned> {
public:
    static constexpr std::string_view kernel_id = "symplectic-euler-partitioned";
    template <class Q>
    static constexpr bool applies = [] {
        if constexpr (requires { Q::partitioned_halves; })
            return Q::partitioned_halves;
        else
            return false;
    }();

    SymplecticEulerPartitioned(const P& problem, const MethodInfo&, double h, Counters& counters)
        : prob_(problem), h_(h), c_(counters), d_(problem.dim()), m_(d_ / 2), zs_(d_), f_(d_),
          J_(d_, d_), rhs_(m_, d_), dU_(m_, d_), newton_(m_) {}

private:
    friend class OneCodePathKernel<SymplecticEulerPartitioned<P>,
                                   Scheme::symplectic_euler_partitioned>; // step(), step_jacobian()
    int state_dim() const { return d_; }

    template <bool WithJacobian>
    [[gnu::always_inline]] inline StepStatus advance(double t, Vec& z, Mat* Psi) {
        const double t1 = t + h_;
        zs_ = z; // (U, v): U iterated in place, v fixed
        Vec& U = newton_.X;
        U = z.head(m_);
        const bool solved = newton_.solve_step(NewtonPolicy::full, c_, [&](bool) {
            zs_.head(m_) = U;
            prob_.rhs(t1, zs_, f_);
            prob_.rhs_jacobian(t1, zs_, J_);
            c_.rhs_evals += 1;
            c_.jac_evals += 1;
            newton_.R = U - z.head(m_) - h_ * f_.head(m_);
            newton_.S = Mat::Identity(m_, m_) - h_ * J_.topLeftCorner(m_, m_);
        });
        if (!solved) return StepStatus::solve_failed;
        zs_.head(m_) = U;
        prob_.rhs(t1, zs_, f_); // b(U, v) at the converged U
        c_.rhs_evals += 1;
        if constexpr (WithJacobian) jacobian_at_solution(t1, *Psi);
        z.head(m_) = U;
        z.tail(d_ - m_) += h_ * f_.tail(d_ - m_);
        return StepStatus::ok;
    }

    void jacobian_at_solution(double t1, Mat& Psi) {
        prob_.rhs_jacobian(t1, zs_, J_);
        c_.jac_evals += 1;
        const Eigen::Index n = d_ - m_;
        newton_.S = Mat::Identity(m_, m_) - h_ * J_.topLeftCorner(m_, m_);
        rhs_ << Mat::Identity(m_, m_), h_ * J_.topRightCorner(m_, n); // [I, hB]
        newton_.factor_and_solve(rhs_, dU_);                          // [∂U/∂u, ∂U/∂v]
        Psi.topRows(m_) = dU_;
        Psi.bottomRows(n) = h_ * J_.bottomLeftCorner(n, m_) * dU_;
        Psi.bottomRightCorner(n, n) += Mat::Identity(n, n) + h_ * J_.bottomRightCorner(n, n);
    }

    const P& prob_;
    double h_;
    Counters& c_;
    int d_;
    Eigen::Index m_; // size of u (the first half)
    Vec zs_, f_;     // (U, v) and f there
    Mat J_;          // f' at (U, v)
    Mat rhs_, dU_;   // step Jacobian: [I, hB] and [∂U/∂u, ∂U/∂v]
    StageNewton newton_;
};

} // namespace dampsym
