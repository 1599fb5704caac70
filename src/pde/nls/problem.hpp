// Linear Schrödinger and damped cubic NLS  iψ_t + ψ_xx + V'(|ψ|²)ψ + 2iγψ = 0  on [−L, L),
// periodic (B (4.7) with F = 0, (5.19), §5.3), V(η) = λη (problem "schrodinger") or ½λη²
// (problem "nls"), as ordinary dampsym problems: the semi-discretisation with the central δ_x² of
// B (1.14) (the spatial operator of B's IF (4.15), ETD (5.27), IMP (5.28)), in real form ψ = q +
// ip:
//   q' = −(δ_x² p + V'(|ψ|²) p) − 2γq,   p' = δ_x² q + V'(|ψ|²) q − 2γp,
// i.e. z' = −J∇H(z) − 2γz with H = ½Σ(q δ_x² q + p δ_x² p) + ½ΣV(q² + p²), canonical (the sign of
// J does not change ΨᵀJ⁻¹Ψ). Both components are damped, so in dampsym's conformal form
// (docs/conventions.md §1)  z' = N(z) − γ_c z  the damping function is γ_c = 2γ (B's γ is the
// parameter `gamma`): Γ(t) = 2γt, and the quadratic invariants decay as e^{−2Γ} = e^{−4γt},
// which is B's "e^{4γt} I_k preserved" (§5.3.1 (ii)–(iii), R_k of (5.29) with 4γΔt).
// With this γ_c, dampsym's cimp is exactly B's IF (4.15) (X = e^{γ_cΔt/2}ψ^{i+1} = e^{γΔt}ψ^{i+1}),
// etdrk2 is exactly B's ETD (5.27) (the factor γΔt/sinh(γΔt) on D_t^γ), and implicit-midpoint on
// the plain form is B's IMP (5.28) (docs/pde.md).
// Invariants with the spectral derivative 𝒟_x (B (5.29)), evaluated by Parseval from one DFT
// (ψ̂_j, wavenumber k_j, Nyquist k = 0):
//   momentum I₁ = Im Δx Σ ψ̄ 𝒟_xψ = (Δx/M) Σ k_j |ψ̂_j|²,     scale (Δx/M) Σ |k_j| |ψ̂_j|²
//   mass     I₂ = Δx Σ |ψ|²,                                   scale I₂ (definite)
//   energy   I₃ = Δx Σ (−|𝒟_xψ|² + λ|ψ|²)  (linear only),   scale (Δx/M) Σ (k_j² + |λ|) |ψ̂_j|²
// Linear Schrödinger: all three are quadratic forms that commute with the generator (Fourier
// multipliers), so the semi-discrete flow keeps e^{4γt}I_k, k = 1..3 (B §5.3.1 (iii)); cubic NLS:
// I₂ exactly (B (ii)); I₁ is listed too, its law the PDE's, which the semi-discrete cubic flow
// keeps only up to the aliasing of |ψ|²ψ (B Fig 5.9's R₁); I₃ of the cubic NLS is not listed.
// Initial states (parameter `initial`): the plane wave A e^{ikx} (B §5.3.2.1–2 with a wavenumber,
// docs/pde.md item 8), or B's collision profile e^{5ix} sech(x+1) + 1.5 e^{−5ix} sech(1.5(x−5))
// (Fig 5.9, as printed). Exact solution: linear Schrödinger, mode by mode from any (t0, z0),
// ψ̂_j(t) = ψ̂_j(t0) e^{(i(λ − κ_j²) − 2γ)(t − t0)}, κ_j² = 4 sin²(θ_j/2)/Δx²; the cubic NLS has
// none from an arbitrary state (certified reference). Library schemes: src/pde/nls/schemes.hpp.
//
// Damped driven NLS (problem "nls-driven", B §5.3.2.3, Fig 5.10): the cubic NLS with the forcing
// F(t) = Γ e^{i(ω₀t + α)} of (4.7), iψ_t = −ψ_xx − V'ψ − 2iγψ + F, so ψ_t gains −iF:
//   q' += Γ sin(ω₀t + α),   p' += −Γ cos(ω₀t + α).
// A forcing constant in z is a Hamiltonian vector field (of the linear Hamiltonian −zᵀJ⁻¹f(t)),
// so the step maps stay conformal symplectic, but no invariant follows a law (none is listed).
// Initial state "sech": A sech(Ax) (B: ψ(x, 0) = 3 sech 3x, A = 3). probe(z) = |ψ| at the grid
// point nearest x = 0, the amplitude B's Fig 5.10 plots (the `attractor` diagnostic).
#pragma once

