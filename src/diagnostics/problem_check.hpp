// A problem's Jacobians checked against the functions they differentiate, once per case
// (docs/conventions.md "Derivative checks"): every kernel, diagnostic and E_n pass that uses
// rhs_jacobian (∂f/∂z of the plain form; for a separable problem it holds force_jacobian and
// hess_T) or N_jacobian (∂N/∂z of the conformal form) trusts them, and a certified reference
// integrates the same force, so a force whose Jacobian does not match it is seen by nothing else.
//   rhs  rhs_jacobian(t, z) against central differences of rhs(t, ·) at z;
//   N    N_jacobian against N, when the problem has both;
//   structure  where E_n uses a structure matrix D (the canonical J⁻¹ of a problem in canonical
//        coordinates, or the problem's structure_matrix, conformal_symplectic.hpp), that N is a
//        D-Hamiltonian field, N = D∇H_γ: then N' = D H'' with H'' symmetric and D antisymmetric,
//        so N'D + DN'ᵀ = DH''D − DH''D = 0 (for canonical coordinates: the force's Jacobian is
//        symmetric, F = −∇V). Checked as (N'D + DN'ᵀ)w = N'(Dw) + D(N'ᵀw) for 2 random w with
//        r_j = ±1 (matrix–vector products only: cheap for M = 1024), against the rounding bound
//        of the two products, componentwise 2κε(|N'|(|D||w|) + |D|(|N'|ᵀ|w|)), κ = 16.
// The derivative checks are those of diagnostics/jacobian_check.hpp (full columns up to d = 16,
// else 2 random directions): a few dense Jacobians and 6 evaluations per direction per state.
#pragma once

#include "diagnostics/conformal_symplectic.hpp"
#include "diagnostics/jacobian_check.hpp"

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace dampsym {

struct ProblemCheck {
    std::vector<std::string> parts; // "rhs", "N", "structure" (those the problem has)
    DerivativeCheck derivative;     // rhs and N
    std::int64_t structure_vectors = 0;
    double structure_ratio = 0.0; // max |(N'D + DN'ᵀ)w|_i / bound_i (> 1: N is not D-Hamiltonian)
    double structure_rel = 0.0;   // |(N'D + DN'ᵀ)w|_i / (|N'||D||w| + |D||N'|ᵀ|w|)_i there
    bool passed() const { return !derivative.mismatch() && structure_ratio <= 1.0; }
};

namespace detail {

template <class P>
constexpr bool has_rhs_jacobian() {
    return requires(const P& p, const Vec& z, Mat& J) {
        p.rhs_jacobian(0.0, z, J);
    };
}

template <class P>
constexpr bool has_N_and_jacobian() {
    return requires(const P& p, const Vec& z, Vec& out, Mat& J) {
        p.N(0.0, z, out);
        p.N_jacobian(0.0, z, J);
    };
}

// The structure matrix E_n uses for P (J⁻¹ or D), into D.
template <class P>
void structure_of(const P& p, Mat& D) {
    if constexpr (is_canonical_problem<P>()) {
        D = canonical_J_inverse(p.dim());
    } else {
        D.resize(p.dim(), p.dim());
        p.structure_matrix(D);
    }
}

// (N'D + DN'ᵀ)w against its rounding bound for 2 random sign vectors w; merged into out.
inline void check_structure(const Mat& Jn, const Mat& D, std::uint64_t seed, ProblemCheck& out) {
    const double eps = std::numeric_limits<double>::epsilon();
    const Mat aJ = Jn.cwiseAbs(), aD = D.cwiseAbs();
    for (int k = 0; k < 2; ++k) {
        std::uint64_t s = seed * 7919ULL + static_cast<std::uint64_t>(k);
        Vec w(D.cols());
        for (Eigen::Index j = 0; j < w.size(); ++j) w[j] = (splitmix64(s) >> 63) != 0 ? 1.0 : -1.0;
        const Vec r = Jn * (D * w) + D * (Jn.transpose() * w);
        const Vec size = aJ * (aD * w.cwiseAbs()) + aD * (aJ.transpose() * w.cwiseAbs());
        for (Eigen::Index i = 0; i < r.size(); ++i) {
            const double bound = 2.0 * fd_kappa * eps * size[i];
            const double ratio =
                bound > 0.0 ? std::abs(r[i]) / bound : (r[i] != 0.0 ? HUGE_VAL : 0.0);
            if (!(ratio <= out.structure_ratio)) {
                out.structure_ratio = std::isnan(ratio) ? HUGE_VAL : ratio;
                out.structure_rel = std::abs(r[i]) / (size[i] > 0.0 ? size[i] : 1.0);
            }
        }
        ++out.structure_vectors;
    }
}

} // namespace detail

// The checks of P's Jacobians at state z, time t, merged into out; seed selects the random
// directions (a different one per state).
template <class P>
void check_problem_at(const P& p, double t, const Vec& z, std::uint64_t seed, ProblemCheck& out) {
    const Eigen::Index d = z.size();
    if constexpr (detail::has_rhs_jacobian<P>()) {
        auto f = [&](const Vec& x, Vec& y) {
            y.resize(d);
            p.rhs(t, x, y);
            return true;
        };
        Vec f0(d);
        f(z, f0);
        Mat J = Mat::Zero(d, d);
        p.rhs_jacobian(t, z, J);
        out.derivative.merge(check_derivative(f, z, f0, J, false, seed));
    }
    if constexpr (detail::has_N_and_jacobian<P>()) {
        auto f = [&](const Vec& x, Vec& y) {
            y.resize(d);
            p.N(t, x, y);
            return true;
        };
        Vec f0(d);
        f(z, f0);
        Mat J = Mat::Zero(d, d);
        p.N_jacobian(t, z, J);
        out.derivative.merge(check_derivative(f, z, f0, J, false, seed + 1));
        if constexpr (has_conformal_structure<P>()) {
            Mat D;
            detail::structure_of(p, D);
            detail::check_structure(J, D, seed, out);
        }
    }
}

// The parts checked for P (ProblemCheck::parts).
template <class P>
std::vector<std::string> problem_check_parts() {
    std::vector<std::string> parts;
    if constexpr (detail::has_rhs_jacobian<P>()) parts.emplace_back("rhs");
    if constexpr (detail::has_N_and_jacobian<P>()) {
        parts.emplace_back("N");
        if constexpr (has_conformal_structure<P>())
            parts.emplace_back(is_canonical_problem<P>() ? "structure:canonical"
                                                         : "structure:structure-matrix");
    }
    return parts;
}

} // namespace dampsym
