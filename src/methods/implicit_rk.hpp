// Generic Runge–Kutta kernel for implicit (and explicit) tableaux on the plain form
// z' = f(t, z) (the full damped vector field, f = problem.rhs), HLW II.1, BS:
//   Z_i = z + h Σ_j a_ij f(t + c_j h, Z_j),   i = 1..s,
//   z₁  = z + h Σ_i b_i f(t + c_i h, Z_i).
// implicit-euler HLW(1.5) (A = b = c = 1), implicit-midpoint HLW(1.6) and gauss1..3 are rows of
// the catalog that point at their tableaux (src/methods/tableaux.hpp); this file is the only code.
//
// The same engine (detail::RungeKuttaEngine) also steps the integrating-factor methods B(2.5)
// (src/methods/ifrk.hpp); there the stage equations carry the factors of B(2.5) and f = N.
// In both cases the stage equations are written for the stage values,
//   R_i(Z) = Z_i − Y0_i − Σ_j M_ij g_j(Z_j) = 0     (plain: Y0_i = z, M = hA, g_j = f(t_j, ·)),
// and solved, for a tableau that is not explicit, by Newton's method on the full (s·d)×(s·d)
// system with the analytic Jacobian (block δ_ij I − M_ij ∂g_j), starting from Z_i = Y0_i, until
// the update is at round-off (a few ulps of the scale, or stalled once it is below 1e-10 of the
// scale), as in cimp.hpp. One stage (s = 1): full Newton, g and ∂g at every iteration and one LU
// of the d×d matrix each time, which is cimp's arithmetic step for step. Several stages (s ≥ 2):
// the LU of the (s·d)×(s·d) matrix dominates the cost, so the Newton matrix is formed once per
// step, at the predictor Z = Y0 (s Jacobian evaluations, one LU), and kept for the later
// iterations of the step (simplified Newton, HW II §IV.8): the iteration still converges to
// round-off, linearly with a rate O(h·‖Z − Y0‖·‖∂²g‖), each iteration costing s evaluations of g
// and one triangular solve. No convergence within 50 iterations, or a NaN, returns
// StepStatus::solve_failed and leaves z unchanged.
//
// When A is invertible the update needs no further evaluation: with d = A⁻ᵀb (bᵀA⁻¹),
//   z₁ = Σ_k F_k (d_k Z_k − (d_k − e_k) Y0_k),   e = (1, 0, …, 0),
// which is z₁ = e^{−x(h)} z + Σ_k F_k d_k (Z_k − Y0_k) with e^{−x(h)} z = F_1 Y0_1 (plain: F_k =
// 1). For s = 1 Gauss (d = 2) this is F (2Z − Y0): the implicit midpoint rule 2Z − z, and, under
// the integrating factor, exactly the arithmetic of cimp.hpp. A singular implicit A costs s more
// evaluations (g at the converged stages); an explicit A is stepped stage by stage (s evaluations).
//
// Exact step Jacobian (step_jacobian): the implicit-function theorem at the converged stages,
//   (I − M ⊗ ∂g) dZ = ∂Y0/∂z,   then the derivative of the update formula above,
// with the analytic Jacobians at the converged stage values (s Jacobian evaluations).
#pragma once

#include "core/method.hpp"
#include "core/problem.hpp"
#include "methods/newton.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string_view>
#include <vector>

namespace dampsym {
namespace detail {

// Conformal = false: plain form, g = f = rhs. Conformal = true: B(2.5), g = N (ifrk.hpp).
template <class P, bool Conformal>
class RungeKuttaEngine {
public:
    static constexpr int max_iterations = 50;
    static constexpr bool has_step_jacobian = true;

    RungeKuttaEngine(const P& problem, const ButcherTableau& tableau, double h, Counters& counters)
        : prob_(problem), tab_(tableau), s_(tableau.stages), d_(problem.dim()), h_(h), c_(counters),
          explicit_(is_explicit(tableau)), dw_(Vec::Zero(s_)), ex_(Vec::Ones(s_)),
          F_(Vec::Ones(s_)), M_(s_, s_), Y0_(static_cast<std::size_t>(s_), Vec(d_)),
          Z_(static_cast<std::size_t>(s_), Vec(d_)), G_(static_cast<std::size_t>(s_), Vec(d_)),
          J_(static_cast<std::size_t>(s_), Mat(d_, d_)), acc_(d_), X_(s_ * d_), R_(s_ * d_),
          dX_(s_ * d_), S_(s_ * d_, s_ * d_), lu_(s_ * d_), B_(Mat::Zero(s_ * d_, d_)),
          dZ_(s_ * d_, d_) {
        if (!explicit_) {
            Mat A(s_, s_);
            Vec b(s_);
            for (int i = 0; i < s_; ++i) {
                b[i] = tab_.b[static_cast<std::size_t>(i)];
                for (int j = 0; j < s_; ++j) A(i, j) = tab_.A(i, j);
            }
            Eigen::FullPivLU<Mat> lu(A.transpose());
            use_d_ = lu.isInvertible();
            if (use_d_) dw_ = lu.solve(b);
        }
        for (int i = 0; i < s_; ++i)
            for (int j = 0; j < s_; ++j) M_(i, j) = h_ * tab_.A(i, j);
    }

