// Derivatives checked against what they differentiate (docs/conventions.md "Derivative checks"):
// a Jacobian A = ∂G/∂z of a map G (a kernel's step, a problem's rhs or N) against central
// differences of G itself, in a few directions u at a state z.
//
// Scheme. For a direction u and a step δ (dimensionless; the perturbation is δu), with
// z± = z ± δu rounded to doubles and w = z₊ − z₋ the perturbation actually represented,
//   E(δ) = (G(z₊) − G(z₋) − A w) / (2δ) = (δ²/6) G'''[u,u,u] + (δ⁴/120) G⁽⁵⁾[u⁵] + O(δ⁶) +
//   rounding,
// which is zero up to truncation and rounding when A is G's derivative (A w, not 2δ A u: the
// rounding of z ± δu is then no error). Two Richardson levels from δ, δ/2, δ/4 remove the δ² and
// δ⁴ terms:
//   R₁ = (4E(δ/2) − E(δ))/3,  R₂ = (4E(δ/4) − E(δ/2))/3  (both O(δ⁴)),  and R₂ is O(δ⁴)/16.
// Error of R₂, componentwise:
//   truncation  ≈ |R₂ − R₁|/15 (the standard Richardson estimate); we take |R₂ − R₁| itself, which
//               also holds the rounding of R₁ and R₂ as far as it shows in their difference;
//   rounding    each evaluation of G_i at z± has an absolute error at most ρ_i(z±), so E(η) has
//               at most r_i(η) = (ρ_i(z₊) + ρ_i(z₋) + dε(|A||w|)_i)/(2η) (dε: the rounding of the
//               d-term products A w), and R₂ at most (4r_i(δ/4) + r_i(δ/2))/3 (≈ 6ρ_i/δ).
//   ρ_i(x)      the first-order rounding bound of evaluating G_i at x: the rounding of its result
//               plus that of its arguments propagated, ρ_i = κε(|G_i(x)| + Σ_k |A_ik||x_k|) (the
//               componentwise condition of G; for a term g(x_k) the rounding of x_k moves it by
//               |∂g/∂x_k| ε|x_k|), κ = 16 roundings along a path (a step is at most a few stages
//               of a few operations each).
//               A step that solves a nonlinear system (an implicit kernel, methods/newton.hpp)
//               returns its stages to the solve's stopping test, not to round-off: the test stops
//               at an error left ≤ θ/(1−θ)·4ε‖X‖∞ (≤ 16ε‖X‖∞ for a contraction θ ≤ 0.8), ≤ ε‖X‖∞,
//               or at the residual's round-off floor, in the max norm over the stages X. The
//               stages are of the size of the state, so such a step adds ε_solve·max(‖z‖∞,
//               ‖G(z)‖∞) with ε_solve = 16ε to every ρ_i.
// The check passes in direction u when, for every component i,
//   |R₂,i| ≤ tol_i = 2(|R₂ − R₁|_i + (4r_i(δ/4) + r_i(δ/2))/3)
// (the factor 2 for the estimates' own uncertainty). δ = 1e-3: the truncation left in R₂ is
// (δ/4)⁴ ≈ 4e-15 relative for a map whose derivatives vary on the scale of u, while the rounding
// term 6ρ/δ ≈ 2e-11 relative (κ = 16) stays far below a 1e-7 relative defect of a coefficient.
// Reported: rel = |R₂,i| / (|A||u|)_i (the disagreement relative to the size of the derivative's
// terms in that direction), tol = tol_i / (|A||u|)_i and ratio = |R₂,i| / tol_i, at the component
// and direction of the largest ratio; ratio > 1 is a mismatch.
//
// Directions: u_j = s_j e_j (every column) when d ≤ 16, else 2 random directions u = s ⊙ r with
// r_j = ±1 from a fixed seed (results identical for any --jobs); s_j = |z_j|, or where z_j = 0
// the largest |z_k| (1 if z = 0), so that each component is perturbed on its own scale.
#pragma once

#include "core/types.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace dampsym {

// The outcome of derivative checks, merged over directions and states.
struct DerivativeCheck {
    std::int64_t states = 0;     // states checked
    std::int64_t directions = 0; // directions checked (over all states)
    std::int64_t skipped = 0;    // states skipped: G failed or was not finite near z
    double ratio = 0.0;          // max |R₂,i| / tol_i (> 1: mismatch)
    double rel = 0.0;            // |R₂,i| / (|A||u|)_i at the largest ratio
    double tol = 0.0;            // tol_i / (|A||u|)_i at the largest ratio
    bool mismatch() const { return ratio > 1.0; }
    void merge(const DerivativeCheck& o) {
        const bool take = o.directions > 0 && (directions == 0 || o.ratio > ratio);
        states += o.states;
        directions += o.directions;
        skipped += o.skipped;
        if (take) {
            ratio = o.ratio;
            rel = o.rel;
            tol = o.tol;
        }
    }
};

