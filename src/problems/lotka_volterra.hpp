// Lotka–Volterra (Volterra–Lotka) predator–prey model, HLW(1.1):
//   u' = u(v − 2),   v' = v(1 − u),
// with the first integral I(u, v) = ln u − u + 2 ln v − v (HLW(1.2)). Not a damped Hamiltonian
// system in q/p form: only the plain form f(z) is offered (no separable or conformal form, so
// cimp, csv1 and csv2 do not apply; HLW's symplectic Euler (1.8) is the method
// symplectic-euler-partitioned, on the halves z = (u, v)), no damping (Γ ≡ 0, so the "conformal
// law" of I is plain conservation). HLW Fig 1.1: h = 0.12, (u0, v0) = (2, 2) for explicit Euler,
// (4, 8) for implicit Euler, (4, 2) and (6, 2) for symplectic Euler. Numerical (certified GSL)
// reference.
#pragma once

#include "core/param_table.hpp"
#include "core/problem.hpp"

#include <array>
#include <cmath>
#include <string_view>

namespace dampsym {

struct LotkaVolterra : ParamTable<LotkaVolterra> {
    static constexpr std::string_view id = "lotka-volterra";
    static constexpr OrbitFigure figure_orbit =
        OrbitFigure::by_default; // its figures draw the orbit
    static constexpr std::string_view title = "Lotka–Volterra u'=u(v−2), v'=v(1−u) (HLW(1.1))";
    static constexpr bool has_separable = false;
    static constexpr bool has_conformal = false;
    static constexpr bool constant_gamma = true;
    static constexpr bool is_linear = false;
    static constexpr bool has_exact = false;
    static constexpr bool has_energy = false;
    // z = (u, v) is a partitioned system HLW (1.7): HLW's symplectic Euler (1.8) applies
    // (methods/symplectic_euler_partitioned.hpp).
    static constexpr bool partitioned_halves = true;
    static constexpr std::array<std::string_view, 1> invariant_names{"I"};
    // Law residual scale (docs/conventions.md): I ≤ max(ln u − u) + max(2 ln v − v) =
    // −1 + 2 ln 2 − 2 ≈ −1.61 on the whole domain, so I is bounded away from zero and |I| is its
    // own scale (the plain relative residual).
    static constexpr std::array<std::string_view, 1> invariant_scale_defs{
        "|I| (I <= 2 ln 2 - 3 < 0)"};

    double u0 = 2.0, v0 = 2.0;

    // Ranges: populations in [1e-3, 1e3]; beyond, the orbit's excursions (e^{±u0}, e^{±v0} along
    // the level set of I) leave the range where the certified reference finishes.
    static std::vector<Param<LotkaVolterra>> param_table() {
        return {
            {{"u0", 2.0, Range::closed(1e-3, 1e3),
              "initial predator population u(0) (HLW: 2, 4 or 6)"},
             &LotkaVolterra::u0},
            {{"v0", 2.0, Range::closed(1e-3, 1e3), "initial prey population v(0) (HLW: 2 or 8)"},
             &LotkaVolterra::v0}};
    }

    int dim() const { return 2; }
    Vec initial_state() const { return Vec{{u0, v0}}; }
    double gamma_at(double) const { return 0.0; }
    double Gamma(double) const { return 0.0; }
    double dGamma(double, double) const { return 0.0; }

    void rhs(double, const Vec& z, Vec& out) const {
        out[0] = z[0] * (z[1] - 2.0);
        out[1] = z[1] * (1.0 - z[0]);
    }
    void rhs_jacobian(double, const Vec& z, Mat& J) const {
        J(0, 0) = z[1] - 2.0;
        J(0, 1) = z[0];
        J(1, 0) = -z[1];
        J(1, 1) = 1.0 - z[0];
    }

    // HLW(1.2); NaN once a population leaves (0, ∞), which the check then reports.
    void invariants(double, const Vec& z, double* out) const {
        out[0] = std::log(z[0]) - z[0] + 2.0 * std::log(z[1]) - z[1];
    }
    void invariant_scales(double t, const Vec& z, double* out) const {
        invariants(t, z, out);
        out[0] = std::abs(out[0]);
    }
};

} // namespace dampsym