#include "core/problem.hpp"
#include "pde/nls/schemes.hpp"
#include "pde/periodic_grid.hpp"

#include <algorithm>

#include <array>
#include <cmath>
#include <complex>
#include <numbers>
#include <stdexcept>
#include <string_view>
#include <vector>

namespace dampsym {

namespace nls_detail {
inline constexpr std::array<std::string_view, 3> linear_names{"momentum", "mass", "energy"};
inline constexpr std::array<std::string_view, 3> linear_scales{
    "(dx/M) sum_j |k_j| |psi_hat_j|^2", "|I| (definite)",
    "(dx/M) sum_j (k_j^2 + |lambda|) |psi_hat_j|^2"};
// The cubic NLS's momentum: the PDE keeps e^{4γt}I₁, the semi-discrete flow only up to the
// aliasing of |ψ|²ψ on the grid (B Fig 5.9's R₁: round-off for a resolved profile, larger where it
// is steep, near a collision).
inline constexpr std::array<std::string_view, 2> cubic_names{"momentum", "mass"};
inline constexpr std::array<std::string_view, 2> cubic_scales{"(dx/M) sum_j |k_j| |psi_hat_j|^2",
                                                              "|I| (definite)"};
} // namespace nls_detail

// The semi-discretisation of ψ_xx an NLS problem steps: B (1.14)'s central δ_x² (see the header
// comment), the one B's IF, ETD and IMP are written on.
enum class NLSSpace { central };

template <bool Cubic, bool Driven = false>
struct SchrodingerProblem : ConformalForm<SchrodingerProblem<Cubic, Driven>> {
    static_assert(Cubic || !Driven, "the driven problem is the cubic NLS");
    static constexpr std::string_view id = Driven ? "nls-driven" : Cubic ? "nls" : "schrodinger";
    static constexpr std::string_view title =
        Driven  ? "damped driven cubic NLS i psi_t + psi_xx + lambda |psi|^2 psi + 2i gamma psi = "
                  "Gamma e^{i(omega0 t + alpha)}, periodic, semi-discrete (B 4.7, 5.3.2.3)"
        : Cubic ? "damped cubic NLS i psi_t + psi_xx + lambda |psi|^2 psi + 2i gamma psi = 0, "
                  "periodic, semi-discrete (B 4.7, 5.3)"
                : "damped linear Schroedinger i psi_t + psi_xx + lambda psi + 2i gamma psi = 0, "
                  "periodic, semi-discrete (B 4.7, 5.19)";
    static constexpr bool has_separable = false;
    static constexpr bool has_conformal = true;
    static constexpr bool is_canonical = true;
    static constexpr bool constant_gamma = true;
    static constexpr bool is_linear = false; // not the oscillator's stability diagnostics
    static constexpr bool has_exact = !Cubic;
    static constexpr bool autonomous = !Driven;
    static constexpr bool has_energy = false;
    // B's own schemes IF (4.15), ETD (5.27), IMP (5.28) step it (src/pde/nls/methods.hpp).
    static constexpr NLSSpace pde_space = NLSSpace::central;
    static constexpr auto invariant_names = [] {
        if constexpr (Driven)
            return std::array<std::string_view, 0>{};
        else if constexpr (Cubic)
            return nls_detail::cubic_names;
        else
            return nls_detail::linear_names;
    }();
    static constexpr auto invariant_scale_defs = [] {
        if constexpr (Driven)
            return std::array<std::string_view, 0>{};
        else if constexpr (Cubic)
            return nls_detail::cubic_scales;
        else
            return nls_detail::linear_scales;
    }();

