// Periodic spatial grid and the finite-difference operators of B (1.14) in space, for the damped
// PDEs of B ch. 4–5 (docs/pde.md).
//
// Grid: M points x_n = −L + nΔx, n = 0..M−1, Δx = 2L/M, with u^{n+M} = u^n. (B §5.2.1 writes
// x_1 = −L, …, x_M = L with M points and u^{n+M} = u^n; under periodicity x_1 and x_M are the same
// point, so the grid B describes has M − 1 distinct points. We use M distinct points and
// Δx = 2L/M; docs/pde.md "Conventions and issues in B ch. 4–5".)
//
// Operators (α = 0 forms of B (1.14), acting on a periodic sequence φ):
//   D_x φ^n  = (φ^{n+1} − φ^n)/Δx            forward difference
//   A_x φ^n  = (φ^{n+1} + φ^n)/2             forward average
//   T_x φ^n  = φ^{n−1}                       shift
//   δ_x φ^n  = (φ^{n+1} − φ^{n−1})/(2Δx)     central first difference
//   δ_x² φ^n = (φ^{n+1} − 2φ^n + φ^{n−1})/Δx² central second difference
// and the spectral derivative 𝒟_x (B §5.3.2, "MATLAB's FFT"): multiply the discrete Fourier
// coefficient of wavenumber k = 2πj/(2L) by ik, j ∈ (−M/2, M/2), with the Nyquist coefficient
// (j = M/2, even M) set to zero so that 𝒟_x of a real sequence is real. GSL mixed-radix FFT
// (gsl_fft_complex_*), any M.
//
// A_x on a periodic grid has a kernel when M is even: the alternating mode (−1)^n. Symbols (Fourier
// mode e^{iθn}, θ = 2πj/M): A_x → e^{iθ/2} cos(θ/2), D_x → 2i e^{iθ/2} sin(θ/2)/Δx, δ_x² →
// −4 sin²(θ/2)/Δx². cos(θ/2) = 0 exactly at θ = π, i.e. j = M/2, which exists only for even M.
#pragma once

#include "core/types.hpp"

#include <complex>
#include <vector>

namespace dampsym::pde {

struct PeriodicGrid {
    int M = 0;
    double L = 0.0;  // half length: the interval is [−L, L)
    double dx = 0.0; // 2L/M

    PeriodicGrid() = default;
    PeriodicGrid(int m, double half_length) : M(m), L(half_length), dx(2.0 * half_length / m) {}
    double x(int n) const { return -L + n * dx; }
    int wrap(int n) const { return ((n % M) + M) % M; }
};

// out = op(in); in and out must be distinct vectors of size M.
void forward_difference(const PeriodicGrid& g, const Vec& in, Vec& out); // D_x
void forward_average(const PeriodicGrid& g, const Vec& in, Vec& out);    // A_x
void shift(const PeriodicGrid& g, const Vec& in, Vec& out);              // T_x
void central_difference(const PeriodicGrid& g, const Vec& in, Vec& out); // δ_x
void second_difference(const PeriodicGrid& g, const Vec& in, Vec& out);  // δ_x²

// Spectral derivative 𝒟_x by FFT; real and complex sequences.
class SpectralDerivative {
public:
    explicit SpectralDerivative(const PeriodicGrid& g);
    ~SpectralDerivative();
    SpectralDerivative(const SpectralDerivative&) = delete;
    SpectralDerivative& operator=(const SpectralDerivative&) = delete;

    void apply(const Vec& in, Vec& out);
    void apply(const std::vector<std::complex<double>>& in, std::vector<std::complex<double>>& out);

    // Forward DFT (no normalisation) and inverse DFT (divided by M) of a complex sequence in place,
    // as interleaved (re, im) pairs of length 2M.
    void forward(std::vector<double>& data);
    void inverse(std::vector<double>& data);
    // Wavenumber of DFT index j: 2πj'/(2L), j' = j or j − M (j > M/2); 0 at the Nyquist index.
    double wavenumber(int j) const;

private:
    PeriodicGrid g_;
    void* wavetable_ = nullptr;
    void* workspace_ = nullptr;
    std::vector<double> buf_;
};

// Solve the symmetric cyclic tridiagonal system with constant coefficients
//   a x_{n−1} + b x_n + a x_{n+1} = r_n  (indices mod M, M ≥ 3)
// in O(M): Sherman–Morrison on the Thomas algorithm. The matrix has eigenvalues b + 2a cos θ_j,
// θ_j = 2πj/M; the caller guarantees that none vanishes (|b| > 2|a| suffices; on the alternating
// mode, θ = π, the eigenvalue is b − 2a). x may alias r.
void solve_cyclic_tridiagonal(double a, double b, const Vec& r, Vec& x);

// Solve the cyclic tridiagonal system with variable coefficients
//   lo_n x_{n−1} + di_n x_n + up_n x_{n+1} = r_n  (indices mod M, M ≥ 3)
// in O(M) (Sherman–Morrison on the Thomas algorithm, no pivoting: the caller's matrix must be
// diagonally dominant enough for Thomas to be stable). Returns false if a pivot vanishes.
bool solve_cyclic_tridiagonal(const Vec& lo, const Vec& di, const Vec& up, const Vec& r, Vec& x);

} // namespace dampsym::pde