namespace detail {

inline constexpr double fd_delta = 1e-3;
inline constexpr double fd_kappa = 16.0;
inline constexpr double fd_solve_eps = 16.0 * std::numeric_limits<double>::epsilon();
inline constexpr Eigen::Index fd_full_columns_max = 16;
inline constexpr int fd_random_directions = 2;

// splitmix64: a fixed, portable sequence for the random directions' signs.
inline std::uint64_t splitmix64(std::uint64_t& s) {
    std::uint64_t x = (s += 0x9E3779B97F4A7C15ULL);
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
    return x ^ (x >> 31);
}

// Direction k of the check at z (see the header comment).
inline Vec fd_direction(const Vec& z, Eigen::Index k, std::uint64_t seed) {
    const Eigen::Index d = z.size();
    const double zmax = d > 0 ? z.cwiseAbs().maxCoeff() : 0.0;
    Vec u = Vec::Zero(d);
    auto scale = [&](Eigen::Index j) {
        return z[j] != 0.0 ? std::abs(z[j]) : (zmax > 0.0 ? zmax : 1.0);
    };
    if (d <= fd_full_columns_max) {
        u[k] = scale(k);
        return u;
    }
    std::uint64_t s = seed * 1000003ULL + static_cast<std::uint64_t>(k);
    for (Eigen::Index j = 0; j < d; ++j)
        u[j] = ((splitmix64(s) >> 63) != 0 ? 1.0 : -1.0) * scale(j);
    return u;
}

inline Eigen::Index fd_direction_count(Eigen::Index d) {
    return d <= fd_full_columns_max ? d : fd_random_directions;
}

} // namespace detail

// Checks A = ∂G/∂z at z. g(const Vec& x, Vec& out) -> bool evaluates G (false: it failed);
// g0 = G(z); solves: G solves a nonlinear system (adds the solve tolerance to ρ, see above).
// seed: selects the random directions (d > 16).
template <class G>
DerivativeCheck check_derivative(G&& g, const Vec& z, const Vec& g0, const Mat& A, bool solves,
                                 std::uint64_t seed) {
    using detail::fd_delta;
    DerivativeCheck out;
    const Eigen::Index d = z.size();
    const double eps = std::numeric_limits<double>::epsilon();
    const Mat absA = A.cwiseAbs();
    const double solve_rho =
        solves ? detail::fd_solve_eps * std::max(z.cwiseAbs().maxCoeff(), g0.cwiseAbs().maxCoeff())
               : 0.0;
    const double dot_eps = static_cast<double>(d) * eps; // rounding of A w (a d-term dot product)
    Vec gp(g0.size()), gm(g0.size());
    for (Eigen::Index k = 0; k < detail::fd_direction_count(d); ++k) {
        const Vec u = detail::fd_direction(z, k, seed);
        Vec E[3], r[3]; // E(η) and its rounding bound, η = δ, δ/2, δ/4
        for (int l = 0; l < 3; ++l) {
            const double eta = fd_delta / static_cast<double>(1 << l);
            const Vec zp = z + eta * u, zm = z - eta * u, w = zp - zm;
            if (!g(zp, gp) || !g(zm, gm) || !gp.allFinite() || !gm.allFinite()) {
                out.skipped = 1;
                return out;
            }
            E[l] = (gp - gm - A * w) / (2.0 * eta);
            const Vec aw = absA * w.cwiseAbs();
            r[l] = (detail::fd_kappa * eps *
                        (gp.cwiseAbs() + gm.cwiseAbs() + absA * (zp.cwiseAbs() + zm.cwiseAbs())) +
                    dot_eps * aw) /
                   (2.0 * eta);
            r[l].array() += solve_rho / eta;
        }
        const Vec R1 = (4.0 * E[1] - E[0]) / 3.0, R2 = (4.0 * E[2] - E[1]) / 3.0;
        const Vec size = absA * u.cwiseAbs();
        for (Eigen::Index i = 0; i < R2.size(); ++i) {
            const double rounding = (4.0 * r[2][i] + r[1][i]) / 3.0;
            const double tol = 2.0 * (std::abs(R2[i] - R1[i]) + rounding);
            const double err = std::abs(R2[i]);
            const double ratio = tol > 0.0 ? err / tol : (err > 0.0 ? HUGE_VAL : 0.0);
            if (!(ratio <= out.ratio)) { // also takes a NaN ratio (reported as a mismatch)
                out.ratio = std::isnan(ratio) ? HUGE_VAL : ratio;
                const double s = size[i] > 0.0 ? size[i] : 1.0;
                out.rel = err / s;
                out.tol = tol / s;
            }
        }
        ++out.directions;
    }
    out.states = 1;
    return out;
}

} // namespace dampsym
