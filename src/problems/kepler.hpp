// Kepler's problem, HLW I.2: q'' = −q/|q|³ in the plane (HLW(2.1)), i.e. the Hamiltonian system
// HLW(2.2) with H = ½|p|² − 1/|q| (HLW(2.3)), unit mass, no damping (γ ≡ 0, Γ ≡ 0). Initial values
// HLW(2.9): q(0) = (1 − e, 0), p(0) = (0, √((1+e)/(1−e))), 0 ≤ e < 1 (default e = 0.6 as in HLW
// Figs 2.1–2.2), so H0 = −½, L0 = √(1 − e²), period 2π; long-time behaviour of the methods in
// HLW Table 2.1. It is the N-body problem with one body in the field of a fixed centre (the
// relative motion of a 2-body problem), written directly, not through NBodySystem:
//   force F(q) = −q/|q|³,   ∂F/∂q = −I/|q|³ + 3 q qᵀ/|q|⁵.
// Invariant: the angular momentum L = q1 p2 − q2 p1 (HLW(2.4)), a quadratic conformal invariant
// (with γ = 0 a first integral). energy() = H (HLW(2.3)). Exact solution through Kepler's equation
// (reference/kepler_exact.hpp). Momentum hooks (space_dim 2): angular_momentum = (L); the linear
// momentum p is NOT conserved here (the fixed centre exerts a force), so linear_momentum_law =
// false and a momentum diagnostic must not check Σp on this problem.
#pragma once

#include "core/param_table.hpp"
#include "core/problem.hpp"
#include "reference/kepler_exact.hpp"

#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace dampsym {

struct Kepler : SeparableProblem<Kepler>, UnitMass, ConstantGamma<Kepler>, ParamTable<Kepler> {
    static constexpr std::string_view id = "kepler";
    static constexpr OrbitFigure figure_orbit =
        OrbitFigure::by_default; // its figures draw the orbit
    static constexpr std::string_view title = "Kepler's problem q''=-q/|q|^3, HLW(2.1), HLW(2.9)";
    static constexpr bool is_linear = false;
    static constexpr bool has_exact = true;
    static constexpr bool autonomous = true;
    static constexpr bool has_energy = true;
    static constexpr bool has_momentum = true;
    static constexpr bool linear_momentum_law = false;
    static constexpr bool autonomous_potential = true; // V = −1/|q|
    static constexpr std::array<std::string_view, 1> invariant_names{"angular_momentum"};
    // Law residual scale (docs/conventions.md): L = q1 p2 − q2 p1 vanishes for radial motion, so
    // its scale is |z|ᵀ|A||z| = |q1 p2| + |q2 p1|.
    static constexpr std::array<std::string_view, 1> invariant_scale_defs{"|q1 p2| + |q2 p1|"};
    static constexpr double gamma = 0.0; // no damping: γ ≡ 0 (used by ConstantGamma)

    double e = 0.6;

    // Range: e ≤ 0.99 (HLW(2.9) needs e < 1; near 1 the initial speed √((1+e)/(1−e)) and Kepler's
    // equation lose accuracy).
    static std::vector<Param<Kepler>> param_table() {
        return {{{"e", 0.6, Range::closed(0.0, 0.99), "eccentricity, 0 <= e <= 0.99 (HLW(2.9))"},
                 &Kepler::e}};
    }
    void check_params() const {
        if (!(e >= 0.0 && e < 1.0))
            throw std::invalid_argument("kepler: e must satisfy 0 <= e < 1, got " +
                                        std::to_string(e));
    }

    // H0 = −½, L0 = √(1 − e²), period 2π (HLW I.2).
    static constexpr double H0() { return -0.5; }
    double L0() const { return std::sqrt((1.0 - e) * (1.0 + e)); }
    static constexpr double period() { return 2.0 * std::numbers::pi; }

