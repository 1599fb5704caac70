// CSV1, conformal Störmer–Verlet method 1 (F(2.12), B(2.20) with B's γ = 2× ours), our γ:
//   p½  = e^{−γh} p − (h/2) ∇V(q)
//   q₁  = q + h ∇T(p½)
//   p₁  = e^{−γh} (p½ − (h/2) ∇V(q₁))
// i.e. damping, kick, drift, kick, damping (Strang splitting of F §2.2.1). With time-dependent γ
// the half-step factors are e^{−2(Γ(t+h/2)−Γ(t))} and e^{−2(Γ(t+h)−Γ(t+h/2))}; the kicks use the
// force at t and t+h. Two force evaluations per step (as counted in F Table 4.1).
//
// step_jacobian() also returns Ψ = ∂z₁/∂z₀ by the chain rule through the three stages, with
// F' = ∂F/∂q (force_jacobian) and T'' = ∇²T (hess_T), each a row block over the columns (q₀, p₀):
//   ∂p½ = [ (h/2)F'(q₀, t),  d₁ I ]
//   ∂q₁ = [ I, 0 ] + h T''(p½) ∂p½
//   ∂p₁ = d₂ (∂p½ + (h/2) F'(q₁, t+h) ∂q₁)
#pragma once

#include "core/method.hpp"
#include "core/problem.hpp"

#include <cmath>
#include <string_view>

namespace dampsym {

template <class P>
class Csv1 {
public:
    static constexpr std::string_view kernel_id = "csv1";
    template <class Q>
    static constexpr bool applies = Q::has_separable;

    static constexpr bool has_step_jacobian = true;

    Csv1(const P& problem, const MethodInfo&, double h, Counters& counters)
        : prob_(problem), h_(h), c_(counters), n_(problem.n()), a_(n_), f_(n_), Fq_(n_, n_),
          Tpp_(n_, n_), dp_(n_, 2 * n_), dq_(n_, 2 * n_),
          d_const_(std::exp(-2.0 * problem.dGamma(0.0, 0.5 * h))) {}

    // Forced inline into the integrate() loop (the harness's step loop costs as the bare one).
    [[gnu::always_inline]] inline StepStatus step(double t, Vec& z) {
        return advance<false>(t, z, nullptr);
    }

    // Same arithmetic for z as step() (one code path); Psi = ∂z₁/∂z₀ (resized to d×d if needed).
    StepStatus step_jacobian(double t, Vec& z, Mat& Psi) {
        if (Psi.rows() != 2 * n_ || Psi.cols() != 2 * n_) Psi.resize(2 * n_, 2 * n_);
        return advance<true>(t, z, &Psi);
    }

private:
    // Stage vectors of the problem's compile-time size when it has one (static_dof): the updates
    // below are then scalar code that needs no inlining of Eigen's assignment loops, which GCC
    // declines in the large translation units that instantiate every kernel.
    static constexpr int N = static_dof<P>();
    using VecN = Eigen::Matrix<double, N, 1>;

    template <bool WithJacobian>
    [[gnu::always_inline]] inline StepStatus advance(double t, Vec& z, Mat* Psi) {
        const int n = N == Eigen::Dynamic ? n_ : N;
        Eigen::Map<VecN> q(z.data(), n), p(z.data() + n, n);
        const double hh = 0.5 * h_;
        // Constant γ: both factors are e^{−γh}, computed once (same value as per step).
        const double d1 = P::constant_gamma ? d_const_ : std::exp(-2.0 * prob_.dGamma(t, hh));
        const double d2 = P::constant_gamma ? d_const_ : std::exp(-2.0 * prob_.dGamma(t + hh, hh));
        prob_.force(t, q, f_);
        if constexpr (WithJacobian) {
            Fq_.setZero(); // as SeparableProblem::N_jacobian: problems may fill a part
            prob_.force_jacobian(t, q, Fq_); // at q₀
            dp_.leftCols(n_) = hh * Fq_;
            dp_.rightCols(n_).setZero();
            dp_.rightCols(n_).diagonal().setConstant(d1);
        }
        for (int i = 0; i < n; ++i) p[i] = d1 * p[i] + hh * f_[i]; // p½
        prob_.grad_T(p, a_);
        if constexpr (WithJacobian) {
            Tpp_.setZero();        // as SeparableProblem::N_jacobian: problems may fill a part
            prob_.hess_T(p, Tpp_); // at p½
            dq_.noalias() = h_ * Tpp_ * dp_;
            dq_.leftCols(n_).diagonal().array() += 1.0;
        }
        for (int i = 0; i < n; ++i) q[i] += h_ * a_[i]; // q₁
        prob_.force(t + h_, q, f_);
        for (int i = 0; i < n; ++i) p[i] = d2 * (p[i] + hh * f_[i]); // p₁
        c_.rhs_evals += 2;
        if constexpr (WithJacobian) {
            Fq_.setZero(); // as SeparableProblem::N_jacobian: problems may fill a part
            prob_.force_jacobian(t + h_, q, Fq_); // at q₁
            c_.jac_evals += 2;
            Psi->topRows(n_) = dq_;
            Psi->bottomRows(n_) = dp_;
            Psi->bottomRows(n_).noalias() += hh * Fq_ * dq_;
            Psi->bottomRows(n_) *= d2;
        }
        return StepStatus::ok;
    }

    const P& prob_;
    double h_;
    Counters& c_;
    int n_;
    VecN a_, f_;     // ∇T(p½) and the force at the current stage
    Mat Fq_, Tpp_;   // ∂F/∂q and ∇²T at the current stage
    Mat dp_, dq_;    // ∂p½/∂z₀ and ∂q₁/∂z₀, n × 2n
    double d_const_; // e^{−2ΔΓ} over a half step when γ is constant
};

} // namespace dampsym
