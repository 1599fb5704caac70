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
#include "methods/hand_written.hpp"

#include <cmath>
#include <string_view>

namespace dampsym {

template <class P>
class Csv1 : public OneCodePathKernel<Csv1<P>, Scheme::csv1> {
public:
    static constexpr std::string_view kernel_id = "csv1";
    template <class Q>
    static constexpr bool applies = Q::has_separable;

    Csv1(const P& problem, const MethodInfo&, double h, Counters& counters)
        : prob_(problem), h_(h), c_(counters), n_(problem.n()), a_(n_), f_(n_), Fq_(n_, n_),
          Tpp_(n_, n_), dp_(n_, 2 * n_), dq_(n_, 2 * n_),
          d_const_(std::exp(-2.0 * problem.dGamma(0.0, 0.5 * h))) {}

private:
    friend class OneCodePathKernel<Csv1<P>, Scheme::csv1>; // step() and step_jacobian()
    int state_dim() const { return 2 * n_; }

    // With the problem's compile-time size (static_dof), q, p and the stage vectors are fixed-size
    // locals for the step, which the compiler keeps in registers (z is read once and written once),
    // and every update is scalar code that needs no inlining of Eigen's assignment loops (GCC
    // declines those in the large translation units that instantiate every kernel). Otherwise q
    // and p are views of z and the stage vectors are members.
    static constexpr int N = static_dof<P>();
    using VecN = Eigen::Matrix<double, N, 1>;

    template <bool WithJacobian>
    [[gnu::always_inline]] inline StepStatus advance(double t, Vec& z, Mat* Psi) {
        if constexpr (N == Eigen::Dynamic) {
            Eigen::Map<Vec> q(z.data(), n_), p(z.data() + n_, n_);
            advance_qp<WithJacobian>(t, q, p, a_, f_, Psi);
        } else {
            VecN q, p, a, f;
            for (int i = 0; i < N; ++i) {
                q[i] = z[i];
                p[i] = z[N + i];
            }
            advance_qp<WithJacobian>(t, q, p, a, f, Psi);
            for (int i = 0; i < N; ++i) {
                z[i] = q[i];
                z[N + i] = p[i];
            }
        }
        return StepStatus::ok;
    }

    // One step on q, p (n each), with a and f the storage of ∇T(p½) and of the force.
    template <bool WithJacobian, class Q, class A>
    [[gnu::always_inline]] inline void advance_qp(double t, Q& q, Q& p, A& a, A& f, Mat* Psi) {
        const int n = static_cast<int>(q.size());
        const double hh = 0.5 * h_;
        // Constant γ: both factors are e^{−γh}, computed once (same value as per step).
        const double d1 = P::constant_gamma ? d_const_ : std::exp(-2.0 * prob_.dGamma(t, hh));
        const double d2 = P::constant_gamma ? d_const_ : std::exp(-2.0 * prob_.dGamma(t + hh, hh));
        prob_.force(t, q, f);
        if constexpr (WithJacobian) {
            Fq_.setZero(); // as SeparableProblem::N_jacobian: problems may fill a part
            prob_.force_jacobian(t, q, Fq_); // at q₀
            dp_.leftCols(n_) = hh * Fq_;
            dp_.rightCols(n_).setZero();
            dp_.rightCols(n_).diagonal().setConstant(d1);
        }
        for (int i = 0; i < n; ++i) p[i] = d1 * p[i] + hh * f[i]; // p½
        prob_.grad_T(p, a);
        if constexpr (WithJacobian) {
            Tpp_.setZero();        // as SeparableProblem::N_jacobian: problems may fill a part
            prob_.hess_T(p, Tpp_); // at p½
            dq_.noalias() = h_ * Tpp_ * dp_;
            dq_.leftCols(n_).diagonal().array() += 1.0;
        }
        for (int i = 0; i < n; ++i) q[i] += h_ * a[i]; // q₁
        prob_.force(t + h_, q, f);
        for (int i = 0; i < n; ++i) p[i] = d2 * (p[i] + hh * f[i]); // p₁
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
    }

    const P& prob_;
    double h_;
    Counters& c_;
    int n_;
    Vec a_, f_;      // ∇T(p½) and the force (dynamic size only)
    Mat Fq_, Tpp_;   // ∂F/∂q and ∇²T at the current stage
    Mat dp_, dq_;    // ∂p½/∂z₀ and ∂q₁/∂z₀, n × 2n
    double d_const_; // e^{−2ΔΓ} over a half step when γ is constant
};

} // namespace dampsym
