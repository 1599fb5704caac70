// Modified Burgers equation u_t + u u_x = −2γu on [−π, π), periodic (B (4.5), §5.2), as an
// ordinary dampsym problem: the central semi-discretisation of B (5.9) on M grid points,
//   u_j' = −(u_{j+1}² − u_{j−1}²)/(4Δx) − 2γ u_j          (δ_x(u²/2), B (1.14)),
// which is (5.9) written on the full grid (B's ∂_x^± are one half of the forward/backward
// differences over the coarse even/odd index, i.e. δ_x on the full grid; docs/pde.md).
// It is B's conformal Poisson system z' = D∇H(z) − 2γz with the constant skew structure matrix D
// and H = −Σ u³/6, given here in dampsym's conformal form (docs/conventions.md §1)
//   z' = N(z) − γ_c z,   N(u)_j = −(u_{j+1}² − u_{j−1}²)/(4Δx),   γ_c = 2γ,
// so Γ(t) = 2γt: B's γ of (4.5) is the parameter `gamma`, the problem's damping function is 2γ
// (a first-order system damped as a whole, like B's rigid body (1.7); docs/pde.md "Damping
// factors"). Invariant: the Casimir C = Δx Σ u (B (5.13)–(5.14)), conserved by N (Σ_j N_j
// telescopes) and decaying as e^{−2γt} = e^{−Γ(t)} under the damped flow, i.e. rate factor ½ of
// dampsym's e^{−2Γ} law (core/problem.hpp invariant_rate_factor). Its residual is B's (5.15) to
// first order (Theorem 5.2). Scale Δx Σ |u|. D is singular (C is its Casimir), so the semi-discrete
// map is not canonical and E_n (docs/conventions.md §5) does not apply. Initial state: the standard
// normal density (B §5.2.1). No closed-form solution: cases use the certified reference. B's own
// schemes (5.10), (5.12), (4.18) are src/pde/burgers/schemes.hpp (unit tests); here any dampsym
// method steps the semi-discrete system (cimp = conformal implicit midpoint in time, B (2.11)).
// Background and conventions: docs/pde.md.
//
// Two more semi-discretisations, the ones B's fully discrete (5.12) and (4.18) tend to as Δt → 0,
// so that those schemes have a reference of their own semi-discrete system (time order, B §5.2):
//  - `burgers-box`: A_x(u' + 2γu) + D_x(u²/2) = 0 (the box scheme (5.12) with D_t^γ → ∂_t + 2γ,
//    A_t^γ → 1), i.e. N = −A_x⁻¹ D_x(u²/2) (B (1.14)'s forward A_x, D_x), one O(M) cyclic
//    bidiagonal solve. A_x is singular for even M (alternating mode, docs/pde.md), so M must be
//    odd. Σ_n N_n = Σ_n (A_x N)_n = −Σ_n D_x(u²/2)_n = 0: the Casimir is conserved by N.
//  - `burgers-upwind`: N_j = −u_j (u_j − u_{j−1})/Δx (NSFD (4.18) as Δt → 0). Not conservative:
//    Σ_j u_j (u_j − u_{j−1}) = ½ Σ_j (u_j − u_{j−1})² ≥ 0, so the Casimir law is not a law of this
//    flow either; the problem keeps the `casimir` invariant so that the residual (5.15) of NSFD
//    can be measured as B's negative control of Theorem 5.2.
// B's schemes are the kernels of src/pde/burgers/methods.hpp, each applicable to its own one.
#pragma once

#include "core/problem.hpp"
#include "pde/burgers/schemes.hpp"

#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string_view>

