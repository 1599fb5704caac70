// Generic exponential Runge–Kutta kernel (ERK), B(2.7), on the conformal form
// z' = N(z, t) − γz (conventions §1, B(1.1)), for coefficient data that are functions of x = γh
// (src/methods/exponential_tableaux.hpp, held by the row's ExponentialCoefficients):
//   Z_i     = φ_i(x) z_n + h Σ_j a_ij(x) N(Z_j, t_n + c_j h),   i = 1..s,
//   z_{n+1} = φ_0(x) z_n + h Σ_i b_i(x) N(Z_i, t_n + c_i h),                          B(2.7)
// with tableau B(2.10) [c | A | φ ; bᵀ | φ_0]. Both constructions of B §2.1 are data of this one
// kernel: the integrating factor B(2.5) (a_ij = α_ij e^{−(c_i−c_j)x}, φ_i = e^{−c_i x},
// b_i = β_i e^{−(1−c_i)x}, φ_0 = e^{−x}) and exponential time differencing B(2.6), e.g. etdrk2
// B(2.13): c = ½, a = (e^{x/2} − e^{−x/2})/(2x) = sinh(x/2)/x, φ_1 = e^{−x/2}, b = (1 − e^{−x})/x,
// φ_0 = e^{−x}. x = γh is OUR γ: B(1.1), (2.5), (2.13) use the conformal-form γ, which is the
// γ of conventions §1 (only B(2.17)–(2.22), (2.34) use twice ours; see
// partitioned_exponential_rk.hpp).
//
// Damping argument. With constant γ the coefficients are evaluated once, in the constructor, at
// x = problem.dGamma(0, h) = γh. With time-dependent γ (hill, rigid-body) they are re-evaluated at
// the start of every step at the step's own argument x_n = Γ(t_n + h) − Γ(t_n) =
// problem.dGamma(t_n, h), i.e. γ frozen at its mean over the step (no allocation: the sizes do not
// change). Then φ_0 = e^{−x_n} and B(2.30) holds at x_n, so the step is conformal symplectic with
// exactly the physical factor e^{−2(Γ(t_n+h)−Γ(t_n))} (B(2.31), Thm 2.11;
// exponential_conditions.hpp evaluates both on the data). Freezing γ at its mean changes the exact
// flow by O(γ'h³) per step (the difference γ(s) − γ̄ has zero mean over the step), so the order is
// min(p, 2): every ERK/PERK row of the catalog has p ≤ 2. (glifrk1..3 keep their full order with
// time-dependent γ: they use the ifrk kernel, which evaluates Γ at every stage time, B(2.4)–(2.5).)
//
// Stepping: the RK engine (rk_engine.hpp: stage by stage for an explicit A, else the stage-Newton
// solver with N_jacobian; with A(x) invertible the update z_{n+1} = φ_0 z_n + Σ_k d_k (Z_k − φ_k
// z_n), d = A⁻ᵀb, needs no further evaluation (etdrk2: d = 2e^{−x/2}); exact step Jacobian by the
// implicit-function theorem). This file is its exponential-coefficient provider and the adapter.
#pragma once

#include "core/method.hpp"
#include "core/problem.hpp"
#include "methods/exponential_tableaux.hpp"
#include "methods/rk_engine.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string_view>
#include <vector>

namespace dampsym {

// Conformal form, B(2.7): y0 = φ(x), M = hA(x), w = hb(x), φ0(x), d = A(x)⁻ᵀb(x), at the damping
// argument x; recomputed only when x changes (nothing is allocated then).
class ExponentialProvider {
public:
    static constexpr bool conformal = true;
    explicit ExponentialProvider(const ExponentialRKData& data) : data_(checked(data)) {}
    int stages() const { return data_.stages; }
    const ExponentialTableau& tableau() const { return tab_; }

    template <class P>
    void init(const P& problem, double h, RKStepCoefficients& k) {
        const double x = problem.dGamma(0.0, h); // x = γh for constant γ
        erk_coefficients(data_, x, tab_);
        k.factored_update = false;
        k.explicit_tableau = true;
        for (int i = 0; i < data_.stages; ++i)
            for (int j = i; j < data_.stages; ++j)
                if (tab_.A(i, j) != 0.0) k.explicit_tableau = false;
        if (!k.explicit_tableau) k.use_d = Eigen::FullPivLU<Mat>(tab_.A.transpose()).isInvertible();
        set_argument(x, h, k, true);
    }
    template <class P>
    void at_step(const P& problem, double t, double h, RKStepCoefficients& k) {
        if constexpr (!detail::declares_constant_gamma<P>())
            set_argument(problem.dGamma(t, h), h, k, false);
    }

private:
    static const ExponentialRKData& checked(const ExponentialRKData& data) {
        if (data.stages < 1 || data.coefficients == nullptr)
            throw std::invalid_argument("exponential-rk: method row has no ERK coefficient data");
        return data;
    }

    void set_argument(double x, double h, RKStepCoefficients& k, bool force) {
        if (x == x_ && !force) return;
        x_ = x;
        erk_coefficients(data_, x, tab_);
        k.M = h * tab_.A;
        if (k.use_d) {
            lu_d_.compute(tab_.A.transpose());
            k.d = lu_d_.solve(tab_.b);
        }
        k.c = tab_.c;
        k.y0 = tab_.phi;
        k.w = h * tab_.b;
        k.phi0 = tab_.phi0;
    }

    const ExponentialRKData& data_;
    ExponentialTableau tab_;
    double x_ = std::numeric_limits<double>::quiet_NaN();
    Eigen::PartialPivLU<Mat> lu_d_{};
};

template <class P>
class ExponentialRK : public RungeKuttaEngine<P, ExponentialProvider> {
public:
    static constexpr std::string_view kernel_id = "exponential-rk";
    using Data = dampsym::ExponentialCoefficients;
    static bool accepts(const Data&) { return true; }
    template <class Q>
    static constexpr bool applies = [] {
        if constexpr (requires { Q::has_conformal; })
            return Q::has_conformal;
        else
            return false;
    }();

    ExponentialRK(const P& problem, const MethodInfo& info, double h, Counters& counters)
        : ExponentialRK(problem, *std::get<Data>(info.data).data, h, counters) {}
    ExponentialRK(const P& problem, const ExponentialRKData& data, double h, Counters& counters)
        : RungeKuttaEngine<P, ExponentialProvider>(problem, ExponentialProvider(data), h,
                                                   counters) {}

    // The coefficients at the current damping argument.
    const ExponentialTableau& coefficients() const { return this->provider().tableau(); }
};

} // namespace dampsym
