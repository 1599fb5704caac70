// Damped Klein–Gordon equation u_tt = u_xx − c u − 2γ u_t on [−L, L), periodic (B (4.3), §5.1),
// in dampsym's convention (docs/conventions.md: p' = −∇V − 2γp): the semi-discretisation
//   u' = v,  v' = (δ_x² − c) u − 2γ v                                     (B (5.2) with δ_x²)
// is a separable damped Hamiltonian system with q = u, p = v, T = ½|v|², V = ½(|D_x u|² + c|u|²)Δx
// (up to the factor Δx, which does not change the flow), and B's γ of (4.3) is our γ. Its
// conformal invariant is the momentum I = Δx Σ_n v^n δ_x u^n (B (5.7) discretised as in §5.1.2),
// I(t) = e^{−2γt} I(0) (B (5.8)).
//
// Exact solutions:
//   PDE (B (5.1)):            u = e^{−γt} cos(Kx − Wt),     W² = K² + c − γ²
//   semi-discrete (any z0):   each discrete Fourier mode j is a damped oscillator
//                             q'' + 2γq' + ω_j² q = 0, ω_j² = c + 4 sin²(θ_j/2)/Δx², θ_j = 2πj/M;
//                             for the plane wave this is (5.1) with K² replaced by
//                             K_d² = 4 sin²(KΔx/2)/Δx².
//   box scheme (5.5):         u^{n,i} = e^{−γt_i} cos(K x_n − Ω t_i) with
//                             tan²(ΩΔt/2) (2/Δt)² = tan²(KΔx/2) (2/Δx)² + c − γ²
//                             (the scheme's own dispersion relation, docs/pde.md §KG).
#pragma once

#include "pde/periodic_grid.hpp"

