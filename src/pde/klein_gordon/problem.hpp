// Damped Klein–Gordon u_tt = u_xx − c u − 2γ u_t on [−π, π), periodic (B (4.3), §5.1), as an
// ordinary dampsym problem: the semi-discretisation u' = v, v' = (δ_x² − c)u − 2γv on M grid points
// (B (5.2) with the central difference δ_x² of B (1.14)), a separable damped Hamiltonian system
// with q = u, p = v (dampsym's convention p' = F − 2γp; B's γ of (4.3) is our γ). B's schemes
// (5.3) and (5.4) are exactly the kernels csv1 and csv2 on this system (B (2.20), (2.21) with
// B's ODE γ = 2× ours). Invariant: the conformal momentum I = Δx Σ v δ_x u (B (5.7), §5.1.2), which
// decays as e^{−2γt} (B (5.8), Theorem 5.1). Initial state: the plane wave (5.1) at t = 0.
// Exact solution: of the semi-discrete system from any (t0, z0), mode by mode
// (src/pde/klein_gordon/schemes.hpp); the PDE solution (5.1) is separate (pde::kg_plane_wave),
// for space errors. Background and conventions: docs/pde.md.
//
// A second semi-discretisation, the one B's box scheme (5.5) tends to as Δt → 0, so that (5.5)
// (the method kg-box, src/pde/klein_gordon/methods.hpp) has the exact solution of its own
// semi-discrete system (time error alone), as burgers-box has for (5.12):
//  - `klein-gordon-box`: u' = v, v' = (A_c²)⁻¹D_c² u − cu − 2γv, odd M. (5.5) in y = e^{γt}u is
//    A_x²(D_t)²y = (D_x² + (γ² − c)A_x²)(A_t)²y; as Δt → 0, y'' = (A_x⁻²D_x² + γ² − c)y, i.e. the
//    damped system above with L = A_x⁻²D_x², which re-indexed by one is the symmetric circulant
//    (A_c²)⁻¹D_c² (A_c² = (1,2,1)/4, D_c² = δ_x²), symbol −(2/Δx)² tan²(θ/2). A_c² is singular on
//    the alternating mode of an even grid, so M must be odd. Still a separable damped Hamiltonian
//    system (L symmetric), and the momentum I = Δx Σ v δ_x u is still conformal: δ_x is skew and
//    commutes with L, so u·Lδ_x u = u·δ_x u = v·δ_x v = 0 and I' = −2γI.
#pragma once

#include "core/problem.hpp"
#include "pde/klein_gordon/schemes.hpp"

#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string_view>

