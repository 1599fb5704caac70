// CSV1, conformal Störmer–Verlet method 1 (F(2.12), B(2.20) with B's γ = 2× ours), our γ:
//   p½  = e^{−γh} p − (h/2) ∇V(q)
//   q₁  = q + h ∇T(p½)
//   p₁  = e^{−γh} (p½ − (h/2) ∇V(q₁))
// i.e. damping, kick, drift, kick, damping (Strang splitting of F §2.2.1). With time-dependent γ
// the half-step factors are e^{−2(Γ(t+h/2)−Γ(t))} and e^{−2(Γ(t+h)−Γ(t+h/2))}; the kicks use the
// force at t and t+h. Two force evaluations per step (as counted in F Table 4.1).
#pragma once

#include "core/method.hpp"

#include <cmath>
#include <string_view>

namespace dampsym {

template <class P>
class Csv1 {
public:
    static constexpr std::string_view kernel_id = "csv1";
    template <class Q>
    static constexpr bool applies = Q::has_separable;

    Csv1(const P& problem, const MethodInfo&, double h, Counters& counters)
        : prob_(problem), h_(h), c_(counters), n_(problem.n()), a_(n_), f_(n_) {}

    StepStatus step(double t, Vec& z) {
        auto q = z.head(n_);
        auto p = z.tail(n_);
        const double d1 = std::exp(-2.0 * prob_.dGamma(t, 0.5 * h_));
        const double d2 = std::exp(-2.0 * prob_.dGamma(t + 0.5 * h_, 0.5 * h_));
        prob_.force(t, q, f_);
        p = d1 * p + (0.5 * h_) * f_;
        prob_.grad_T(p, a_);
        q += h_ * a_;
        prob_.force(t + h_, q, f_);
        p = d2 * (p + (0.5 * h_) * f_);
        c_.rhs_evals += 2;
        return StepStatus::ok;
    }

private:
    const P& prob_;
    double h_;
    Counters& c_;
    int n_;
    Vec a_, f_;
};

} // namespace dampsym