    StepStatus step(double t, Vec& z) {
        set_coefficients(t);
        for (int i = 0; i < s_; ++i) {
            if constexpr (Conformal)
                Y0_[ui(i)] = ex_[i] * z;
            else
                Y0_[ui(i)] = z;
        }
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
            // z₁ = Σ_k F_k (d_k Z_k − (d_k − e_k) Y0_k), e = (1, 0, …, 0).
            acc_ = dw_[0] * Z_[0] - (dw_[0] - 1.0) * Y0_[0];
            z = F_[0] * acc_;
            for (int k = 1; k < s_; ++k) {
                acc_ = dw_[k] * Z_[ui(k)] - dw_[k] * Y0_[ui(k)];
                z += F_[k] * acc_;
            }
        } else {
            for (int i = 0; i < s_; ++i) eval(t, i);
            c_.rhs_evals += s_;
            final_from_evaluations(z);
        }
        return StepStatus::ok;
    }

    // Advances z exactly as step() and writes Psi = ∂z₁/∂z₀ (implicit-function theorem at the
    // converged stages, analytic Jacobians; no finite differences).
    StepStatus step_jacobian(double t, Vec& z, Mat& Psi) {
        const StepStatus st = step(t, z);
        if (st != StepStatus::ok) return st;
        for (int j = 0; j < s_; ++j) jac(t, j);
        c_.jac_evals += s_;
        assemble_newton_matrix();
        lu_.compute(S_);
        for (int i = 0; i < s_; ++i)
            B_.middleRows(i * d_, d_) = ex_[i] * Mat::Identity(d_, d_); // ∂Y0_i/∂z
        dZ_ = lu_.solve(B_);
        Psi.resize(d_, d_);
        if (!explicit_ && use_d_) {
            Psi = F_[0] *
                  (dw_[0] * dZ_.topRows(d_) - ((dw_[0] - 1.0) * ex_[0]) * Mat::Identity(d_, d_));
            for (int k = 1; k < s_; ++k)
                Psi += (F_[k] * dw_[k]) *
                       (dZ_.middleRows(k * d_, d_) - ex_[k] * Mat::Identity(d_, d_));
        } else {
            Psi = exh_ * Mat::Identity(d_, d_);
            for (int i = 0; i < s_; ++i)
                Psi.noalias() +=
                    (h_ * tab_.b[ui(i)] * F_[i]) * J_[ui(i)] * dZ_.middleRows(i * d_, d_);
        }
        return StepStatus::ok;
    }

private:
    static std::size_t ui(int i) { return static_cast<std::size_t>(i); }

    static bool is_explicit(const ButcherTableau& t) {
        for (int i = 0; i < t.stages; ++i)
            for (int j = i; j < t.stages; ++j)
                if (t.A(i, j) != 0.0) return false;
        return true;
    }

    double stage_time(double t, int i) const { return t + tab_.c[ui(i)] * h_; }

    // B(2.5) with x(τ) = Γ(t+τ) − Γ(t), each factor e^{−(Γ(a)−Γ(b))} = exp(−dGamma(b, a−b)):
    //   ex_i = e^{−x(c_i h)},  F_i = e^{x(c_i h) − x(h)},  M_ij = h α_ij e^{x(c_j h) − x(c_i h)}.
    // Plain form: all factors are 1 and M = hA (set once in the constructor).
    // With constant γ the factors do not depend on t: computed at the first step only (the same
    // values, since dGamma(t, a) = γa for every t).
    void set_coefficients(double t) {
        if constexpr (Conformal) {
            if constexpr (detail::declares_constant_gamma<P>()) {
                if (coefficients_set_) return;
                coefficients_set_ = true;
            }
            exh_ = std::exp(-prob_.dGamma(t, h_));
            for (int i = 0; i < s_; ++i) {
                const double ci = tab_.c[ui(i)];
                ex_[i] = std::exp(-prob_.dGamma(t, ci * h_));
                F_[i] = std::exp(-prob_.dGamma(t + ci * h_, (1.0 - ci) * h_));
                for (int j = 0; j < s_; ++j) {
                    const double aij = tab_.A(i, j);
                    const double cj = tab_.c[ui(j)];
                    M_(i, j) =
                        aij == 0.0
                            ? 0.0
                            : (h_ * aij) * std::exp(-prob_.dGamma(t + cj * h_, (ci - cj) * h_));
                }
            }
        } else {
            (void)t;
        }
    }

