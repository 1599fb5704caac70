// The one Runge–Kutta engine (HLW II.1, BS; B(2.5), (2.7)) behind the implicit RK, IFRK and
// exponential RK kernels. A coefficient provider says which form is stepped and supplies the
// coefficients of each step; the engine is the only code that solves and combines the stages:
//   Z_i = y0_i z + Σ_j M_ij g(t + c_j h, Z_j),   i = 1..s,
//   z₁  = φ0 z + Σ_i w_i g(t + c_i h, Z_i),
// with g = problem.rhs (plain form, z' = f(t, z)) or g = problem.N (conformal form
// z' = N(z, t) − γz). The providers (in the adapter files):
//   ConstantTableauProvider   plain form; y0 = 1, M = hA, w = hb, φ0 = 1 (implicit_rk.hpp);
//   IntegratingFactorProvider conformal form, B(2.5) with the problem's exact Γ at the stage times
//                          (integrating_factor.hpp; ifrk.hpp);
//   ExponentialProvider       conformal form, B(2.7): data φ_i(x), a_ij(x), b_i(x), φ_0(x) at the
//                          damping argument x = γh, or x_n = Γ(t_n + h) − Γ(t_n) for a
//                          time-dependent γ (exponential_tableaux.hpp; exponential_rk.hpp).
//
// Stages. An explicit tableau (M strictly lower triangular) is stepped stage by stage (s
// evaluations of g). Otherwise the stage equations R_i(Z) = Z_i − Y0_i − Σ_j M_ij g_j(Z_j) = 0 are
// solved by the stage-Newton solver (newton.hpp) on the full (s·d)×(s·d) system with the analytic
// Jacobian (blocks δ_ij I − M_ij ∂g_j) from Z_i = Y0_i: one stage, full Newton (g and ∂g at every
// iteration, one LU of the d×d matrix each time: cimp's arithmetic step for step); several stages,
// simplified Newton (the matrix formed once per step at the predictor, s Jacobian evaluations and
// one LU, then s evaluations of g and one triangular solve per iteration). No convergence, or a
// NaN/inf, returns StepStatus::solve_failed and leaves z unchanged.
//
// Update. When the provider sets use_d (the plain and integrating-factor providers: one implicit
// stage only, implicit_rk.hpp says why; exponential coefficients: A(x) invertible) the update needs
// no further evaluation: with the provider's weights d (d = A⁻ᵀb),
// Σ w_i g_i = Σ_k d_k (Z_k − Y0_k)-type combinations:
//   plain / integrating factor: z₁ = Σ_k F_k (d_k Z_k − (d_k − e_k) Y0_k), e = (1, 0, …, 0), with
//     d = A⁻ᵀb of the underlying tableau and e^{−x(h)} z = F_1 Y0_1 (plain: F = 1). For s = 1 Gauss
//     (d = 2) this is F(2Z − Y0): the implicit midpoint rule, and cimp under the factor;
//   exponential coefficients: z₁ = φ0 z + Σ_k d_k (Z_k − Y0_k), d = A(x)⁻ᵀ b(x) (etdrk2:
//     d = 2e^{−x/2}).
// Otherwise the update z₁ = φ0 z + Σ w_i g_i costs s more evaluations (g at the converged stages).
//
// Exact step Jacobian (step_jacobian): the implicit-function theorem at the converged stages,
//   (I − M ⊗ ∂g) dZ = y0 ⊗ I,   then the derivative of the update formula above,
// with the analytic Jacobians at the converged stages (s Jacobian evaluations).
#pragma once

#include "core/method.hpp"
#include "core/problem.hpp"
#include "methods/newton.hpp"

#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