namespace dampsym::pde {

struct KGParams {
    int M = 64;
    double L = 3.141592653589793; // π: B §5.1 uses [−π, π]
    double c = 1.0;
    double gamma = 0.0;
    int K = 1; // wavenumber of the plane wave (integer: periodic on [−π, π])
};

// W of (5.1) for wavenumber² k2: √(k2 + c − γ²) (requires k2 + c > γ²).
double kg_frequency(double k2, double c, double gamma);
// K_d² = 4 sin²(KΔx/2)/Δx².
double kg_discrete_k2(const PeriodicGrid& g, int K);
// Ω of the box scheme (5.5) for the plane wave of wavenumber K at step dt.
double kg_box_frequency(const PeriodicGrid& g, double c, double gamma, int K, double dt);

// Plane wave e^{−γt} cos(Kx − Wt) and its time derivative at the grid points (u, v).
void kg_plane_wave(const PeriodicGrid& g, double gamma, int K, double W, double t, Vec& u, Vec& v);

// The space operator a Klein–Gordon semi-discretisation puts in place of u_xx, by −(its symbol) k²
// on the Fourier mode j (θ = 2πj/M):
//   central  δ_x² (B (5.2), problem klein-gordon):           k² = 4 sin²(θ/2)/Δx²
//   box      (A_c²)⁻¹ D_c², the Δt → 0 limit of (5.5)         k² = 4 tan²(θ/2)/Δx²
//            (problem klein-gordon-box; odd M: A_c² = (1,2,1)/4 has the symbol cos²(θ/2), zero on
//            the alternating mode of an even grid)
//   pde      the PDE's own ∂_x² on the trigonometric interpolant: k² = min(j, M − j)² (L = π)
enum class KGSymbol { central, box, pde };
double kg_mode_k2(const PeriodicGrid& g, int j, KGSymbol s);

// out = (A_c²)⁻¹ D_c² u, A_c² = (1,2,1)/4, D_c² = δ_x² (schemes' "centred" pair below): one
// cyclic tridiagonal solve (A_c² is positive definite for odd M ≥ 3; the caller checks M).
void kg_box_space_operator(const PeriodicGrid& g, const Vec& u, Vec& out);

// Exact solution of the semi-discrete system u' = v, v' = Lu − cu − 2γv from (t0, u0, v0) at t,
// for any initial data: FFT, each mode j by the damped-oscillator solution with
// ω_j² = c + kg_mode_k2(j) (reference/oscillator_exact.hpp), inverse FFT. KGSymbol::pde gives
// the exact solution of the PDE (4.3) from the trigonometric interpolants of (u0, v0) (B (5.1) for
// the plane wave), sampled on the grid.
void kg_semidiscrete_exact(const PeriodicGrid& g, double c, double gamma, double t0, const Vec& u0,
                           const Vec& v0, double t, Vec& u, Vec& v,
                           KGSymbol symbol = KGSymbol::central);

// Momentum of the Störmer–Verlet-type schemes (5.3), (5.4) (B §5.1.2): I = Δx Σ v δ_x u, and its
// scale Δx Σ |v| |δ_x u| (docs/conventions.md "Law residuals and their scales").
double kg_momentum(const PeriodicGrid& g, const Vec& u, const Vec& v);
double kg_momentum_scale(const PeriodicGrid& g, const Vec& u, const Vec& v);

// The MCS box scheme (5.5) in B's u-form (§5.1.2),
//   (D_t^{γ/2})² A_x² u − D_x² (A_t^{γ/2})² u = (γ² − c) A_x² (A_t^{γ/2})² u,
// a two-level scheme in (u^i, u^{i+1}). Each step solves one symmetric cyclic tridiagonal system
// with constant coefficients (O(M), never dense): the forward operators A_x², D_x² are centred at
// n+1, and re-indexing the equations by one makes the matrix
//   e^{γΔt} [ (1/Δt² − (γ² − c)/4) A_c² − D_c²/4 ],  A_c² = (1,2,1)/4, D_c² = (1,−2,1)/Δx²,
// whose eigenvalues e^{γΔt}[cos²(θ/2)(1/Δt² − (γ² − c)/4) + sin²(θ/2)/Δx²] vanish for no θ when
// Δt² (γ² − c) < 4. The kernel of A_x (alternating mode, even M) is therefore harmless here: D_x²
// does not vanish on it, and the alternating mode has eigenvalue e^{γΔt}/Δx² > 0.
class KGBox {
public:
    KGBox(const PeriodicGrid& g, double c, double gamma, double dt);
    // State (u^i, u^{i+1}); step() advances to (u^{i+1}, u^{i+2}).
    void set_state(const Vec& u_prev, const Vec& u_curr);
    // Start from u(0) = u0, u_t(0) = v0: u^1 from the scheme's own equation at i = 0 with the
    // central value u^{−1} (in y = e^{γt}u: y^{−1} = y^1 − 2Δt y'(0)), one cyclic solve; local
    // error O(Δt³) with the scheme's own spatial operator. (A Taylor start with δ_x² instead
    // leaves an O(Δt²Δx²) start error that the two-level scheme turns into O(ΔtΔx²): measured
    // time order 1.4 at M = 32.)
    void start(const Vec& u0, const Vec& v0);
    void step();
    const Vec& u_prev() const { return u0_; }
    const Vec& u_curr() const { return u1_; }
    // Conformal momentum of (5.5) (B §5.1.2): P^i = Δx Σ D_t^{γ/2} A_x² u · δ_x A_t^{γ/2} A_x² u,
    // from (u^i, u^{i+1}); and its scale Δx Σ |D_t A_x² u| |δ_x A_t A_x² u|.
    double momentum() const;
    double momentum_scale() const;

private:
    PeriodicGrid g_;
    double c_, gamma_, dt_, E2_;
    double a_, b_; // cyclic tridiagonal coefficients of the step matrix (divided by e^{γΔt})
    Vec u0_, u1_, rhs_, tmp_, wa_, wd_;
    // Factorisation of the constant step matrix (schemes.cpp): pivots, Thomas coefficients,
    // the Sherman–Morrison vector and denominator.
    Vec piv_, cf_, zf_;
    double denom_ = 1.0;
    void factorise();
    void solve_factorised(const Vec& r, Vec& x) const;
};

} // namespace dampsym::pde
