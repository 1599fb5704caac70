// Generic exponential Runge–Kutta kernel (ERK), B(2.7), on the conformal form
// z' = N(z, t) − γz (SPEC §1, B(1.1)), for coefficient data that are functions of x = γh
// (src/methods/exponential_tableaux.hpp, pointed at by MethodInfo::family_data):
//   Z_i     = φ_i(x) z_n + h Σ_j a_ij(x) N(Z_j, t_n + c_j h),   i = 1..s,
//   z_{n+1} = φ_0(x) z_n + h Σ_i b_i(x) N(Z_i, t_n + c_i h),                          B(2.7)
// with tableau B(2.10) [c | A | φ ; bᵀ | φ_0]. Both constructions of B §2.1 are data of this one
// kernel: the integrating factor B(2.5) (a_ij = α_ij e^{−(c_i−c_j)x}, φ_i = e^{−c_i x},
// b_i = β_i e^{−(1−c_i)x}, φ_0 = e^{−x}) and exponential time differencing B(2.6), e.g. etdrk2
// B(2.13): c = ½, a = (e^{x/2} − e^{−x/2})/(2x) = sinh(x/2)/x, φ_1 = e^{−x/2}, b = (1 − e^{−x})/x,
// φ_0 = e^{−x}. x = γh is OUR γ: B(1.1), (2.5), (2.13) use the conformal-form γ, which is the
// γ of SPEC §1 (only B(2.17)–(2.22), (2.34) use twice ours; see partitioned_exponential_rk.hpp).
//
// Damping argument. With constant γ the coefficients are evaluated once, in the constructor, at
// x = problem.dGamma(0, h) = γh. With time-dependent γ (hill, rigid-body) they are re-evaluated at
// the start of every step at the step's own argument x_n = Γ(t_n + h) − Γ(t_n) =
// problem.dGamma(t_n, h), i.e. γ frozen at its mean over the step (no allocation: the sizes do not
// change). Then φ_0 = e^{−x_n} and B(2.30) holds at x_n, so the step is conformal symplectic with
// exactly the physical factor e^{−2(Γ(t_n+h)−Γ(t_n))} (B(2.31), Thm 2.11;
// exponential_conditions.hpp evaluates both on the data). Freezing γ at its mean changes the exact
// flow by O(γ'h³) per step (the difference γ(s) − γ̄ has zero mean over the step), so the order is
// min(p, 2): every ERK/PERK row of the catalog has p ≤ 2. (glifrk1..3 keep their full order with
// time-dependent γ: they use the ifrk kernel, which evaluates Γ at every stage time, B(2.4)–(2.5).)
//
// Stages. An explicit A (strictly lower triangular) is stepped stage by stage (s evaluations of
// N). Otherwise the stage equations R_i(Z) = Z_i − φ_i z − h Σ_j a_ij N(Z_j, t_j) = 0 are solved by
// Newton's method on the full (s·d)×(s·d) system with the analytic Jacobian N_jacobian (block
// δ_ij I − h a_ij ∂N(Z_j), one LU per iteration), from Z_i = φ_i z, until the update is at
// round-off (≤ 4 ulps of the scale, or stalled below 1e−10 of the scale), as cimp.hpp and
// implicit_rk.hpp. Every iteration counts s N and s Jacobian evaluations and one Newton iteration
// in Counters. No convergence within 50 iterations, or a NaN/inf, returns
// StepStatus::solve_failed and leaves z unchanged (never throws). When A is invertible the update
// needs no further evaluation: with d = A⁻ᵀb, h Σ_i b_i N_i = Σ_k d_k (Z_k − φ_k z), so
//   z_{n+1} = φ_0 z_n + Σ_k d_k (Z_k − φ_k z_n)       (etdrk2: d = 2e^{−x/2}, z₁ = 2e^{−x/2}Z −
//   e^{−x}z).
//
// Exact step Jacobian (step_jacobian): the implicit-function theorem at the computed stages,
//   (I − hA ⊗ ∂N) dZ = φ ⊗ I,   Ψ = φ_0 I + Σ_k d_k (dZ_k − φ_k I)   (or φ_0 I + h Σ b_i ∂N_i
//   dZ_i),
// with N_jacobian at the stages (s Jacobian evaluations); z advances exactly as in step().
#pragma once

#include "core/method.hpp"
#include "core/problem.hpp"
#include "methods/exponential_tableaux.hpp"
#include "methods/newton.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string_view>
#include <vector>