    void eval(double t, int j) {
        if constexpr (Conformal)
            prob_.N(stage_time(t, j), Z_[ui(j)], G_[ui(j)]);
        else
            prob_.rhs(stage_time(t, j), Z_[ui(j)], G_[ui(j)]);
    }
    void jac(double t, int j) {
        if constexpr (Conformal)
            prob_.N_jacobian(stage_time(t, j), Z_[ui(j)], J_[ui(j)]);
        else
            prob_.rhs_jacobian(stage_time(t, j), Z_[ui(j)], J_[ui(j)]);
    }

    // z₁ = e^{−x(h)} z + Σ_i (h β_i F_i) g_i (B(2.5), second line; plain: z + h Σ b_i f_i).
    void final_from_evaluations(Vec& z) {
        if constexpr (Conformal) z = exh_ * z;
        for (int i = 0; i < s_; ++i)
            if (tab_.b[ui(i)] != 0.0) z += (h_ * tab_.b[ui(i)] * F_[i]) * G_[ui(i)];
    }

    // Newton matrix S = I − M ⊗ ∂g at the current stages (blocks δ_ij I − M_ij J_j).
    void assemble_newton_matrix() {
        for (int i = 0; i < s_; ++i)
            for (int j = 0; j < s_; ++j) {
                auto blk = S_.block(i * d_, j * d_, d_, d_);
                if (i == j)
                    blk = Mat::Identity(d_, d_) - M_(i, j) * J_[ui(j)];
                else
                    blk = -M_(i, j) * J_[ui(j)];
            }
    }

    bool newton(double t) {
        for (int i = 0; i < s_; ++i) {
            X_.segment(i * d_, d_) = Y0_[ui(i)];
            Z_[ui(i)] = Y0_[ui(i)];
        }
        double previous = std::numeric_limits<double>::infinity();
        const bool simplified = s_ >= 2; // Newton matrix frozen at the predictor (see header)
        for (int it = 1; it <= max_iterations; ++it) {
            const bool refresh = !simplified || it == 1;
            for (int j = 0; j < s_; ++j) {
                eval(t, j);
                if (refresh) jac(t, j);
            }
            c_.rhs_evals += s_;
            if (refresh) c_.jac_evals += s_;
            c_.newton_iters += 1;
            for (int i = 0; i < s_; ++i) { // residual R_i = Z_i − Y0_i − Σ_j M_ij g_j
                acc_ = M_(i, 0) * G_[0];
                for (int j = 1; j < s_; ++j) acc_ += M_(i, j) * G_[ui(j)];
                R_.segment(i * d_, d_) = Z_[ui(i)] - Y0_[ui(i)] - acc_;
            }
            if (refresh) {
                assemble_newton_matrix();
                lu_.compute(S_);
            }
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
    const ButcherTableau& tab_;
    int s_, d_;
    double h_;
    Counters& c_;
    bool explicit_;
    bool use_d_ = false;
    bool coefficients_set_ = false;
    Vec dw_;                      // d = A⁻ᵀ b
    Vec ex_, F_;                  // e^{−x(c_i h)}, e^{x(c_i h) − x(h)}
    double exh_ = 1.0;            // e^{−x(h)}
    Mat M_;                       // M_ij (per step for the conformal form)
    std::vector<Vec> Y0_, Z_, G_; // Y0_i, stage values, g at the stages
    std::vector<Mat> J_;          // ∂g at the stages
    Vec acc_, X_, R_, dX_;
    Mat S_;
    Eigen::PartialPivLU<Mat> lu_;
    Mat B_, dZ_;
};

} // namespace detail

template <class P>
class ImplicitRK : public detail::RungeKuttaEngine<P, false> {
public:
    static constexpr std::string_view kernel_id = "implicit-rk";
    template <class Q>
    static constexpr bool applies = true; // every problem offers the plain form and its Jacobian

    ImplicitRK(const P& problem, const MethodInfo& info, double h, Counters& counters)
        : detail::RungeKuttaEngine<P, false>(problem, *info.tableau, h, counters) {}
};

} // namespace dampsym
