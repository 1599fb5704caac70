// Damped N-body problem with pair potentials (B Ex. 1.3, B(1.5)–(1.6), B(3.9); HLW(2.10), HLW(3.1);
// F §2.1.2), in conventions §1's convention:
//   q_i' = ∇_{p_i} T = p_i / m_i,   p_i' = −∇_{q_i} V(q) − 2γ p_i,   i = 1..N,
//   H = T + V,  T(p) = Σ_i |p_i|²/(2 m_i),  V(q) = Σ_{i<j} φ_ij(|q_i − q_j|)   (B(3.9), HLW(3.1)),
// with q_i, p_i ∈ R^d, d = 2 or 3. Pair potentials:
//   gravity        φ_ij(r) = −G m_i m_j / r                          (HLW(2.10), B §3.3)
//   Lennard-Jones  φ_ij(r) = 4ε[(σ/r)^12 − (σ/r)^6]                 (HLW(3.2); minimum at 2^{1/6}σ)
// Writing τ_ij = φ'_ij(r)/r (B Ex. 1.3), the force on body i is F_i = −Σ_{j≠i} τ_ij (q_i − q_j), so
// Σ_i F_i = 0 (Newton's third law) and Σ_i q_i × F_i = 0. Hence B Ex. 1.3: the total linear
// momentum Σ p_i and the total angular momentum Σ q_i × p_i are conformal invariants,
//   Σ p_i(t) = e^{−2γt} Σ p_i(0),   Σ q_i × p_i (t) = e^{−2γt} Σ q_i × p_i (0).
// (B writes Σ p_i × q_i, the negative; we use q × p.) They are exposed through the momentum hooks
// (has_momentum, space_dim, linear_momentum, angular_momentum), not as invariant_names.
// Force Jacobian, per pair with u = q_i − q_j, r = |u|:
//   K_ij = a(r) I + b(r) u uᵀ,  a = φ'(r)/r,  b = (φ''(r) − φ'(r)/r)/r²,
//   ∂F_i/∂q_i −= K_ij, ∂F_i/∂q_j += K_ij (and symmetrically for j); dense dN × dN.
//   gravity: a = G m_i m_j / r³, b = −3 G m_i m_j / r⁵;
//   LJ (s = σ/r): a = 24ε(s⁶ − 2s¹²)/r², b = ε(672 s¹² − 192 s⁶)/r⁴.
// State layout z = [q; p], q = (q_1, ..., q_N) body-major (q_1x, q_1y[, q_1z], q_2x, ...), the
// same for p; n() = dN. Constant damping γ (ConstantGamma): Γ(t) = γt.
//
// The reusable core (NBodySystem: masses, d, pair potential and all the sums) is in
// nbody_system.hpp; this header holds the CRTP base NBodyProblem<Derived> that turns it into a
// SeparableProblem with the momentum and energy hooks; kepler.hpp, outer_solar_system.hpp and
// argon.hpp use it. The problem `nbody` below exposes every parameter; from_params throws
// std::invalid_argument (message starting "nbody: ") when the parameters are inconsistent (array
// lengths, dim, potential, coincident bodies).
#pragma once

#include "core/problem.hpp"
#include "problems/nbody_system.hpp"

#include <array>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace dampsym {

// CRTP base for problems built on NBodySystem: Derived inherits `sys`, `gamma`, the initial state
// `q0`, `p0` and every form and hook; it provides id, title, param_specs, from_params and the
// has_exact / exact members if any.
template <class Derived>
struct NBodyProblem : SeparableProblem<Derived>, ConstantGamma<Derived> {
    static constexpr bool is_linear = false;
    static constexpr bool has_energy = true;
    static constexpr bool has_momentum = true;
    // V does not depend on t: energy balance dH/dt = −2γ p·∇T(p) = −2γ Σ|p_i|²/m_i.
    static constexpr bool autonomous_potential = true;
    // Σ p_i obeys e^{−2γt} (B Ex. 1.3): true for a closed N-body system.
    static constexpr bool linear_momentum_law = true;
    static constexpr std::array<std::string_view, 0> invariant_names{};
    static constexpr std::array<std::string_view, 0> invariant_scale_defs{};

    NBodySystem sys;
    double gamma = 0.0;
    std::vector<double> q0, p0;

    int n() const { return sys.n(); }
    Vec initial_state() const {
        const int k = n();
        Vec z(2 * k);
        for (int i = 0; i < k; ++i) {
            z[i] = q0[static_cast<std::size_t>(i)];
            z[k + i] = p0[static_cast<std::size_t>(i)];
        }
        return z;
    }

    template <class In, class Out>
    void grad_T(const In& p, Out& out) const {
        sys.grad_T(p, out);
    }
    template <class In, class Out>
    void hess_T(const In& p, Out& out) const {
        sys.hess_T(p, out);
    }
    template <class In, class Out>
    void force(double, const In& q, Out& out) const {
        sys.force(q, out);
    }
    template <class In, class Out>
    void force_jacobian(double, const In& q, Out& out) const {
        sys.force_jacobian(q, out);
    }

    void invariants(double, const Vec&, double*) const {}
    void invariant_scales(double, const Vec&, double*) const {}
    // H = T + V (B(3.9), HLW(2.10), HLW(3.1)).
    double energy(const Vec& z) const {
        const int k = n();
        return sys.kinetic(z.tail(k)) + sys.potential(z.head(k));
    }
    // Scale of energy changes and errors: T + |V| (H = T + V may cross zero).
    double energy_scale(const Vec& z) const {
        const int k = n();
        return sys.kinetic(z.tail(k)) + std::abs(sys.potential(z.head(k)));
    }
    double potential_energy(const Vec& z) const { return sys.potential(z.head(n())); }
    double kinetic_energy(const Vec& z) const { return sys.kinetic(z.tail(n())); }

