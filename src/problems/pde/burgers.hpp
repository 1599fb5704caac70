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
// schemes (5.10), (5.12), (4.18) are src/pde/burgers.hpp (unit tests); here any dampsym method
// steps the semi-discrete system (cimp = conformal implicit midpoint in time, B (2.11)). Background
// and conventions: docs/pde.md.
#pragma once

#include "core/problem.hpp"
#include "pde/burgers.hpp"

#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string_view>

namespace dampsym {

struct Burgers {
    static constexpr std::string_view id = "burgers";
    static constexpr std::string_view title =
        "modified Burgers u_t + u u_x = -2 gamma u, periodic, central semi-discrete (B 4.5, 5.9)";
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

    pde::PeriodicGrid grid{64, std::numbers::pi};
    double gamma = 0.1;

    // Ranges: 2 ≤ M ≤ 8192 (dense Jacobians of the implicit kernels are M×M); 0 ≤ γ ≤ 1.
    static std::vector<ParamSpec> param_specs() {
        return {
            integer_param("M", 64, 2, 8192, "grid points on [-pi, pi) (dx = 2 pi / M)"),
            {"gamma", 0.1, Range::closed(0.0, 1.0), "damping γ of B (4.5): u_t + u u_x = -2γu"}};
    }
    static Burgers from_params(const ParamMap& m) {
        Burgers p;
        const double M = m.at("M");
        if (M != std::floor(M)) throw std::invalid_argument("M must be a whole number");
        p.grid = pde::PeriodicGrid(static_cast<int>(M), std::numbers::pi);
        p.gamma = m.at("gamma");
        return p;
    }

    int dim() const { return grid.M; }
    Vec initial_state() const { return pde::burgers_gaussian(grid); }
    double gamma_at(double) const { return 2.0 * gamma; }
    double Gamma(double t) const { return 2.0 * gamma * t; }
    double dGamma(double, double h) const { return 2.0 * gamma * h; }

    void N(double, const Vec& z, Vec& out) const {
        const int M = grid.M;
        const double s = 1.0 / (4.0 * grid.dx);
        for (int j = 0; j < M; ++j) {
            const double l = z[j == 0 ? M - 1 : j - 1], r = z[j + 1 == M ? 0 : j + 1];
            out[j] = -(r * r - l * l) * s;
        }
    }
    void N_jacobian(double, const Vec& z, Mat& J) const {
        const int M = grid.M;
        const double s = 1.0 / (2.0 * grid.dx);
        J.setZero();
        for (int j = 0; j < M; ++j) {
            const int jl = j == 0 ? M - 1 : j - 1, jr = j + 1 == M ? 0 : j + 1;
            J(j, jr) -= z[jr] * s;
            J(j, jl) += z[jl] * s;
        }
    }
    void rhs(double t, const Vec& z, Vec& out) const {
        N(t, z, out);
        out -= gamma_at(t) * z;
    }
    void rhs_jacobian(double t, const Vec& z, Mat& J) const {
        N_jacobian(t, z, J);
        J.diagonal().array() -= gamma_at(t);
    }

    void invariants(double, const Vec& z, double* out) const { out[0] = grid.dx * z.sum(); }
    void invariant_scales(double, const Vec& z, double* out) const {
        out[0] = grid.dx * z.cwiseAbs().sum();
    }
};

} // namespace dampsym