    // The Laplace–Runge–Lenz vector A = p × L e_z − q/|q| = (p2 L − q1/|q|, −p1 L − q2/|q|)
    // (L = q1 p2 − q2 p1): constant along the exact flow, pointing to the perihelion, |A| = e
    // (diagnostic "precession", HLW Fig 2.1). With HLW(2.9), A(0) = (e, 0).
    std::array<double, 2> runge_lenz(const Vec& z) const {
        const double L = z[0] * z[3] - z[1] * z[2];
        const double r = std::hypot(z[0], z[1]);
        return {z[3] * L - z[0] / r, -z[2] * L - z[1] / r};
    }

    static constexpr int static_n = 2; // degrees of freedom (core/problem.hpp)
    int n() const { return static_n; }
    Vec initial_state() const { return Vec{{1.0 - e, 0.0, 0.0, std::sqrt((1.0 + e) / (1.0 - e))}}; }

    template <class In, class Out>
    void force(double, const In& q, Out& out) const {
        const double r2 = q[0] * q[0] + q[1] * q[1];
        const double c = 1.0 / (r2 * std::sqrt(r2));
        out[0] = -c * q[0];
        out[1] = -c * q[1];
    }
    template <class In, class Out>
    void force_jacobian(double, const In& q, Out& out) const {
        const double r2 = q[0] * q[0] + q[1] * q[1];
        const double c = 1.0 / (r2 * std::sqrt(r2));
        const double d = 3.0 * c / r2;
        out(0, 0) = -c + d * q[0] * q[0];
        out(0, 1) = d * q[0] * q[1];
        out(1, 0) = d * q[0] * q[1];
        out(1, 1) = -c + d * q[1] * q[1];
    }

    void invariants(double, const Vec& z, double* out) const { out[0] = z[0] * z[3] - z[1] * z[2]; }
    void invariant_scales(double, const Vec& z, double* out) const {
        out[0] = std::abs(z[0] * z[3]) + std::abs(z[1] * z[2]);
    }
    double energy(const Vec& z) const {
        return 0.5 * (z[2] * z[2] + z[3] * z[3]) - 1.0 / std::hypot(z[0], z[1]);
    }
    // Scale of energy changes and errors: T + |V| = ½|p|² + 1/|q| (H = T + V crosses zero).
    double energy_scale(const Vec& z) const {
        return 0.5 * (z[2] * z[2] + z[3] * z[3]) + 1.0 / std::hypot(z[0], z[1]);
    }
    // Solution with z(t0) = z0 (core/problem.hpp), autonomous: from HLW(2.9)'s own state
    // (initial_state(), bitwise) through Kepler's equation at t − t0 (kepler_exact); from any
    // other state on an elliptic orbit by Lagrange's f and g (kepler_propagate); NaN on an
    // unbound or radial orbit.
    void exact(double t0, const Vec& z0, double t, Vec& out) const {
        KeplerState s;
        if (t == t0)
            s = {z0[0], z0[1], z0[2], z0[3]};
        else if (z0 == initial_state())
            s = kepler_exact(e, t - t0);
        else
            s = kepler_propagate({z0[0], z0[1], z0[2], z0[3]}, t - t0);
        out[0] = s.q1;
        out[1] = s.q2;
        out[2] = s.p1;
        out[3] = s.p2;
    }

    int space_dim() const { return 2; }
    void linear_momentum(const Vec& z, Vec& out) const {
        out.resize(2);
        out[0] = z[2];
        out[1] = z[3];
    }
    void angular_momentum(const Vec& z, Vec& out) const {
        out.resize(1);
        out[0] = z[0] * z[3] - z[1] * z[2];
    }
    // Scales of the momentum laws (docs/conventions.md): ‖p‖ and ‖q‖‖p‖.
    double linear_momentum_scale(const Vec& z) const { return std::hypot(z[2], z[3]); }
    double angular_momentum_scale(const Vec& z) const {
        return std::hypot(z[0], z[1]) * std::hypot(z[2], z[3]);
    }
};

} // namespace dampsym
