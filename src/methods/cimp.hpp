// CIMP, conformal implicit midpoint (F(2.3), B(2.11): 1-stage Gauss under the integrating factor):
//   (e^{γh/2} z₁ − e^{−γh/2} z₀)/h = N((e^{γh/2} z₁ + e^{−γh/2} z₀)/2),   N = J⁻¹∇H_γ.
// With y₀ = e^{−γh/2} z₀ and the midpoint m = (e^{γh/2} z₁ + y₀)/2 this is
//   m = y₀ + (h/2) N(m, t + h/2),    z₁ = e^{−γh/2} (2m − y₀),
// and with time-dependent γ the two factors become e^{−(Γ(t+h/2)−Γ(t))}, e^{−(Γ(t+h)−Γ(t+h/2))}.
// The midpoint equation is solved by the stage-Newton solver (methods/newton.hpp, full policy) with
// the problem's analytic Jacobian of N until the update reaches round-off; one N and one Jacobian
// evaluation per iteration.
//
// step_jacobian() also returns Ψ = ∂z₁/∂z₀ of this discrete map, by the implicit-function theorem
// at the converged midpoint (never by differentiating the Newton iterations): with a = e^{−ΔΓ₁},
// b = e^{−ΔΓ₂} the two half-step factors, dy₀ = a dz₀, (I − (h/2)N'(m)) dm = dy₀, so
//   Ψ = b (2 ∂m/∂z₀ − a I) = ab [2 (I − (h/2)N'(m))⁻¹ − I]   (the Cayley transform of (h/2)N').
// One extra Jacobian evaluation and LU factorisation per step (counted in jac_evals).
#pragma once

#include "core/method.hpp"
#include "methods/hand_written.hpp"
#include "methods/newton.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string_view>

namespace dampsym {

template <class P>
class Cimp : public OneCodePathKernel<Cimp<P>, Scheme::cimp> {
public:
    static constexpr std::string_view kernel_id = "cimp";
    template <class Q>
    static constexpr bool applies = Q::has_conformal; // needs the conformal form N and its Jacobian

    Cimp(const P& problem, const MethodInfo&, double h, Counters& counters)
        : prob_(problem), h_(h), c_(counters), d_(problem.dim()), y0_(d_), n_(d_), J_(d_, d_),
          newton_(d_) {}

private:
    friend class OneCodePathKernel<Cimp<P>, Scheme::cimp>; // step() and step_jacobian()
    int state_dim() const { return d_; }

    template <bool WithJacobian>
    [[gnu::always_inline]] inline StepStatus advance(double t, Vec& z, Mat* Psi) {
        const double tm = t + 0.5 * h_;
        const double a = std::exp(-prob_.dGamma(t, 0.5 * h_));
        y0_ = a * z;
        Vec& m = newton_.X; // the midpoint
        m = y0_;
        // Full Newton on F(m) = m − y₀ − (h/2) N(m, t + h/2), F'(m) = I − (h/2) N'(m).
        const bool solved = newton_.solve_step(NewtonPolicy::full, c_, [&](bool) {
            prob_.N(tm, m, n_);
            prob_.N_jacobian(tm, m, J_);
            c_.rhs_evals += 1;
            c_.jac_evals += 1;
            newton_.R = m - y0_ - (0.5 * h_) * n_;
            newton_.S = Mat::Identity(d_, d_) - (0.5 * h_) * J_;
        });
        if (!solved) return StepStatus::solve_failed;
        const double b = std::exp(-prob_.dGamma(tm, 0.5 * h_));
        z = b * (2.0 * m - y0_);
        if constexpr (WithJacobian) jacobian_at_solution(tm, a * b, *Psi);
        return StepStatus::ok;
    }

    // Ψ = ab [2 (I − (h/2)N'(m))⁻¹ − I] at the converged midpoint (implicit-function theorem).
    void jacobian_at_solution(double tm, double ab, Mat& Psi) {
        prob_.N_jacobian(tm, newton_.X, J_);
        c_.jac_evals += 1;
        newton_.S = Mat::Identity(d_, d_) - (0.5 * h_) * J_;
        newton_.factor_and_solve(Mat::Identity(d_, d_), Psi);
        Psi *= 2.0 * ab;
        Psi.diagonal().array() -= ab;
    }

    const P& prob_;
    double h_;
    Counters& c_;
    int d_;
    Vec y0_, n_; // e^{−ΔΓ₁} z₀ and N at the midpoint
    Mat J_;      // N' at the midpoint
    StageNewton newton_;
};

} // namespace dampsym