namespace dampsym {

// Per-step coefficients of the RK engine, filled by a coefficient provider.
struct RKStepCoefficients {
    bool explicit_tableau = true; // M strictly lower triangular (structurally)
    bool use_d = false;           // implicit and invertible: update from the stages
    bool factored_update = true;  // the plain / integrating-factor form of the update (header)
    Vec c;                        // abscissae
    Vec y0;                       // factor of z in stage i
    Mat M;                        // stage matrix
    Vec w;                        // weight of g_i in the update from evaluations
    Vec F;                        // factored update: factor of stage k
    Vec d;                        // update weights from the stages
    double phi0 = 1.0;            // factor of z in the update
    void resize(int s) {
        c = Vec::Zero(s);
        y0 = Vec::Ones(s);
        M = Mat::Zero(s, s);
        w = Vec::Zero(s);
        F = Vec::Ones(s);
        d = Vec::Zero(s);
        phi0 = 1.0;
    }
};

// Provider interface (implicit_rk.hpp, ifrk.hpp, exponential_rk.hpp):
//   static constexpr bool conformal;             g = N (true) or g = rhs (false)
//   int stages() const;
//   template <class P> void init(const P&, double h, RKStepCoefficients&);    once
//   template <class P> void at_step(const P&, double t, double h, RKStepCoefficients&);
template <class P, class Provider>
class RungeKuttaEngine {
public:
    static constexpr bool has_step_jacobian = true;

    RungeKuttaEngine(const P& problem, Provider provider, double h, Counters& counters)
        : prob_(problem), pv_(std::move(provider)), s_(pv_.stages()), d_(problem.dim()), h_(h),
          c_(counters), Y0_(ui(s_), Vec(d_)), Z_(ui(s_), Vec(d_)), G_(ui(s_), Vec(d_)),
          J_(ui(s_), Mat(d_, d_)), acc_(d_), newton_(s_ * d_), B_(Mat::Zero(s_ * d_, d_)),
          dZ_(s_ * d_, d_) {
        k_.resize(s_);
        pv_.init(problem, h, k_);
    }

    const Provider& provider() const { return pv_; }

