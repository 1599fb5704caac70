// Linear Schrödinger, damped NLS and damped driven NLS (B (4.7), §5.3; docs/pde.md):
//   iψ_t + ψ_xx + V'(|ψ|²)ψ + 2iγψ = F(t),  V(η) = λη (linear) or ½λη² (cubic), λ = 2 in B,
//   F(t) = Γ e^{i(ω₀t + α)} (driven) or 0, periodic on [−L, L).
// Invariants (B (5.16)–(5.17), (5.29)), with the spectral derivative 𝒟_x:
//   I₁ = Im Δx Σ ψ̄ 𝒟_xψ,  I₂ = Δx Σ |ψ|²,  I₃ = Δx Σ (−|𝒟_xψ|² + V(|ψ|²)),
// which decay as e^{−4γt} (I₂ for damped NLS, all three for linear Schrödinger, F = 0): the rate
// factor is 4γ, twice dampsym's e^{−2Γ} (docs/conventions.md), because they are quadratic in ψ
// whose amplitude decays as e^{−2γt}. Residual R_k = ln(I_k^{i+1}/I_k^i) + 4γΔt (B (5.29)).
//
// Schemes (X = e^{γΔt}ψ^{i+1}, Y = e^{−γΔt}ψ^i, D_t^γψ = (X − Y)/Δt, A_t^γψ = Φ = (X + Y)/2):
//   IF  (4.15): i D_t^γψ + A_t^γ δ_x²ψ + V'(|A_t^γψ|²) A_t^γψ = F(A_t t)
//   ETD (5.27): the same with i D_t^γψ multiplied by γΔt / sinh(γΔt)
//   IMP (5.28): i D_tψ + A_t δ_x²ψ + V'(|A_tψ|²) A_tψ + 2iγ A_tψ = F(A_t t)   (γ = 0 operators)
// Each step solves for Φ: (2iκ/Δt + δ_x² [+ 2iγ for IMP]) Φ = 2iκ Y'/Δt − V'(|Φ|²)Φ + F by a
// fixed-point iteration on the nonlinear term, the linear operator inverted exactly by FFT (it
// is diagonal in Fourier: δ_x² → −4 sin²(θ/2)/Δx²), O(M log M) per iteration.
#pragma once

#include "pde/periodic_grid.hpp"

#include <complex>
#include <string>
#include <vector>

namespace dampsym::pde {

using CVec = std::vector<std::complex<double>>;

enum class NLSScheme { integrating_factor, etd, implicit_midpoint };

struct NLSParams {
    double gamma = 0.0;
    double lambda = 2.0;
    bool cubic = true;  // V = ½λη² (damped NLS); false: V = λη (linear Schrödinger)
    double drive = 0.0; // Γ of F(t) = Γ e^{i(ω₀t + α)}
    double omega0 = 1.0, alpha = 0.0;
};

class NLSStepper {
public:
    NLSStepper(const PeriodicGrid& g, const NLSParams& p, double dt, NLSScheme s);
    // One step from time t, in place; false (why()) if the fixed-point iteration fails.
    bool step(double t, CVec& psi);
    const std::string& why() const { return why_; }
    int max_iterations() const { return max_its_; }
    int last_iterations() const { return last_its_; } // of the last step
    const PeriodicGrid& grid() const { return g_; }

private:
    PeriodicGrid g_;
    NLSParams p_;
    double dt_;
    NLSScheme s_;
    SpectralDerivative fft_;
    std::vector<double> buf_;
    std::vector<std::complex<double>> inv_sym_; // 1 / the linear operator's Fourier symbol
    CVec Y_, Phi_;                              // the step's Y and Φ
    double ey_ = 1.0;                           // e^{−γΔt} (1 for IMP)
    std::complex<double> c2_;                   // 2iκ/Δt
    std::string why_;
    int max_its_ = 0, last_its_ = 0;
};

struct NLSInvariants {
    double I1, I2, I3;
};
NLSInvariants nls_invariants(const PeriodicGrid& g, const NLSParams& p, SpectralDerivative& D,
                             const CVec& psi);

// Plane waves of §5.3.2 generalised to wavenumber k (B's are k = 0): |ψ| is constant in x, so
//   linear:  ψ = A e^{i(kx − (k² − λ)t) − 2γt}
//   cubic:   ψ = A e^{ikx − ik²t − 2γt} exp(iλ|A|²(1 − e^{−4γt})/(4γ))  (limit λ|A|²t at γ = 0).
// With k_d² = 4 sin²(kΔx/2)/Δx² in place of k² they solve the semi-discrete system exactly.
CVec nls_plane_wave(const PeriodicGrid& g, const NLSParams& p, double A, int k, double t,
                    bool discrete_k);

} // namespace dampsym::pde