    pde::PeriodicGrid grid{8, std::numbers::pi};
    double gamma = 0.05, lambda = 2.0, A = 1.0;
    int k = 1, initial = 0; // 0 plane wave, 1 collision profile, 2 A sech(Ax)
    double drive = 0.0, omega0 = 1.0, alpha = 0.0; // F(t) = Γ e^{i(ω₀t + α)} (nls-driven)

    static std::vector<ParamSpec> param_specs() {
        // Default M = 8: cases set their own M; a small default keeps the highest frequency
        // 4/Δx² + λ of the semi-discrete flow moderate (tests/test_exact_solutions.cpp
        // differentiates the exact solution of random states numerically at step 2⁻⁸).
        std::vector<ParamSpec> s{
            integer_param("M", Driven ? 64 : 8, 2, 4096, "grid points on [-L, L) (dx = 2L / M)"),
            {"L", std::numbers::pi, Range::closed(0.1, 1000.0), "half length L of [-L, L)"},
            {"gamma", Driven ? 0.2 : 0.05, Range::closed(0.0, 1.0), "damping γ of B (4.7): + 2iγψ"},
            {"lambda", 2.0, Range::symmetric(100.0), "λ of V (B: 2)"},
            choice_param("initial", Driven ? 2 : 0, {"plane-wave", "collision", "sech"},
                         "A e^{ikx}, B Fig 5.9's profile, or A sech(Ax) (B Fig 5.10: A = 3)"),
            {"A", Driven ? 3.0 : 1.0, Range::closed(0.0, 10.0),
             "amplitude A of the plane wave or of A sech(Ax)"},
            integer_param("k", 1, -1024, 1024, "plane-wave wavenumber (in units of pi/L)")};
        if constexpr (Driven) {
            s.push_back({"Gamma", 0.45, Range::closed(0.0, 100.0),
                         "forcing amplitude Γ of F(t) = Γ e^{i(ω₀t + α)} (B §5.3.2.3)"});
            s.push_back(
                {"omega0", 1.0, Range::closed(-100.0, 100.0), "forcing frequency ω₀ (B: 1)"});
            s.push_back({"alpha", 0.0, Range::symmetric(100.0), "forcing phase α (B: 0)"});
        }
        return s;
    }
    static SchrodingerProblem from_params(const ParamMap& m) {
        SchrodingerProblem p;
        const double M = m.at("M");
        if (M != std::floor(M) || m.at("k") != std::floor(m.at("k")))
            throw std::invalid_argument("M and k must be whole numbers");
        p.grid = pde::PeriodicGrid(static_cast<int>(M), m.at("L"));
        p.gamma = m.at("gamma");
        p.lambda = m.at("lambda");
        p.initial = static_cast<int>(m.at("initial"));
        p.A = m.at("A");
        p.k = static_cast<int>(m.at("k"));
        if constexpr (Driven) {
            p.drive = m.at("Gamma");
            p.omega0 = m.at("omega0");
            p.alpha = m.at("alpha");
        }
        return p;
    }
    pde::NLSParams nls_params() const {
        return {.gamma = gamma,
                .lambda = lambda,
                .cubic = Cubic,
                .drive = drive,
                .omega0 = omega0,
                .alpha = alpha};
    }

    int dim() const { return 2 * grid.M; }
    double gamma_at(double) const { return 2.0 * gamma; }
    double Gamma(double t) const { return 2.0 * gamma * t; }
    double dGamma(double, double h) const { return 2.0 * gamma * h; }