    StepStatus step(double t, Vec& z) {
        pv_.at_step(prob_, t, h_, k_);
        for (int i = 0; i < s_; ++i) {
            if constexpr (Provider::conformal)
                Y0_[ui(i)] = k_.y0[i] * z;
            else
                Y0_[ui(i)] = z;
        }
        if (k_.explicit_tableau) {
            for (int i = 0; i < s_; ++i) {
                Z_[ui(i)] = Y0_[ui(i)];
                for (int j = 0; j < i; ++j)
                    if (k_.M(i, j) != 0.0) Z_[ui(i)] += k_.M(i, j) * G_[ui(j)];
                eval(t, i);
            }
            c_.rhs_evals += s_;
            final_from_evaluations(z);
            return StepStatus::ok;
        }
        if (!solve_stages(t)) return StepStatus::solve_failed;
        if (k_.use_d) {
            final_from_stages(z);
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
        for (int i = 0; i < s_; ++i) { // ∂Y0_i/∂z
            auto blk = B_.middleRows(i * d_, d_);
            blk.setZero();
            blk.diagonal().setConstant(k_.y0[i]);
        }
        newton_.factor_and_solve(B_, dZ_);
        Psi.resize(d_, d_);
        if (!k_.explicit_tableau && k_.use_d) {
            if (k_.factored_update) {
                const auto& d = k_.d;
                Psi = k_.F[0] *
                      (d[0] * dZ_.topRows(d_) - ((d[0] - 1.0) * k_.y0[0]) * Mat::Identity(d_, d_));
                for (int k = 1; k < s_; ++k)
                    Psi += (k_.F[k] * d[k]) *
                           (dZ_.middleRows(k * d_, d_) - k_.y0[k] * Mat::Identity(d_, d_));
            } else {
                Psi = k_.phi0 * Mat::Identity(d_, d_);
                for (int k = 0; k < s_; ++k) {
                    Psi += k_.d[k] * dZ_.middleRows(k * d_, d_);
                    Psi.diagonal().array() -= k_.d[k] * k_.y0[k];
                }
            }
        } else {
            Psi = k_.phi0 * Mat::Identity(d_, d_);
            for (int i = 0; i < s_; ++i)
                if (k_.w[i] != 0.0)
                    Psi.noalias() += k_.w[i] * J_[ui(i)] * dZ_.middleRows(i * d_, d_);
        }
        return StepStatus::ok;
    }

private:
    static std::size_t ui(int i) { return static_cast<std::size_t>(i); }

    double stage_time(double t, int i) const { return t + k_.c[i] * h_; }

    void eval(double t, int j) {
        if constexpr (Provider::conformal)
            prob_.N(stage_time(t, j), Z_[ui(j)], G_[ui(j)]);
        else
            prob_.rhs(stage_time(t, j), Z_[ui(j)], G_[ui(j)]);
    }
    void jac(double t, int j) {
        if constexpr (Provider::conformal)
            prob_.N_jacobian(stage_time(t, j), Z_[ui(j)], J_[ui(j)]);
        else
            prob_.rhs_jacobian(stage_time(t, j), Z_[ui(j)], J_[ui(j)]);
    }

    // z₁ = φ0 z + Σ_i w_i g_i.
    void final_from_evaluations(Vec& z) {
        if constexpr (Provider::conformal) z *= k_.phi0;
        for (int i = 0; i < s_; ++i)
            if (k_.w[i] != 0.0) z += k_.w[i] * G_[ui(i)];
    }

    // The update from the converged stages (header), no evaluation.
    void final_from_stages(Vec& z) {
        const auto& d = k_.d;
        if (k_.factored_update) { // z₁ = Σ_k F_k (d_k Z_k − (d_k − e_k) Y0_k)
            acc_ = d[0] * Z_[0] - (d[0] - 1.0) * Y0_[0];
            z = k_.F[0] * acc_;
            for (int k = 1; k < s_; ++k) {
                acc_ = d[k] * Z_[ui(k)] - d[k] * Y0_[ui(k)];
                z += k_.F[k] * acc_;
            }
        } else { // z₁ = φ0 z + Σ_k d_k (Z_k − Y0_k)
            acc_ = Z_[0] - Y0_[0];
            z *= k_.phi0;
            z += d[0] * acc_;
            for (int k = 1; k < s_; ++k) {
                acc_ = Z_[ui(k)] - Y0_[ui(k)];
                z += d[k] * acc_;
            }
        }
    }

    // Newton matrix S = I − M ⊗ ∂g at the current stages (blocks δ_ij I − M_ij J_j).
    void assemble_newton_matrix() {
        for (int i = 0; i < s_; ++i)
            for (int j = 0; j < s_; ++j) {
                auto blk = newton_.S.block(i * d_, j * d_, d_, d_);
                if (i == j)
                    blk = Mat::Identity(d_, d_) - k_.M(i, j) * J_[ui(j)];
                else
                    blk = -k_.M(i, j) * J_[ui(j)];
            }
    }

    bool solve_stages(double t) {
        Vec& X = newton_.X;
        for (int i = 0; i < s_; ++i) X.segment(i * d_, d_) = Y0_[ui(i)];
        const NewtonPolicy policy = s_ >= 2 ? NewtonPolicy::simplified : NewtonPolicy::full;
        const bool solved = newton_.solve_step(policy, c_, [&](bool refresh) {
            for (int j = 0; j < s_; ++j) {
                Z_[ui(j)] = X.segment(j * d_, d_);
                eval(t, j);
                if (refresh) jac(t, j);
            }
            c_.rhs_evals += s_;
            if (refresh) c_.jac_evals += s_;
            for (int i = 0; i < s_; ++i) { // residual R_i = Z_i − Y0_i − Σ_j M_ij g_j
                acc_ = k_.M(i, 0) * G_[0];
                for (int j = 1; j < s_; ++j) acc_ += k_.M(i, j) * G_[ui(j)];
                newton_.R.segment(i * d_, d_) = Z_[ui(i)] - Y0_[ui(i)] - acc_;
            }
            if (refresh) assemble_newton_matrix();
        });
        if (!solved) return false;
        for (int i = 0; i < s_; ++i) Z_[ui(i)] = X.segment(i * d_, d_);
        return true;
    }

    const P& prob_;
    Provider pv_;
    int s_, d_;
    double h_;
    Counters& c_;
    RKStepCoefficients k_;
    std::vector<Vec> Y0_, Z_, G_; // Y0_i, stage values, g at the stages
    std::vector<Mat> J_;          // ∂g at the stages
    Vec acc_;
    StageNewton newton_;
    Mat B_, dZ_;
};

} // namespace dampsym