namespace dampsym {

template <class P>
class ExponentialRK {
public:
    static constexpr std::string_view kernel_id = "exponential-rk";
    template <class Q>
    static constexpr bool applies = [] {
        if constexpr (requires { Q::has_conformal; })
            return Q::has_conformal;
        else
            return false;
    }();
    static constexpr bool has_step_jacobian = true;
    static constexpr int max_iterations = 50;

    ExponentialRK(const P& problem, const MethodInfo& info, double h, Counters& counters)
        : prob_(problem), s_(checked(info).stages), d_(problem.dim()), h_(h), c_(counters),
          M_(s_, s_), dw_(Vec::Zero(s_)), Y0_(ui(s_), Vec(d_)), Z_(ui(s_), Vec(d_)),
          G_(ui(s_), Vec(d_)), J_(ui(s_), Mat(d_, d_)), acc_(d_), X_(s_ * d_), R_(s_ * d_),
          dX_(s_ * d_), S_(s_ * d_, s_ * d_), lu_(s_ * d_), B_(Mat::Zero(s_ * d_, d_)),
          dZ_(s_ * d_, d_), data_(checked(info)) {
        set_argument(problem.dGamma(0.0, h)); // x = γh for constant γ
        explicit_ = true;
        for (int i = 0; i < s_; ++i)
            for (int j = i; j < s_; ++j)
                if (tab_.A(i, j) != 0.0) explicit_ = false;
        if (!explicit_) {
            Eigen::FullPivLU<Mat> lu(tab_.A.transpose());
            use_d_ = lu.isInvertible();
        }
        set_argument(x_, true);
    }

    const ExponentialTableau& coefficients() const { return tab_; }

    StepStatus step(double t, Vec& z) {
        if constexpr (!detail::declares_constant_gamma<P>()) set_argument(prob_.dGamma(t, h_));
        for (int i = 0; i < s_; ++i) Y0_[ui(i)] = tab_.phi[i] * z;
        if (explicit_) {
            for (int i = 0; i < s_; ++i) {
                Z_[ui(i)] = Y0_[ui(i)];
                for (int j = 0; j < i; ++j)
                    if (M_(i, j) != 0.0) Z_[ui(i)] += M_(i, j) * G_[ui(j)];
                eval(t, i);
            }
            c_.rhs_evals += s_;
            final_from_evaluations(z);
            return StepStatus::ok;
        }
        if (!newton(t)) return StepStatus::solve_failed;
        if (use_d_) {
            // z₁ = φ_0 z + Σ_k d_k (Z_k − φ_k z).
            acc_ = Z_[0] - Y0_[0];
            z *= tab_.phi0;
            z += dw_[0] * acc_;
            for (int k = 1; k < s_; ++k) {
                acc_ = Z_[ui(k)] - Y0_[ui(k)];
                z += dw_[k] * acc_;
            }
        } else {
            for (int i = 0; i < s_; ++i) eval(t, i);
            c_.rhs_evals += s_;
            final_from_evaluations(z);
        }
        return StepStatus::ok;
    }

    // Advances z exactly as step() and writes Psi = ∂z₁/∂z₀ (implicit-function theorem at the
    // computed stages, analytic Jacobians; no finite differences).
    StepStatus step_jacobian(double t, Vec& z, Mat& Psi) {
        const StepStatus st = step(t, z);
        if (st != StepStatus::ok) return st;
        for (int j = 0; j < s_; ++j) jac(t, j);
        c_.jac_evals += s_;
        assemble_newton_matrix();
        lu_.compute(S_);
        dZ_ = lu_.solve(B_);
        Psi.resize(d_, d_);
        if (!explicit_ && use_d_) {
            Psi = tab_.phi0 * Mat::Identity(d_, d_);
            for (int k = 0; k < s_; ++k) {
                Psi += dw_[k] * dZ_.middleRows(k * d_, d_);
                Psi.diagonal().array() -= dw_[k] * tab_.phi[k];
            }
        } else {
            Psi = tab_.phi0 * Mat::Identity(d_, d_);
            for (int i = 0; i < s_; ++i)
                if (tab_.b[i] != 0.0)
                    Psi.noalias() += (h_ * tab_.b[i]) * J_[ui(i)] * dZ_.middleRows(i * d_, d_);
        }
        return StepStatus::ok;
    }

private:
    static std::size_t ui(int i) { return static_cast<std::size_t>(i); }

