// Integrating-factor Runge–Kutta methods (IFRK), B(2.5), built from any RK tableau (α, β, c),
// explicit or implicit, on the conformal form z' = N(z, t) − γ(t) z (SPEC §1, B(1.1)):
//   x_n(τ) = ∫₀^τ γ(s + t_n) ds = Γ(t_n + τ) − Γ(t_n)                                   B(2.4)
//   Z_i     = e^{−x_n(c_i h)} z_n + h Σ_j α_ij e^{x_n(c_j h) − x_n(c_i h)} N(Z_j, t_n + c_j h),
//   z_{n+1} = e^{−x_n(h)} z_n + h Σ_i β_i e^{−x_n(h) + x_n(c_i h)} N(Z_i, t_n + c_i h).  B(2.5)
// Every factor e^{−(Γ(a) − Γ(b))} is formed as exp(−problem.dGamma(b, a − b)) at the stage times
// t_n + c_i h, so a time-dependent γ (hill, rigid-body) enters through the problem's exact Γ.
// With the s-stage Gauss–Legendre tableau (src/methods/tableaux.hpp) this is GL-IFRK, B(2.11)
// (s = 1, = cimp F(2.3)) and B(2.12) (s = 2, written there for constant γ): conformal symplectic
// and conformal-quadratic-invariant preserving (B Thm 2.6, 2.11), order 2s ([12] in B, B §2).
// The glifrk1..3 rows of the catalog point at gauss_tableau(1..3).
//
// The stages are solved by Newton's method with the problem's analytic Jacobian N_jacobian on the
// full (s·d)×(s·d) system (implicit tableau) or computed stage by stage (explicit tableau); see
// detail::RungeKuttaEngine in implicit_rk.hpp for the iteration, the update without an extra
// evaluation (which for s = 1 reproduces cimp's arithmetic step for step), the counters, the
// solve_failed path and the exact step Jacobian (implicit-function theorem at the stages).
#pragma once

#include "core/method.hpp"
#include "methods/implicit_rk.hpp"

#include <string_view>

namespace dampsym {

template <class P>
class IFRK : public detail::RungeKuttaEngine<P, true> {
public:
    static constexpr std::string_view kernel_id = "ifrk";
    template <class Q>
    static constexpr bool applies = Q::has_conformal; // needs N(z, t), N_jacobian and Γ

    IFRK(const P& problem, const MethodInfo& info, double h, Counters& counters)
        : detail::RungeKuttaEngine<P, true>(problem, *info.tableau, h, counters) {}
};

} // namespace dampsym