namespace dampsym {

// The semi-discretisation of u_t + u u_x = −2γu a Burgers problem steps (see the header comment).
enum class BurgersSpace { central, box, upwind };

template <BurgersSpace S>
struct BurgersSemi : ConformalForm<BurgersSemi<S>> {
    static constexpr BurgersSpace pde_space = S;
    static constexpr std::string_view id = S == BurgersSpace::central ? "burgers"
                                           : S == BurgersSpace::box   ? "burgers-box"
                                                                      : "burgers-upwind";
    static constexpr std::string_view title =
        S == BurgersSpace::central
            ? "modified Burgers u_t + u u_x = -2 gamma u, periodic, central semi-discrete (B 4.5, "
              "5.9)"
        : S == BurgersSpace::box
            ? "modified Burgers, box semi-discretisation A_x(u_t + 2 gamma u) + D_x(u^2/2) = 0 "
              "(limit of B 5.12), odd M"
            : "modified Burgers, upwind semi-discretisation u_t = -u (u_j - u_{j-1})/dx - 2 gamma "
              "u (limit of NSFD, B 4.18)";
    static constexpr bool has_separable = false;
    static constexpr bool has_conformal = true;
    static constexpr bool is_canonical = false; // structure matrix D of (5.9) is singular
    static constexpr bool constant_gamma = true;
    static constexpr bool is_linear = false;
    static constexpr bool has_exact = false;
    static constexpr bool has_energy = false;
    static constexpr std::array<std::string_view, 1> invariant_names{"casimir"};
    static constexpr std::array<std::string_view, 1> invariant_scale_defs{"dx sum_n |u_n|"};
    // C decays as e^{-Γ} = e^{-2γt}: rate factor ½ (core/problem.hpp).
    static constexpr std::array<double, 1> invariant_rate_factors{0.5};

    pde::PeriodicGrid grid{S == BurgersSpace::box ? 65 : 64, std::numbers::pi};
    double gamma = 0.1;

    // Ranges: 2 ≤ M ≤ 8192 (dense Jacobians of the implicit kernels are M×M; burgers-box: odd
    // 1 ≤ M ≤ 8191, so that both edges are valid and a fraction is reported as not whole); 0 ≤ γ
    // ≤ 1.
    static std::vector<ParamSpec> param_specs() {
        return {
            integer_param("M", S == BurgersSpace::box ? 65 : 64, S == BurgersSpace::box ? 1 : 2,
                          8191 + (S == BurgersSpace::box ? 0 : 1),
                          S == BurgersSpace::box
                              ? "grid points on [-pi, pi) (dx = 2 pi / M), odd: A_x invertible"
                              : "grid points on [-pi, pi) (dx = 2 pi / M)"),
            {"gamma", 0.1, Range::closed(0.0, 1.0), "damping γ of B (4.5): u_t + u u_x = -2γu"}};
    }
    static BurgersSemi from_params(const ParamMap& m) {
        BurgersSemi p;
        const double M = m.at("M");
        if (M != std::floor(M)) throw std::invalid_argument("M must be a whole number");
        if (S == BurgersSpace::box && static_cast<long>(M) % 2 == 0)
            throw std::invalid_argument(
                "M must be odd for burgers-box (A_x is singular on the alternating mode for even "
                "M, docs/pde.md)");
        p.grid = pde::PeriodicGrid(static_cast<int>(M), std::numbers::pi);
        p.gamma = m.at("gamma");
        return p;
    }

    int dim() const { return grid.M; }
    Vec initial_state() const { return pde::burgers_gaussian(grid); }
    // B (4.5)'s own solution on this grid at t (started at t0), before the shock (diagnostic
    // pde-error, B Fig 5.4): the error of a scheme against it holds its space error too.
    bool pde_solution(double t0, double t, Vec& out) const {
        return pde::burgers_characteristic_solution(grid, gamma, t - t0, out);
    }
    double gamma_at(double) const { return 2.0 * gamma; }
    // B's structure matrix D of (5.9) (the central space only): z' = D∇H − 2γz with
    // D_{j,j+1} = 1, D_{j,j−1} = −1 and ∇H_j = −u_j²/(4Δx), so that (D∇H)_j is the central
    // difference −(u_{j+1}² − u_{j−1}²)/(4Δx). Singular (its kernel holds the Casimir gradient 1
    // and, M even, the alternating vector). The E_n law is ΨDΨᵀ = e^{−2ΔΓ}D (docs/pde.md).
    void structure_matrix(Mat& D) const requires(S == BurgersSpace::central) {
        const int M = grid.M;
        D = Mat::Zero(M, M);
        for (int j = 0; j < M; ++j) {
            D(j, grid.wrap(j + 1)) += 1.0;
            D(j, grid.wrap(j - 1)) -= 1.0;
        }
    }
    double Gamma(double t) const { return 2.0 * gamma * t; }
    double dGamma(double, double h) const { return 2.0 * gamma * h; }