namespace dampsym {

// The semi-discretisation of u_xx a Klein–Gordon problem steps (see the header comment).
enum class KGSpace { central, box };

template <KGSpace S>
struct KleinGordonSemi : SeparableProblem<KleinGordonSemi<S>>,
                         UnitMass,
                         ConstantGamma<KleinGordonSemi<S>> {
    static constexpr KGSpace pde_space = S;
    static constexpr bool box = S == KGSpace::box;
    static constexpr std::string_view id = box ? "klein-gordon-box" : "klein-gordon";
    static constexpr std::string_view title =
        box ? "damped Klein-Gordon, box semi-discretisation u_tt = A_c^-2 D_c^2 u - c u - 2 gamma "
              "u_t (limit of B 5.5), odd M"
            : "damped Klein-Gordon u_tt = u_xx - c u - 2 gamma u_t, periodic, semi-discrete (B "
              "4.3, 5.2)";
    // Linear, but is_linear selects the oscillator's stability diagnostics (the LinearOscillator
    // concept of core/problem_concepts.hpp: ω and γ of a single oscillator), which do not apply
    // here. Its parameters include whole numbers (M, K) that build the grid, so it keeps its own
    // param_specs/from_params rather than a ParamTable (core/param_table.hpp sets double members).
    static constexpr bool is_linear = false;
    static constexpr bool has_exact = true;
    static constexpr bool autonomous = true;
    static constexpr bool has_energy = false;
    static constexpr std::array<std::string_view, 1> invariant_names{"momentum"};
    static constexpr std::array<std::string_view, 1> invariant_scale_defs{
        "dx sum_n |v_n| |delta_x u_n|"};

    pde::PeriodicGrid grid{box ? 11 : 32, std::numbers::pi};
    double c = 1.0, gamma = 0.0;
    int K = 1;
    // 1: the exact solution is the PDE's (4.3) (from the trigonometric interpolant of the state;
    // B (5.1) for the plane wave), so the error holds the space error too (B Fig 5.1).
    bool exact_pde = false;

    // Ranges: 2 ≤ M ≤ 8192 (dense Jacobians of the implicit kernels are M×M; klein-gordon-box:
    // odd 3 ≤ M ≤ 8191, the cyclic solve of its operator needs M ≥ 3, default 11: its highest
    // frequency (2/Δx) cot(π/2M) grows like 2M²/π², 24 at M = 11 but 220 at M = 33, and the
    // default should not be stiff; cases choose M); c ≤ 100,
    // γ ≤ 1 so that K² + c > γ² (a real frequency W in (5.1)) holds at every single-parameter
    // edge with the others at their defaults; combinations violating it are rejected by
    // from_params. Any K (a wavenumber above M/2 aliases on the grid; the initial state and the
    // semi-discrete exact solution stay valid).
    static std::vector<ParamSpec> param_specs() {
        return {integer_param("M", box ? 11 : 32, box ? 3 : 2, box ? 8191 : 8192,
                              box ? "grid points on [-pi, pi) (dx = 2 pi / M), odd: A_c^2 "
                                    "invertible"
                                  : "grid points on [-pi, pi) (dx = 2 pi / M)"),
                {"c", 1.0, Range::closed(0.0, 100.0), "mass term c of u_tt = u_xx - c u - 2γu_t"},
                {"gamma", 0.0, Range::closed(0.0, 1.0), "damping γ (B (4.3): 2γ u_t)"},
                integer_param("K", 1, 0, 4096, "wavenumber K of the initial plane wave (5.1)"),
                integer_param("exact_pde", 0, 0, 1,
                              "exact solution: 0 of the semi-discrete system (time error), 1 of "
                              "the PDE (5.1) (time and space error, B Fig 5.1)")};
    }
    static KleinGordonSemi from_params(const ParamMap& m) {
        KleinGordonSemi p;
        const double M = m.at("M"), K = m.at("K");
        if (M != std::floor(M) || K != std::floor(K))
            throw std::invalid_argument("M and K must be whole numbers");
        if (box && static_cast<long>(M) % 2 == 0)
            throw std::invalid_argument("M must be odd for klein-gordon-box (A_c^2 is singular on "
                                        "the alternating mode for even M, docs/pde.md)");
        p.grid = pde::PeriodicGrid(static_cast<int>(M), std::numbers::pi);
        p.c = m.at("c");
        p.gamma = m.at("gamma");
        p.K = static_cast<int>(K);
        p.exact_pde = m.scalars.count("exact_pde") && m.at("exact_pde") != 0.0; // default 0
        if (!(p.K * p.K + p.c > p.gamma * p.gamma))
            throw std::invalid_argument("K^2 + c must exceed gamma^2 (real W in B (5.1))");
        return p;
    }

    int n() const { return grid.M; }
    // The field u = q on the grid (field-drift, B (5.6): d = ln max_x u + γt).
    int field_size() const { return n(); }
    double W() const { return pde::kg_frequency(double(K) * K, c, gamma); }
    Vec initial_state() const {
        Vec u, v, z(2 * grid.M);
        pde::kg_plane_wave(grid, gamma, K, W(), 0.0, u, v);
        z << u, v;
        return z;
    }

    // F(u) = δ_x² u − c u (klein-gordon), (A_c²)⁻¹D_c² u − c u (klein-gordon-box).
    template <class In, class Out>
    void force(double, const In& q, Out& out) const {
        const int M = grid.M;
        if constexpr (box) {
            Vec lu;
            pde::kg_box_space_operator(grid, Vec(q), lu);
            for (int i = 0; i < M; ++i) out[i] = lu[i] - c * q[i];
        } else {
            const double s = 1.0 / (grid.dx * grid.dx);
            for (int i = 0; i < M; ++i) {
                const double l = q[i == 0 ? M - 1 : i - 1], r = q[i + 1 == M ? 0 : i + 1];
                out[i] = (l - 2.0 * q[i] + r) * s - c * q[i];
            }
        }
    }
    template <class In, class Out>
    void force_jacobian(double, const In&, Out& out) const {
        const int M = grid.M;
        out.setZero();
        if constexpr (box) {
            // L is circulant: column k is column 0 (L applied to e_0) shifted down by k.
            Vec e0 = Vec::Zero(M), l0;
            e0[0] = 1.0;
            pde::kg_box_space_operator(grid, e0, l0);
            for (int k = 0; k < M; ++k)
                for (int i = 0; i < M; ++i) out(i, k) = l0[grid.wrap(i - k)];
            out.diagonal().array() -= c;
        } else {
            const double s = 1.0 / (grid.dx * grid.dx);
            for (int i = 0; i < M; ++i) {
                out(i, i) = -2.0 * s - c;
                out(i, i == 0 ? M - 1 : i - 1) += s;
                out(i, i + 1 == M ? 0 : i + 1) += s;
            }
        }
    }

    void invariants(double, const Vec& z, double* out) const {
        out[0] = pde::kg_momentum(grid, z.head(grid.M), z.tail(grid.M));
    }
    void invariant_scales(double, const Vec& z, double* out) const {
        out[0] = pde::kg_momentum_scale(grid, z.head(grid.M), z.tail(grid.M));
    }
    // Semi-discrete solution from (t0, z0) (constant coefficients: a shift); z(t0) = z0 exactly.
    void exact(double t0, const Vec& z0, double t, Vec& out) const {
        if (t == t0) {
            out = z0;
            return;
        }
        Vec u, v;
        pde::kg_semidiscrete_exact(grid, c, gamma, t0, z0.head(grid.M), z0.tail(grid.M), t, u, v,
                                   exact_pde ? pde::KGSymbol::pde
                                   : box     ? pde::KGSymbol::box
                                             : pde::KGSymbol::central);
        out.resize(2 * grid.M);
        out << u, v;
    }
    // has_energy = false; present for the generic code paths that name them.
    double energy(const Vec&) const { return 0.0; }
    double energy_scale(const Vec&) const { return 1.0; }
};

using KleinGordon = KleinGordonSemi<KGSpace::central>;
using KleinGordonBox = KleinGordonSemi<KGSpace::box>;

} // namespace dampsym
