// Integrating-factor Runge–Kutta methods (IFRK), B(2.5), built from any RK tableau (α, β, c),
// explicit or implicit, on the conformal form z' = N(z, t) − γ(t) z (conventions §1, B(1.1)):
//   x_n(τ) = ∫₀^τ γ(s + t_n) ds = Γ(t_n + τ) − Γ(t_n)                                   B(2.4)
//   Z_i     = e^{−x_n(c_i h)} z_n + h Σ_j α_ij e^{x_n(c_j h) − x_n(c_i h)} N(Z_j, t_n + c_j h),
//   z_{n+1} = e^{−x_n(h)} z_n + h Σ_i β_i e^{−x_n(h) + x_n(c_i h)} N(Z_i, t_n + c_i h).  B(2.5)
// The factors are the one integrating-factor formula (integrating_factor.hpp) with the problem's
// exact Γ at the stage times, so a time-dependent γ (hill, rigid-body) keeps the full order; with
// constant γ they do not depend on t and are formed at the first step only (the same values,
// since dGamma(t, a) = γa for every t).
// With the s-stage Gauss–Legendre tableau (src/methods/tableaux.hpp) this is GL-IFRK, B(2.11)
// (s = 1, = cimp F(2.3)) and B(2.12) (s = 2, written there for constant γ): conformal symplectic
// and conformal-quadratic-invariant preserving (B Thm 2.6, 2.11), order 2s ([12] in B, B §2).
// The glifrk1..3 rows of the catalog hold gauss_tableau(1..3). Stepping: the RK engine
// (rk_engine.hpp); this file is its integrating-factor provider and the kernel adapter.
#pragma once

#include "core/method.hpp"
#include "core/problem.hpp"
#include "methods/implicit_rk.hpp"
#include "methods/integrating_factor.hpp"

#include <cstddef>
#include <string_view>

namespace dampsym {

// Conformal form, B(2.5): y0_i = e^{−x(c_i h)}, F_i = e^{x(c_i h) − x(h)},
// M_ij = h α_ij e^{x(c_j h) − x(c_i h)}, w_i = h β_i F_i, φ0 = e^{−x(h)}, per step.
class IntegratingFactorProvider {
public:
    static constexpr bool conformal = true;
    explicit IntegratingFactorProvider(const ButcherTableau& t) : t_(t) {}
    int stages() const { return t_.stages; }
    template <class P>
    void init(const P&, double, RKStepCoefficients& k) const {
        constant_tableau_structure(t_, k);
    }
    template <class P>
    void at_step(const P& problem, double t, double h, RKStepCoefficients& k) {
        if constexpr (detail::declares_constant_gamma<P>()) {
            if (set_) return;
            set_ = true;
        }
        integrating_factors(
            t_, [&](double a, double b) { return problem.dGamma(t + a * h, (b - a) * h); }, f_);
        k.y0 = f_.phi;
        k.F = f_.F;
        k.phi0 = f_.phi0;
        for (int i = 0; i < t_.stages; ++i) {
            k.w[i] = h * t_.b[static_cast<std::size_t>(i)] * f_.F[i];
            for (int j = 0; j < t_.stages; ++j) {
                const double aij = t_.A(i, j);
                k.M(i, j) = aij == 0.0 ? 0.0 : (h * aij) * f_.E(i, j);
            }
        }
    }

private:
    const ButcherTableau& t_;
    IntegratingFactors f_;
    bool set_ = false;
};

template <class P>
class IFRK : public RungeKuttaEngine<P, IntegratingFactorProvider> {
public:
    static constexpr std::string_view kernel_id = "ifrk";
    using Data = IntegratingFactorTableau;
    static bool accepts(const Data&) { return true; }
    template <class Q>
    static constexpr bool applies = Q::has_conformal; // needs N(z, t), N_jacobian and Γ

    IFRK(const P& problem, const MethodInfo& info, double h, Counters& counters)
        : IFRK(problem, *std::get<Data>(info.data).tableau, h, counters) {}
    IFRK(const P& problem, const ButcherTableau& tableau, double h, Counters& counters)
        : RungeKuttaEngine<P, IntegratingFactorProvider>(
              problem, IntegratingFactorProvider(tableau), h, counters) {}
};

} // namespace dampsym