    void N(double, const Vec& z, Vec& out) const {
        const int M = grid.M;
        if constexpr (S == BurgersSpace::central) {
            const double s = 1.0 / (4.0 * grid.dx);
            for (int j = 0; j < M; ++j) {
                const double l = z[j == 0 ? M - 1 : j - 1], r = z[j + 1 == M ? 0 : j + 1];
                out[j] = -(r * r - l * l) * s;
            }
        } else if constexpr (S == BurgersSpace::box) {
            // (N_n + N_{n+1})/2 = −(u_{n+1}² − u_n²)/(2Δx)
            Vec r(M), x;
            for (int n = 0; n < M; ++n) {
                const double un = z[n], um = z[n + 1 == M ? 0 : n + 1];
                r[n] = -(um * um - un * un) / (2.0 * grid.dx);
            }
            solve_box(r, x);
            out = x;
        } else {
            for (int j = 0; j < M; ++j)
                out[j] = -z[j] * (z[j] - z[j == 0 ? M - 1 : j - 1]) / grid.dx;
        }
    }
    void N_jacobian(double, const Vec& z, Mat& J) const {
        const int M = grid.M;
        J.setZero();
        if constexpr (S == BurgersSpace::central) {
            const double s = 1.0 / (2.0 * grid.dx);
            for (int j = 0; j < M; ++j) {
                const int jl = j == 0 ? M - 1 : j - 1, jr = j + 1 == M ? 0 : j + 1;
                J(j, jr) -= z[jr] * s;
                J(j, jl) += z[jl] * s;
            }
        } else if constexpr (S == BurgersSpace::box) {
            // J = −A_x⁻¹ D_x diag(u): column k of D_x diag(u) is u_k/Δx at row k−1, −u_k/Δx at k.
            Vec r(M), x;
            for (int k = 0; k < M; ++k) {
                r.setZero();
                r[k == 0 ? M - 1 : k - 1] = -z[k] / grid.dx;
                r[k] = z[k] / grid.dx;
                solve_box(r, x);
                J.col(k) = x;
            }
        } else {
            for (int j = 0; j < M; ++j) {
                const int jl = j == 0 ? M - 1 : j - 1;
                J(j, j) -= (2.0 * z[j] - z[jl]) / grid.dx;
                J(j, jl) += z[j] / grid.dx;
            }
        }
    }

    void invariants(double, const Vec& z, double* out) const { out[0] = grid.dx * z.sum(); }
    void invariant_scales(double, const Vec& z, double* out) const {
        out[0] = grid.dx * z.cwiseAbs().sum();
    }

private:
    // A_x x = r, (x_n + x_{n+1})/2 = r_n, periodic; odd M (closure denominator 2).
    void solve_box(const Vec& r, Vec& x) const {
        const Vec half = Vec::Constant(grid.M, 0.5);
        pde::solve_cyclic_bidiagonal(half, half, r, x);
    }
};

using Burgers = BurgersSemi<BurgersSpace::central>;
using BurgersBox = BurgersSemi<BurgersSpace::box>;
using BurgersUpwind = BurgersSemi<BurgersSpace::upwind>;

} // namespace dampsym
