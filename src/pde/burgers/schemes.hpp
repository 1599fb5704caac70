// Modified Burgers equation u_t + u u_x = −2γu on [−π, π), periodic (B (4.5), §5.2; docs/pde.md),
// in dampsym's convention (the Casimir C = Σ u decays as e^{−2γt}, B (5.14); B's γ is ours).
// Three schemes, each one step u^i → u^{i+1} on the M grid values:
//
//  (5.10) "CSV2" of B: the conformal splitting on the even–odd split (5.9) of the central
//         semi-discretisation u_j' = −(u_{j+1}² − u_{j−1}²)/(4Δx) − 2γu_j (B's ∂_x^± are one half
//         of the forward/backward differences over the coarse index, i.e. the central difference
//         δ_x(u²/2) on the full grid). M must be even. v = u at even j (0-based; B's u^1, u^3, …),
//         w = u at odd j. Explicit.
//  (5.12) "CIMP" of B, the MCS box scheme D_t^γ A_x u + ½ D_x (A_t^γ u)² = 0 (centred at
//         (n+½, i+½)). Implicit nonlinear: Newton on X = e^{γΔt}u^{i+1}; the Jacobian is cyclic
//         bidiagonal (row n: X_n, X_{n+1}), solved in O(M) by forward substitution with the
//         periodic closure X_M = X_0 (never dense). Kernel of A_x: for even M the alternating mode
//         is in the kernel of A_x; the Jacobian's determinant is then (1/2Δt)^M [Π(1 − ΔtW_n/Δx) −
//         Π(1 + ΔtW_{n+1}/Δx)] ≈ −(1/2Δt)^M (2Δt/Δx) Σ_n W_n with W = A_t^γ u: the step is solvable
//         only through the flux term, with a condition number growing like Δx/(Δt |Σ W|) — singular
//         for zero-mass data. We handle it by detecting it (the closure denominator 1 − Π(−a_n/b_n)
//         is checked against a relative threshold; below it the step fails with a message) and by
//         recommending odd M for (5.12) (A_x invertible: smallest symbol |cos(θ/2)| = sin(π/(2M))).
//         Odd and even M are both tested.
//  (4.18) NSFD: (u^{i+1} − u^i)/φ + u^i (u^{i+1}_n − u^{i+1}_{n−1})/Δx = −2γu^i,
//         φ = (1 − e^{−2γΔt})/(2γ) (φ = Δt at γ = 0). Linear in u^{i+1}: a cyclic lower bidiagonal
//         solve. First order; does not keep the Casimir law (B Theorem 5.2, negative control).
#pragma once

#include "pde/periodic_grid.hpp"

#include <string>

namespace dampsym::pde {

enum class BurgersScheme { csv_split, box, nsfd };

struct BurgersStats {
    int newton_iterations = 0; // total over the run (box only)
    int max_newton_iterations = 0;
};

class BurgersStepper {
public:
    BurgersStepper(const PeriodicGrid& g, double gamma, double dt, BurgersScheme s);
    // One step in place; false (with why()) if the box Newton iteration fails or is singular.
    bool step(Vec& u);
    const std::string& why() const { return why_; }
    const BurgersStats& stats() const { return stats_; }

private:
    bool step_split(Vec& u);
    bool step_box(Vec& u);
    bool step_nsfd(Vec& u);
    PeriodicGrid g_;
    double gamma_, dt_;
    BurgersScheme s_;
    std::string why_;
    BurgersStats stats_;
};

// Right-hand side of the central semi-discretisation (5.9): out_j = −(u_{j+1}² − u_{j−1}²)/(4Δx)
// − 2γu_j; and of the upwind one that NSFD tends to as Δt → 0: −u_j(u_j − u_{j−1})/Δx − 2γu_j.
void burgers_central_rhs(const PeriodicGrid& g, double gamma, const Vec& u, Vec& out);
void burgers_upwind_rhs(const PeriodicGrid& g, double gamma, const Vec& u, Vec& out);

// Solve the cyclic bidiagonal system a_n X_n + b_n X_{n+1} = r_n (X_M = X_0) in O(M):
// X_n = α_n + β_n X_0 by forward substitution, X_0 = α_M/(1 − β_M). Returns the relative size of
// the closure denominator |1 − β_M| / (1 + |β_M|) (0 when singular); x untouched if it is 0.
double solve_cyclic_bidiagonal(const Vec& a, const Vec& b, const Vec& r, Vec& x);

// Initial condition of B §5.2.1: the standard normal density.
Vec burgers_gaussian(const PeriodicGrid& g);

// B (4.5)'s own solution from that initial condition (its periodic extension), τ after the start,
// on the grid points: by characteristics, u = u0(ξ) e^{−2γτ} at x = ξ + u0(ξ) s(τ) with
// s(τ) = (1 − e^{−2γτ})/(2γ) (τ when γ = 0), ξ found by bisection (x − ξ is increasing in ξ
// until characteristics cross). false, out untouched, from the shock time on
// (burgers_gaussian_shock_time). Diagnostic pde-error, B Fig 5.4; docs/pde.md.
bool burgers_characteristic_solution(const PeriodicGrid& g, double gamma, double tau, Vec& out);
// The first τ at which characteristics of that solution cross: s(τ) = 1/max(−u0') = 1/φ(1)
// (u0 = φ, the normal density, steepest descent at x = 1); +inf when 2γ/φ(1) >= 1 (the damping
// stops the steepening: no shock ever).
double burgers_gaussian_shock_time(double gamma);

} // namespace dampsym::pde
