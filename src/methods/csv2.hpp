// CSV2, conformal Störmer–Verlet method 2 (F(2.16), B(2.21) with B's γ = 2× ours), our γ:
//   (1 + γh/2) p½ = e^{−γh/2} p − (h/2) ∇V(q)
//   (1 − γh/2) q₁ = e^{−γh/2} [ (1 + γh/2) e^{−γh/2} q + h ∇T(p½) ]
//   p₁ = e^{−γh/2} [ (1 − γh/2) p½ − (h/2) ∇V(q₁) ]
// Defined for constant γ only, and for γh ≠ 2 (the q-update divides by 1 − γh/2: at γh = 2 the
// step produces inf and the run is reported as diverged, not crashed). Two force evaluations per
// step.
#pragma once

#include "core/method.hpp"

#include <cmath>
#include <string_view>

namespace dampsym {

template <class P>
class Csv2 {
public:
    static constexpr std::string_view kernel_id = "csv2";
    template <class Q>
    static constexpr bool applies = Q::has_separable&& Q::constant_gamma;

    Csv2(const P& problem, const MethodInfo&, double h, Counters& counters)
        : prob_(problem), h_(h), c_(counters), n_(problem.n()), a_(n_), f_(n_) {
        const double gh2 = 0.5 * problem.gamma_at(0.0) * h;
        e_ = std::exp(-gh2);
        plus_ = 1.0 + gh2;
        minus_ = 1.0 - gh2;
    }

    StepStatus step(double t, Vec& z) {
        auto q = z.head(n_);
        auto p = z.tail(n_);
        prob_.force(t, q, f_);
        p = (e_ * p + (0.5 * h_) * f_) / plus_;
        prob_.grad_T(p, a_);
        q = (e_ * (plus_ * e_ * q + h_ * a_)) / minus_;
        prob_.force(t + h_, q, f_);
        p = e_ * (minus_ * p + (0.5 * h_) * f_);
        c_.rhs_evals += 2;
        return StepStatus::ok;
    }

private:
    const P& prob_;
    double h_;
    Counters& c_;
    int n_;
    Vec a_, f_;
    double e_ = 1.0, plus_ = 1.0, minus_ = 1.0;
};

} // namespace dampsym