    int space_dim() const { return sys.d; }
    void linear_momentum(const Vec& z, Vec& out) const { sys.linear_momentum(z.tail(n()), out); }
    void angular_momentum(const Vec& z, Vec& out) const {
        sys.angular_momentum(z.head(n()), z.tail(n()), out);
    }
    double linear_momentum_scale(const Vec& z) const {
        return sys.linear_momentum_scale(z.tail(n()));
    }
    double angular_momentum_scale(const Vec& z) const {
        return sys.angular_momentum_scale(z.head(n()), z.tail(n()));
    }
};

// The general problem `nbody`. Defaults (G = 1, gravity, d = 3, γ = 0.01): a hierarchical bound
// 3-body system: a central body of mass 1 at the origin, light bodies of mass 0.002 at distance 1
// (orbit inclined 0.4 rad about the x axis, 0.97 × circular speed) and 0.001 at distance ≈ 2.07
// (near-circular, orbit normal ∝ (0.3, −0.2, 1)), all drifting with velocity (0.03, −0.02, 0.01),
// so Σ p_i = (0.029435, −0.018442, 0.010948) and Σ q_i × p_i ≈ (4.0e−4, −8.9e−4, 3.1e−3) are
// nonzero in every component. Periods (≈ 6 and ≈ 19) are shorter than the damping time 1/(4γ) = 25,
// so under damping the orbits contract adiabatically like e^{−4γt} (L ∝ e^{−2γt}, r ∝ L²) keeping
// their ratio, without close encounters. Minimum pair distances over the certified solution with
// γ = 0.01: 0.12 for t ≤ 50, 0.016 for t ≤ 100 (body 1 from the centre; 0.017 between the light
// bodies, both near t = 100). No collision, but the inner period drops from ≈ 5.8 to ≈ 0.014 at
// t = 100, so a fixed step must resolve the final period. With γ = 0 the minimum is 0.89 (t ≤ 100).
struct NBody : NBodyProblem<NBody> {
    static constexpr std::string_view id = "nbody";
    static constexpr std::string_view title =
        "damped N-body, pair potential: gravity or Lennard-Jones (B Ex. 1.3, HLW(3.1))";
    static constexpr bool has_exact = false;

    static std::vector<double> default_masses() { return {1.0, 0.002, 0.001}; }
    static std::vector<double> default_q() {
        return {0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -0.45, 2.0, 0.3};
    }
    static std::vector<double> default_p() {
        return {0.03, -0.02, 0.01, 6e-5, 0.00175, 0.000776, -0.000625, -0.000192, 0.000172};
    }

    // Ranges: at most 1000 bodies; masses in [1e-30, 1e30], |q|, |p| entries ≤ 1e6, G, ε ≤ 1e6,
    // σ in [1e-6, 1e6] and pair distances ≥ 1e-6 (checked by validate) keep every force, energy and
    // Jacobian entry below 1e200; γ ≤ 1e3 keeps the certified reference non-stiff enough.
    static std::vector<ParamSpec> param_specs() {
        return {
            {"gamma", 0.01, Range::closed(0.0, 1e3), "damping γ"},
            {"G", 1.0, Range::closed(0.0, 1e6), "gravitational constant (potential gravity)"},
            choice_param("potential", 0, {"gravity", "lennard-jones"},
                         "pair potential: gravity −G m_i m_j/r, or Lennard-Jones HLW(3.2)"),
            {"lj_epsilon", 1.0, Range::closed(0.0, 1e6),
             "Lennard-Jones ε, HLW(3.2) (potential lennard-jones)"},
            {"lj_sigma", 1.0, Range::closed(1e-6, 1e6),
             "Lennard-Jones σ, HLW(3.2) (potential lennard-jones)"},
            integer_param("dim", 3, 2, 3, "space dimension d: 2 or 3"),
            array_param("masses", default_masses(), Range::closed(1e-30, 1e30),
                        "masses m_i (N of them, 2 <= N <= 1000)", 1000),
            array_param(
                "q", default_q(), Range::symmetric(1e6),
                "initial positions, d*N numbers, body-major (q_1x, q_1y[, q_1z], q_2x, ...)", 3000),
            array_param("p", default_p(), Range::symmetric(1e6),
                        "initial momenta p_i = m_i q_i', d*N numbers, body-major", 3000),
        };
    }

    // The defaults above (the same as from_params with every parameter at its default).
    NBody() {
        gamma = 0.01;
        sys.m = default_masses();
        q0 = default_q();
        p0 = default_p();
    }

    // Throws std::invalid_argument ("nbody: ...") on inconsistent parameters.
    static NBody from_params(const ParamMap& m) {
        NBody o;
        o.gamma = m.at("gamma");
        const double dim = m.at("dim"), pot = m.at("potential");
        if (dim != 2.0 && dim != 3.0)
            throw std::invalid_argument("nbody: dim must be 2 or 3, got " + std::to_string(dim));
        if (pot != 0.0 && pot != 1.0)
            throw std::invalid_argument(
                "nbody: potential must be 0 (gravity) or 1 (Lennard-Jones), got " +
                std::to_string(pot));
        o.sys.d = static_cast<int>(dim);
        o.sys.kind = pot == 0.0 ? PairPotential::gravity : PairPotential::lennard_jones;
        o.sys.G = m.at("G");
        o.sys.eps = m.at("lj_epsilon");
        o.sys.sigma = m.at("lj_sigma");
        o.sys.m = m.array("masses");
        o.q0 = m.array("q");
        o.p0 = m.array("p");
        o.sys.validate("nbody", o.q0, o.p0);
        return o;
    }
};

} // namespace dampsym