    static const ExponentialRKData& checked(const MethodInfo& info) {
        const auto* data = static_cast<const ExponentialRKData*>(info.family_data);
        if (data == nullptr || data->stages < 1 || data->coefficients == nullptr)
            throw std::invalid_argument("exponential-rk: method row has no ERK coefficient data");
        return *data;
    }

    // Coefficients at the damping argument x (our γh, or ΔΓ_n for time-dependent γ); recomputed
    // only when x changes. Sizes are fixed, so nothing is allocated.
    void set_argument(double x, bool force = false) {
        if (x == x_ && !force) return;
        x_ = x;
        erk_coefficients(data_, x, tab_);
        M_ = h_ * tab_.A;
        if (use_d_) {
            lu_d_.compute(tab_.A.transpose());
            dw_ = lu_d_.solve(tab_.b);
        }
        for (int i = 0; i < s_; ++i) {
            auto blk = B_.middleRows(i * d_, d_); // ∂(φ_i z)/∂z
            blk.setZero();
            blk.diagonal().setConstant(tab_.phi[i]);
        }
    }

    double stage_time(double t, int i) const { return t + tab_.c[i] * h_; }
    void eval(double t, int j) { prob_.N(stage_time(t, j), Z_[ui(j)], G_[ui(j)]); }
    void jac(double t, int j) { prob_.N_jacobian(stage_time(t, j), Z_[ui(j)], J_[ui(j)]); }

    // z₁ = φ_0 z + h Σ b_i N_i.
    void final_from_evaluations(Vec& z) {
        z *= tab_.phi0;
        for (int i = 0; i < s_; ++i)
            if (tab_.b[i] != 0.0) z += (h_ * tab_.b[i]) * G_[ui(i)];
    }

    // S = I − M ⊗ ∂N at the current stages (blocks δ_ij I − h a_ij J_j).
    void assemble_newton_matrix() {
        for (int i = 0; i < s_; ++i)
            for (int j = 0; j < s_; ++j) {
                auto blk = S_.block(i * d_, j * d_, d_, d_);
                blk = -M_(i, j) * J_[ui(j)];
                if (i == j) blk.diagonal().array() += 1.0;
            }
    }

    bool newton(double t) {
        for (int i = 0; i < s_; ++i) {
            X_.segment(i * d_, d_) = Y0_[ui(i)];
            Z_[ui(i)] = Y0_[ui(i)];
        }
        double previous = std::numeric_limits<double>::infinity();
        for (int it = 1; it <= max_iterations; ++it) {
            for (int j = 0; j < s_; ++j) {
                eval(t, j);
                jac(t, j);
            }
            c_.rhs_evals += s_;
            c_.jac_evals += s_;
            c_.newton_iters += 1;
            for (int i = 0; i < s_; ++i) { // R_i = Z_i − φ_i z − Σ_j M_ij N_j
                acc_ = Z_[ui(i)] - Y0_[ui(i)];
                for (int j = 0; j < s_; ++j)
                    if (M_(i, j) != 0.0) acc_ -= M_(i, j) * G_[ui(j)];
                R_.segment(i * d_, d_) = acc_;
            }
            assemble_newton_matrix();
            lu_.compute(S_);
            dX_ = lu_.solve(R_);
            X_ -= dX_;
            for (int i = 0; i < s_; ++i) Z_[ui(i)] = X_.segment(i * d_, d_);
            const double step_norm = dX_.cwiseAbs().maxCoeff();
            const double scale = std::max(X_.cwiseAbs().maxCoeff(), 1e-300);
            if (!(step_norm == step_norm) || !std::isfinite(scale)) return false; // NaN / inf
            if (newton_converged(step_norm, scale, previous)) {
                c_.max_newton_iters_per_step = std::max(c_.max_newton_iters_per_step, it);
                return true;
            }
            previous = step_norm;
        }
        return false;
    }

    const P& prob_;
    int s_, d_;
    double h_;
    Counters& c_;
    ExponentialTableau tab_;
    bool explicit_ = true, use_d_ = false;
    Mat M_;  // h A
    Vec dw_; // d = A⁻ᵀ b
    std::vector<Vec> Y0_, Z_, G_;
    std::vector<Mat> J_;
    Vec acc_, X_, R_, dX_;
    Mat S_;
    Eigen::PartialPivLU<Mat> lu_;
    Mat B_, dZ_;
    const ExponentialRKData& data_;
    double x_ = std::numeric_limits<double>::quiet_NaN();
    Eigen::PartialPivLU<Mat> lu_d_{};
};

} // namespace dampsym
