// Rigid body with periodic perturbation, B(1.7) (B Ex. 1.4, B §3.4, BS):
//   z' = S(z) z − γ(t) z,   γ(t) = ½ε cos 2t,   z = (z1, z2, z3) the angular momenta,
// with B's skew matrix S(z) = [0, z3/I3, −z2/I2; −z3/I3, 0, z1/I1; z2/I2, −z1/I1, 0], i.e.
//   N(z) = S(z) z = z × ω,   ω = I⁻¹ z   (the angular velocity),
//   z1' = (1/I3 − 1/I2) z2 z3,  z2' = (1/I1 − 1/I3) z3 z1,  z3' = (1/I2 − 1/I1) z1 z2,
// which is Euler's I ω' = (I ω) × ω (BS: A w1' = (B − C) w2 w3, ...). N does not depend on t and
// carries no γ: this problem is given directly in the conformal form of conventions §1 (not
// separable, so csv1/csv2 do not apply). Γ(t) = ¼ε sin 2t; Γ(t+h) − Γ(t) = ½ε cos(2t+h) sin h.
// Conformal invariants (B(3.10)), both decaying as e^{−2Γ(t)}: the Casimir C = |z|² and the energy
// H = ½ Σ z_i²/I_i; energy() = H. Defaults: BS's I = (4, 3, 2) and ω0 = (1, 1, 0), z0 = I ω0 =
// (4, 3, 0) (the z defaults do not follow a changed I). Exact solution for every ε
// (reference/rigid_body_exact.hpp): z(t) = e^{−Γ(t)} y(τ(t)) with the free body y in Jacobi
// elliptic functions; exact(t0, z0, t) is the solution with z(t0) = z0, which for this
// time-dependent γ is not a shift of the one from t = 0: z(t) = e^{−(Γ(t)−Γ(t0))} y(τ_{t0}(t)),
// τ_{t0}(t) = ∫_{t0}^t e^{−(Γ(s)−Γ(t0))} ds, y the free body from z0.
#pragma once

#include "core/param_table.hpp"
#include "core/problem.hpp"
#include "reference/rigid_body_exact.hpp"

#include <array>
#include <cmath>
#include <string_view>

namespace dampsym {

struct RigidBody : ParamTable<RigidBody>, ConformalForm<RigidBody> {
    static constexpr std::string_view id = "rigid-body";
    static constexpr OrbitFigure figure_orbit =
        OrbitFigure::on_request; // a phase portrait when a case asks
    static constexpr std::string_view title =
        "perturbed rigid body z'=z×(I⁻¹z)−γ(t)z, γ(t)=½ε cos 2t (B(1.7))";
    static constexpr bool has_separable = false;
    static constexpr bool has_conformal = true;
    static constexpr bool constant_gamma = false;
    static constexpr bool is_linear = false;
    static constexpr bool has_exact = true;
    static constexpr bool autonomous = false; // γ(t)
    static constexpr bool has_energy = true;
    static constexpr std::array<std::string_view, 2> invariant_names{"casimir", "energy"};
    // Law residual scales (docs/conventions.md): both invariants are definite forms, bounded away
    // from zero by the state's size, so each is its own scale (the plain relative residual).
    static constexpr std::array<std::string_view, 2> invariant_scale_defs{"|I| (definite)",
                                                                          "|I| (definite)"};

    double epsilon = 0.0, I1 = 4.0, I2 = 3.0, I3 = 2.0, z1 = 4.0, z2 = 3.0, z3 = 0.0;

    // Ranges: |ε| ≤ 1e3 bounds the conformal factor e^{±2Γ(t)} ≤ e^{500}; moments in [1e-6, 1e6]
    // and |z_i| ≤ 1e6 keep z_i²/I_i and the elliptic-function solution below overflow.
    static std::vector<Param<RigidBody>> param_table() {
        return {
            {{"epsilon", 0.0, Range::symmetric(1e3), "ε in γ(t) = ½ε cos 2t"}, &RigidBody::epsilon},
            {{"I1", 4.0, Range::closed(1e-6, 1e6), "principal moment of inertia I1 (BS: 4)"},
             &RigidBody::I1},
            {{"I2", 3.0, Range::closed(1e-6, 1e6), "principal moment of inertia I2 (BS: 3)"},
             &RigidBody::I2},
            {{"I3", 2.0, Range::closed(1e-6, 1e6), "principal moment of inertia I3 (BS: 2)"},
             &RigidBody::I3},
            {{"z1", 4.0, Range::symmetric(1e6), "initial angular momentum z1 (BS: I1·1)"},
             &RigidBody::z1},
            {{"z2", 3.0, Range::symmetric(1e6), "initial angular momentum z2 (BS: I2·1)"},
             &RigidBody::z2},
            {{"z3", 0.0, Range::symmetric(1e6), "initial angular momentum z3 (BS: I3·0)"},
             &RigidBody::z3}};
    }

    int dim() const { return 3; }
    Vec initial_state() const { return Vec{{z1, z2, z3}}; }
    double gamma_at(double t) const { return 0.5 * epsilon * std::cos(2.0 * t); }
    double Gamma(double t) const { return 0.25 * epsilon * std::sin(2.0 * t); }
    double dGamma(double t, double h) const {
        return 0.5 * epsilon * std::cos(2.0 * t + h) * std::sin(h);
    }

    // N(z) = z × ω, ω = I⁻¹z.
    void N(double, const Vec& z, Vec& out) const {
        const double w1 = z[0] / I1, w2 = z[1] / I2, w3 = z[2] / I3;
        out[0] = z[1] * w3 - z[2] * w2;
        out[1] = z[2] * w1 - z[0] * w3;
        out[2] = z[0] * w2 - z[1] * w1;
    }
    // ∂N/∂z = −[ω]ₓ + [z]ₓ I⁻¹ ([v]ₓu = v × u).
    void N_jacobian(double, const Vec& z, Mat& J) const {
        const double a1 = 1.0 / I1, a2 = 1.0 / I2, a3 = 1.0 / I3;
        const double w1 = a1 * z[0], w2 = a2 * z[1], w3 = a3 * z[2];
        J(0, 0) = 0.0;
        J(0, 1) = w3 - a2 * z[2];
        J(0, 2) = -w2 + a3 * z[1];
        J(1, 0) = -w3 + a1 * z[2];
        J(1, 1) = 0.0;
        J(1, 2) = w1 - a3 * z[0];
        J(2, 0) = w2 - a1 * z[1];
        J(2, 1) = -w1 + a2 * z[0];
        J(2, 2) = 0.0;
    }

    void invariants(double, const Vec& z, double* out) const {
        out[0] = z.squaredNorm();
        out[1] = energy(z);
    }
    void invariant_scales(double t, const Vec& z, double* out) const { invariants(t, z, out); }
    double energy(const Vec& z) const {
        return 0.5 * (z[0] * z[0] / I1 + z[1] * z[1] / I2 + z[2] * z[2] / I3);
    }
    // Scale of energy changes and errors: H itself (definite).
    double energy_scale(const Vec& z) const { return energy(z); }
    void exact(double t0, const Vec& z0, double t, Vec& out) const {
        const Vec3 s = rigid_body_exact({I1, I2, I3}, {z0[0], z0[1], z0[2]}, epsilon, t0, t);
        out[0] = s[0];
        out[1] = s[1];
        out[2] = s[2];
    }
};

} // namespace dampsym