    Vec initial_state() const {
        const int M = grid.M;
        Vec z(2 * M);
        const double kk = k * std::numbers::pi / grid.L;
        for (int n = 0; n < M; ++n) {
            const double x = grid.x(n);
            std::complex<double> psi;
            if (initial == 0) {
                psi = A * std::exp(std::complex<double>(0.0, kk * x));
            } else if (initial == 2) {
                psi = A / std::cosh(A * x);
            } else {
                psi = std::exp(std::complex<double>(0.0, 5.0 * x)) / std::cosh(x + 1.0) +
                      1.5 * std::exp(std::complex<double>(0.0, -5.0 * x)) /
                          std::cosh(1.5 * (x - 5.0));
            }
            z[n] = psi.real();
            z[M + n] = psi.imag();
        }
        return z;
    }

    // N(z): q' = −(δ²p + V'p), p' = δ²q + V'q, V' = λ (linear) or λ(q² + p²) (cubic);
    // driven: + (Γ sin θ, −Γ cos θ), θ = ω₀t + α.
    void N(double t, const Vec& z, Vec& out) const {
        const int M = grid.M;
        const double s = 1.0 / (grid.dx * grid.dx);
        for (int n = 0; n < M; ++n) {
            const int l = n == 0 ? M - 1 : n - 1, r = n + 1 == M ? 0 : n + 1;
            const double q = z[n], p = z[M + n];
            const double d2q = (z[l] - 2.0 * q + z[r]) * s;
            const double d2p = (z[M + l] - 2.0 * p + z[M + r]) * s;
            const double vp = Cubic ? lambda * (q * q + p * p) : lambda;
            out[n] = -(d2p + vp * p);
            out[M + n] = d2q + vp * q;
        }
        if constexpr (Driven) {
            const double th = omega0 * t + alpha;
            const double fq = drive * std::sin(th), fp = -drive * std::cos(th);
            for (int n = 0; n < M; ++n) {
                out[n] += fq;
                out[M + n] += fp;
            }
        } else {
            (void)t;
        }
    }
    // |ψ| at the grid point nearest x = 0 (x_n = −L + nΔx): the `attractor` diagnostic's probe.
    static constexpr std::string_view probe_name = "|psi(0, t)|";
    double probe(const Vec& z) const {
        const int n = probe_index();
        return std::hypot(z[n], z[grid.M + n]);
    }
    // ψ(0, t) in the complex plane, B Fig 5.10's right panels (the `portrait` figure)
    static constexpr std::array<std::string_view, 2> probe_plane_names{"Re psi(0, t)",
                                                                       "Im psi(0, t)"};
    std::array<double, 2> probe_plane(const Vec& z) const {
        const int n = probe_index();
        return {z[n], z[grid.M + n]};
    }
    int probe_index() const {
        return std::clamp(static_cast<int>(std::lround(grid.L / grid.dx)), 0, grid.M - 1);
    }
    void N_jacobian(double, const Vec& z, Mat& J) const {
        const int M = grid.M;
        const double s = 1.0 / (grid.dx * grid.dx);
        J.setZero();
        for (int n = 0; n < M; ++n) {
            const int l = n == 0 ? M - 1 : n - 1, r = n + 1 == M ? 0 : n + 1;
            const double q = z[n], p = z[M + n];
            // δ² parts: dq'/dp = −δ², dp'/dq = δ²
            J(n, M + l) -= s;
            J(n, M + r) -= s;
            J(n, M + n) += 2.0 * s;
            J(M + n, l) += s;
            J(M + n, r) += s;
            J(M + n, n) -= 2.0 * s;
            if constexpr (Cubic) {
                J(n, n) += -2.0 * lambda * q * p;
                J(n, M + n) += -lambda * (q * q + 3.0 * p * p);
                J(M + n, n) += lambda * (3.0 * q * q + p * p);
                J(M + n, M + n) += 2.0 * lambda * q * p;
            } else {
                J(n, M + n) -= lambda;
                J(M + n, n) += lambda;
            }
        }
    }

