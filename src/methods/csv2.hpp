// CSV2, conformal Störmer–Verlet method 2 (F(2.16), B(2.21) with B's γ = 2× ours), our γ:
//   (1 + γh/2) p½ = e^{−γh/2} p − (h/2) ∇V(q)
//   (1 − γh/2) q₁ = e^{−γh/2} [ (1 + γh/2) e^{−γh/2} q + h ∇T(p½) ]
//   p₁ = e^{−γh/2} [ (1 − γh/2) p½ − (h/2) ∇V(q₁) ]
// Defined for γh ≠ 2 (the q-update divides by 1 − γh/2: at γh = 2 the step produces inf and the
// run is reported as diverged, not crashed). Two force evaluations per step. With time-dependent
// γ (hill) γh is replaced at every step by x_n = Γ(t_n + h) − Γ(t_n) (γ frozen at its mean over
// the step, as the exponential kernels do): the product of the three stage factors is
// e/(1+x/2) · e²(1+x/2)/(1−x/2) · e(1−x/2) = e⁴ = e^{−2x_n}, so the step stays conformal
// symplectic with the physical factor e^{−2ΔΓ}; freezing costs O(γ'h³) per step (order 2 kept).
//
// step_jacobian() also returns Ψ = ∂z₁/∂z₀ by the chain rule through the three stages, with
// e = e^{−γh/2}, F' = ∂F/∂q (force_jacobian), T'' = ∇²T (hess_T), row blocks over (q₀, p₀):
//   ∂p½ = [ (h/2)F'(q₀, t),  e I ] / (1 + γh/2)
//   ∂q₁ = e ([ (1 + γh/2) e I, 0 ] + h T''(p½) ∂p½) / (1 − γh/2)
//   ∂p₁ = e ((1 − γh/2) ∂p½ + (h/2) F'(q₁, t+h) ∂q₁)
#pragma once

#include "core/method.hpp"
#include "methods/hand_written.hpp"

#include <cmath>
#include <string_view>

namespace dampsym {

template <class P>
class Csv2 : public OneCodePathKernel<Csv2<P>, Scheme::csv2> {
public:
    static constexpr std::string_view kernel_id = "csv2";
    template <class Q>
    static constexpr bool applies = Q::has_separable;

    Csv2(const P& problem, const MethodInfo&, double h, Counters& counters)
        : prob_(problem), h_(h), c_(counters), n_(problem.n()), a_(n_), f_(n_), Fq_(n_, n_),
          Tpp_(n_, n_), dp_(n_, 2 * n_), dq_(n_, 2 * n_) {
        set_argument(problem.dGamma(0.0, h)); // γh for constant γ
    }

private:
    friend class OneCodePathKernel<Csv2<P>, Scheme::csv2>; // step() and step_jacobian()
    int state_dim() const { return 2 * n_; }

    void set_argument(double x) {
        e_ = std::exp(-0.5 * x);
        plus_ = 1.0 + 0.5 * x;
        minus_ = 1.0 - 0.5 * x;
    }

    template <bool WithJacobian>
    [[gnu::always_inline]] inline StepStatus advance(double t, Vec& z, Mat* Psi) {
        if constexpr (!P::constant_gamma) set_argument(prob_.dGamma(t, h_));
        auto q = z.head(n_);
        auto p = z.tail(n_);
        prob_.force(t, q, f_);
        if constexpr (WithJacobian) {
            Fq_.setZero(); // as SeparableProblem::N_jacobian: problems may fill a part
            prob_.force_jacobian(t, q, Fq_); // at q₀
            dp_.leftCols(n_) = ((0.5 * h_) / plus_) * Fq_;
            dp_.rightCols(n_).setZero();
            dp_.rightCols(n_).diagonal().setConstant(e_ / plus_);
        }
        p = (e_ * p + (0.5 * h_) * f_) / plus_;
        prob_.grad_T(p, a_);
        if constexpr (WithJacobian) {
            Tpp_.setZero();        // as SeparableProblem::N_jacobian: problems may fill a part
            prob_.hess_T(p, Tpp_); // at p½
            dq_.noalias() = h_ * Tpp_ * dp_;
            dq_.leftCols(n_).diagonal().array() += plus_ * e_;
            dq_ *= e_ / minus_;
        }
        q = (e_ * (plus_ * e_ * q + h_ * a_)) / minus_;
        prob_.force(t + h_, q, f_);
        p = e_ * (minus_ * p + (0.5 * h_) * f_);
        c_.rhs_evals += 2;
        if constexpr (WithJacobian) {
            Fq_.setZero(); // as SeparableProblem::N_jacobian: problems may fill a part
            prob_.force_jacobian(t + h_, q, Fq_); // at q₁
            c_.jac_evals += 2;
            Psi->topRows(n_) = dq_;
            Psi->bottomRows(n_) = minus_ * dp_;
            Psi->bottomRows(n_).noalias() += (0.5 * h_) * Fq_ * dq_;
            Psi->bottomRows(n_) *= e_;
        }
        return StepStatus::ok;
    }

    const P& prob_;
    double h_;
    Counters& c_;
    int n_;
    Vec a_, f_;
    Mat Fq_, Tpp_; // ∂F/∂q and ∇²T at the current stage
    Mat dp_, dq_;  // ∂p½/∂z₀ and ∂q₁/∂z₀, n × 2n
    double e_ = 1.0, plus_ = 1.0, minus_ = 1.0;
};

} // namespace dampsym
