// Damped nonlinear pendulum q'' + 2γq' + sin q = 0 (F(4.5) with its typo 2γq corrected to 2γq',
// conventions §6; B §3.2.1). T = p²/2, V = −cos q; energy ½p² − cos q with the balance
// d/dt(½p² − cos q) = −2γp² (B(3.4)). No closed form: numerical (certified GSL) reference.
#pragma once

#include "core/param_table.hpp"
#include "core/problem.hpp"

#include <array>
#include <cmath>
#include <string_view>

namespace dampsym {

struct Pendulum : SeparableProblem<Pendulum>,
                  UnitMass,
                  ConstantGamma<Pendulum>,
                  ParamTable<Pendulum> {
    static constexpr std::string_view id = "pendulum";
    static constexpr OrbitFigure figure_orbit =
        OrbitFigure::on_request; // a phase portrait when a case asks
    static constexpr std::string_view title = "damped pendulum q''+2γq'+sin q=0";
    static constexpr bool is_linear = false;
    static constexpr bool has_exact = false;
    static constexpr bool has_energy = true;
    static constexpr bool autonomous_potential = true; // V = −cos q: energy balance B(3.4)
    static constexpr std::array<std::string_view, 0> invariant_names{};
    static constexpr std::array<std::string_view, 0> invariant_scale_defs{};

    double gamma = 0.0, q0 = 1.0, p0 = 0.0;

    // Ranges: γ ≤ 1e3 keeps the certified (explicit, adaptive) reference non-stiff enough to
    // finish; |q0|, |p0| ≤ 1e6 keep sin, cos and the energy accurate.
    static std::vector<Param<Pendulum>> param_table() {
        return {{{"gamma", 0.0, Range::closed(0.0, 1e3), "damping γ (q'' + 2γq' + sin q = 0)"},
                 &Pendulum::gamma},
                {{"q0", 1.0, Range::symmetric(1e6), "initial angle"}, &Pendulum::q0},
                {{"p0", 0.0, Range::symmetric(1e6), "initial angular velocity"}, &Pendulum::p0}};
    }

    static constexpr int static_n = 1; // degrees of freedom (core/problem.hpp)
    int n() const { return static_n; }
    Vec initial_state() const { return Vec{{q0, p0}}; }

    template <class In, class Out>
    void force(double, const In& q, Out& out) const {
        out[0] = -std::sin(q[0]);
    }
    template <class In, class Out>
    void force_jacobian(double, const In& q, Out& out) const {
        out(0, 0) = -std::cos(q[0]);
    }

    void invariants(double, const Vec&, double*) const {}
    void invariant_scales(double, const Vec&, double*) const {}
    double energy(const Vec& z) const { return 0.5 * z[1] * z[1] - std::cos(z[0]); }
    // Scale of energy changes and errors: T + the amplitude of V = ½p² + 1 (H crosses zero;
    // |−cos q| ≤ 1, and the amplitude does not vanish where cos q does).
    double energy_scale(const Vec& z) const { return 0.5 * z[1] * z[1] + 1.0; }
};

} // namespace dampsym