    // ψ̂ (forward DFT, no normalisation) as interleaved (re, im); a local transform (thread safe).
    std::vector<double> dft(const Vec& z, pde::SpectralDerivative& D) const {
        const int M = grid.M;
        std::vector<double> d(2 * static_cast<std::size_t>(M));
        for (int n = 0; n < M; ++n) {
            d[2 * n] = z[n];
            d[2 * n + 1] = z[M + n];
        }
        D.forward(d);
        return d;
    }
    // Δx Σ|ψ|² and, over the DFT ψ̂ (a_j = |ψ̂_j|², wavenumber k_j), Σ k_j a_j, Σ |k_j| a_j and
    // Σ k_j² a_j: what the invariants (B (5.29)) and their scales are made of.
    struct SpectralSums {
        double mass = 0.0, k = 0.0, abs_k = 0.0, k2 = 0.0;
    };
    SpectralSums spectral_sums(const Vec& z) const {
        const int M = grid.M;
        SpectralSums s;
        for (int n = 0; n < 2 * M; ++n) s.mass += z[n] * z[n];
        s.mass *= grid.dx;
        pde::SpectralDerivative D(grid);
        const std::vector<double> d = dft(z, D);
        for (int j = 0; j < M; ++j) {
            const double a = d[2 * j] * d[2 * j] + d[2 * j + 1] * d[2 * j + 1];
            const double kj = D.wavenumber(j);
            s.k += kj * a;
            s.abs_k += std::abs(kj) * a;
            s.k2 += kj * kj * a;
        }
        return s;
    }
    void invariants(double, const Vec& z, double* out) const {
        if constexpr (!Driven) {
            const SpectralSums s = spectral_sums(z);
            out[0] = grid.dx / grid.M * s.k;
            out[1] = s.mass;
            if constexpr (!Cubic) out[2] = -grid.dx / grid.M * s.k2 + lambda * s.mass;
        } else {
            (void)z;
            (void)out;
        }
    }
    void invariant_scales(double, const Vec& z, double* out) const {
        if constexpr (!Driven) {
            const SpectralSums s = spectral_sums(z);
            out[0] = grid.dx / grid.M * s.abs_k;
            out[1] = s.mass;
            if constexpr (!Cubic) out[2] = grid.dx / grid.M * s.k2 + std::abs(lambda) * s.mass;
        } else {
            (void)z;
            (void)out;
        }
    }

    // Linear Schrödinger: mode by mode from (t0, z0); z(t0) = z0 exactly.
    void exact(double t0, const Vec& z0, double t, Vec& out) const requires(!Cubic) {
        if (t == t0) {
            out = z0;
            return;
        }
        const int M = grid.M;
        pde::SpectralDerivative D(grid);
        std::vector<double> d = dft(z0, D);
        const double tau = t - t0, decay = std::exp(-2.0 * gamma * tau);
        for (int j = 0; j < M; ++j) {
            const int jj = j <= M / 2 ? j : j - M;
            const double sn = std::sin(std::numbers::pi * jj / M); // sin(θ_j/2), θ_j = 2πj/M
            const double kd2 = 4.0 * sn * sn / (grid.dx * grid.dx);
            const std::complex<double> f =
                decay * std::exp(std::complex<double>(0.0, (lambda - kd2) * tau));
            const std::complex<double> c = f * std::complex<double>(d[2 * j], d[2 * j + 1]);
            d[2 * j] = c.real();
            d[2 * j + 1] = c.imag();
        }
        D.inverse(d);
        out.resize(2 * M);
        for (int n = 0; n < M; ++n) {
            out[n] = d[2 * n];
            out[M + n] = d[2 * n + 1];
        }
    }
};

using Schrodinger = SchrodingerProblem<false>;
using NLS = SchrodingerProblem<true>;
using NLSDriven = SchrodingerProblem<true, true>;

} // namespace dampsym
