// Generic explicit Runge–Kutta kernel on the plain form z' = f(t, z) (the full damped vector
// field). The tableau is data (src/methods/catalog.cpp); this loop is the only code.
//   k_i = f(t + c_i h, z + h Σ_{j<i} a_ij k_j),   z₁ = z + h Σ b_i k_i
#pragma once

#include "core/method.hpp"

#include <string_view>

namespace dampsym {

template <class P>
class ExplicitRK {
public:
    static constexpr std::string_view kernel_id = "explicit-rk";
    template <class Q>
    static constexpr bool applies = true; // every problem offers the plain form

    ExplicitRK(const P& problem, const MethodInfo& info, double h, Counters& counters)
        : prob_(problem), t_(*info.tableau), h_(h), c_(counters), K_(problem.dim(), t_.stages),
          y_(problem.dim()), k_(problem.dim()) {}

    StepStatus step(double t, Vec& z) {
        const int s = t_.stages;
        for (int i = 0; i < s; ++i) {
            y_ = z;
            for (int j = 0; j < i; ++j)
                if (t_.A(i, j) != 0.0) y_ += (h_ * t_.A(i, j)) * K_.col(j);
            prob_.rhs(t + t_.c[static_cast<std::size_t>(i)] * h_, y_, k_);
            K_.col(i) = k_;
        }
        for (int i = 0; i < s; ++i) z += (h_ * t_.b[static_cast<std::size_t>(i)]) * K_.col(i);
        c_.rhs_evals += s;
        return StepStatus::ok;
    }

private:
    const P& prob_;
    const ButcherTableau& t_;
    double h_;
    Counters& c_;
    Mat K_;
    Vec y_, k_;
};

} // namespace dampsym
