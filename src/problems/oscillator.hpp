// Damped harmonic oscillator q'' + 2γq' + ω²q = 0 (F(2.5), F ch.3–4, B Ex. 1.2).
// T = p²/2, V = ω²q²/2; conformal invariant H_γ = ½(ω²q² + p²) + γqp (B Ex. 1.2), which decays as
// e^{-2γt}; energy H = ½(p² + ω²q²) (F Figs 4.2–4.5). Exact solution in all three regimes.
#pragma once

#include "core/param_table.hpp"
#include "core/problem.hpp"
#include "reference/oscillator_exact.hpp"

#include <array>
#include <cmath>
#include <string_view>

namespace dampsym {

struct Oscillator : SeparableProblem<Oscillator>,
                    UnitMass,
                    ConstantGamma<Oscillator>,
                    ParamTable<Oscillator> {
    static constexpr std::string_view id = "oscillator";
    static constexpr OrbitFigure figure_orbit =
        OrbitFigure::on_request; // a phase portrait when a case asks
    static constexpr std::string_view title = "damped harmonic oscillator q''+2γq'+ω²q=0";
    static constexpr bool is_linear = true;
    static constexpr bool has_exact = true;
    static constexpr bool autonomous = true;
    static constexpr bool has_energy = true;
    static constexpr bool autonomous_potential = true; // V = ω²q²/2: Ḣ = −2γp²
    static constexpr std::array<std::string_view, 1> invariant_names{"H_gamma"};
    // Scale of each invariant's law residual (docs/conventions.md, "Law residuals and their
    // scales"): H_γ = zᵀAz is indefinite for γ > ω (it passes through zero), so its scale is
    // |z|ᵀ|A||z| = ½(ω²q² + p²) + γ|qp|, the sum of the magnitudes of its terms.
    static constexpr std::array<std::string_view, 1> invariant_scale_defs{
        "|z|^T|A||z| = (w^2 q^2 + p^2)/2 + gamma |q p|"};

    double omega = 1.0, gamma = 0.0, q0 = 1.0, p0 = 0.0;

    // Ranges: with ω, γ, |q0|, |p0| ≤ 1e6 every product in the exact solution and the invariant
    // (ω²q0, γ², (ω−γ)(ω+γ), γq0p0) stays below 1e24, far from overflow; beyond, γ² overflows
    // near γ = 1.3e154 and the "exact" solution is wrong.
    static std::vector<Param<Oscillator>> param_table() {
        return {
            {{"omega", 1.0, Range::closed(1e-6, 1e6), "natural frequency ω"}, &Oscillator::omega},
            {{"gamma", 0.0, Range::closed(0.0, 1e6), "damping γ (q'' + 2γq' + ω²q = 0)"},
             &Oscillator::gamma},
            {{"q0", 1.0, Range::symmetric(1e6), "initial position q(t0)"}, &Oscillator::q0},
            {{"p0", 0.0, Range::symmetric(1e6), "initial momentum p(t0) = q'(t0)"},
             &Oscillator::p0}};
    }

    // The same oscillator at other coefficients (core/problem_concepts.hpp LinearOscillator).
    Oscillator with(double omega_, double gamma_) const {
        Oscillator o = *this;
        o.omega = omega_;
        o.gamma = gamma_;
        return o;
    }

    static constexpr int static_n = 1; // degrees of freedom (core/problem.hpp)
    int n() const { return static_n; }
    Vec initial_state() const { return Vec{{q0, p0}}; }

    template <class In, class Out>
    void force(double, const In& q, Out& out) const {
        out = -(omega * omega) * q;
    }
    template <class In, class Out>
    void force_jacobian(double, const In&, Out& out) const {
        out.setIdentity();
        out *= -(omega * omega);
    }

    void invariants(double, const Vec& z, double* out) const {
        out[0] = 0.5 * (omega * omega * z[0] * z[0] + z[1] * z[1]) + gamma * z[0] * z[1];
    }
    void invariant_scales(double, const Vec& z, double* out) const {
        out[0] = 0.5 * (omega * omega * z[0] * z[0] + z[1] * z[1]) + gamma * std::abs(z[0] * z[1]);
    }
    double energy(const Vec& z) const { return 0.5 * (z[1] * z[1] + omega * omega * z[0] * z[0]); }
    // Scale of energy changes and errors: H itself (a definite form, zero only at z = 0).
    double energy_scale(const Vec& z) const { return energy(z); }
    // Solution with z(t0) = z0 (core/problem.hpp): constant coefficients, so the solution from
    // (0, z0) at t − t0 (bitwise the old t0 = 0 form; at t = t0 exactly z0: C = 1, S = 0).
    void exact(double t0, const Vec& z0, double t, Vec& out) const {
        const OscillatorState s = oscillator_exact(omega, gamma, z0[0], z0[1], t - t0);
        out[0] = s.q;
        out[1] = s.p;
    }
};

} // namespace dampsym
