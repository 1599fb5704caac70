// Hill's equation with time-dependent damping q'' + 2γ(t)q' + κ²q = 0, γ(t) = ½ε cos 2t
// (B §3.1.2, B(3.2)). Γ(t) = ¼ε sin 2t; Γ(t+h) − Γ(t) = ½ε cos(2t+h) sin h (no cancellation).
// Conformal symplectic structure with time-dependent γ. Numerical reference.
#pragma once

#include "core/param_table.hpp"
#include "core/problem.hpp"

#include <array>
#include <cmath>
#include <string_view>

namespace dampsym {

struct Hill : SeparableProblem<Hill>, UnitMass, ParamTable<Hill> {
    static constexpr std::string_view id = "hill";
    static constexpr OrbitFigure figure_orbit =
        OrbitFigure::by_default; // its figures draw the orbit
    static constexpr std::string_view title = "Hill equation q''+2γ(t)q'+κ²q=0, γ(t)=½ε cos 2t";
    static constexpr bool constant_gamma = false;
    static constexpr bool is_linear =
        false; // linear but time-dependent: no constant one-step matrix
    static constexpr bool has_exact = false;
    static constexpr bool has_energy = false;
    static constexpr std::array<std::string_view, 0> invariant_names{};
    static constexpr std::array<std::string_view, 0> invariant_scale_defs{};

    double epsilon = 0.1, kappa = 1.0, q0 = 1.0, p0 = 0.0;

    // Ranges: |ε| ≤ 1e3 bounds the conformal factor e^{±2Γ(t)} ≤ e^{500} (e^{709} overflows);
    // κ ≤ 1e3 keeps the certified reference non-stiff enough to finish.
    static std::vector<Param<Hill>> param_table() {
        return {{{"epsilon", 0.1, Range::symmetric(1e3), "ε in γ(t) = ½ε cos 2t"}, &Hill::epsilon},
                {{"kappa", 1.0, Range::closed(1e-6, 1e3), "frequency κ"}, &Hill::kappa},
                {{"q0", 1.0, Range::symmetric(1e6), "initial position"}, &Hill::q0},
                {{"p0", 0.0, Range::symmetric(1e6), "initial momentum"}, &Hill::p0}};
    }

    static constexpr int static_n = 1; // degrees of freedom (core/problem.hpp)
    int n() const { return static_n; }
    Vec initial_state() const { return Vec{{q0, p0}}; }
    double gamma_at(double t) const { return 0.5 * epsilon * std::cos(2.0 * t); }
    double Gamma(double t) const { return 0.25 * epsilon * std::sin(2.0 * t); }
    double dGamma(double t, double h) const {
        return 0.5 * epsilon * std::cos(2.0 * t + h) * std::sin(h);
    }

    template <class In, class Out>
    void force(double, const In& q, Out& out) const {
        out = -(kappa * kappa) * q;
    }
    template <class In, class Out>
    void force_jacobian(double, const In&, Out& out) const {
        out.setIdentity();
        out *= -(kappa * kappa);
    }

    void invariants(double, const Vec&, double*) const {}
    void invariant_scales(double, const Vec&, double*) const {}
};

} // namespace dampsym
