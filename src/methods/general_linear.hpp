// Generic general linear method kernel on the plain form z' = f(t, z) (the full damped vector
// field, f = problem.rhs), BD(2.3), BS "A symplectic general linear method":
//   Y       = h (A ⊗ I) F + (U ⊗ I) y^{[n−1]},   F_i = f(t + c_i h, Y_i),
//   y^{[n]} = h (B ⊗ I) F + (V ⊗ I) y^{[n−1]},
// with the coefficients [A U; B V], the abscissae c and the starting method as data
// (GlmCoefficients, src/methods/glm_coefficients.hpp; catalog row glm4 = butcher_glm4()).
//
// The r values. The kernel holds y^{[n]} (r vectors of the problem's dimension) internally;
// step(t, z) takes and returns the first value, the solution approximation z = y_1. On its first
// call (the kernel is constructed fresh for every run) the starting method builds y^{[0]} from z
// at time t (BS: y_1 = z₀, y_2 = h((√3−1)/8 F₁ + (1−√3)/8 F₂) for glm4) and the step then proceeds
// from y^{[0]}; on later calls the incoming z is used as y_1 together with the stored y_2..y_r, so
// a caller that passes back what it got continues the GLM exactly.
//
// Stage equations. When A is lower triangular (glm4 and its starting method are: DIRK-like) the
// stages are solved one after the other; stage i solves
//   Y_i − h a_ii f(t_i, Y_i) = W_i := (U y)_i + h Σ_{j<i} a_ij F_j
// by Newton's method with the analytic Jacobian rhs_jacobian (I − h a_ii ∂f, one LU per
// iteration), from Y_i = W_i; an explicit stage (a_ii = 0) is one evaluation. A full A is solved by
// Newton's method on the whole (s·d)×(s·d) system (blocks δ_ij I − h a_ij ∂f_j), simplified for
// s ≥ 2 as in the RK engine (the matrix at the predictor). The solver is the one stage-Newton
// solver of methods/newton.hpp (update within a few ulps of the scale, or stalled below 1e-10 of
// the scale). The stage derivatives are then taken from the stage equations, without another
// evaluation:
//   F_i = (Y_i − W_i)/(h a_ii)   (triangular),   h F = A⁻¹ (Y − U y)   (full, A invertible),
// as the RK engine (rk_engine.hpp) does; a singular full A evaluates f at the converged stages
// instead.
// No convergence within 50 iterations, or a NaN/inf, returns StepStatus::solve_failed and leaves z
// and the stored values unchanged (nothing throws while stepping).
//
// Cost counters: rhs_evals and jac_evals count evaluations of f and ∂f, newton_iters every Newton
// iteration (per stage for triangular A), max_newton_iters_per_step the most iterations in one
// step (the starting method's iterations count towards the first step).
//
// No step_jacobian: the step map acts on all r values, so ∂z_{n+1}/∂z_n alone is not the
// derivative of the scheme (the conformal-symplectic diagnostic reports it as unavailable).
#pragma once

#include "core/method.hpp"
#include "methods/glm_coefficients.hpp"
#include "methods/newton.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string_view>

namespace dampsym {

template <class P>
class GeneralLinear {
public:
    static constexpr std::string_view kernel_id = "general-linear";
    using Data = GeneralLinearCoefficients;
    static bool accepts(const Data&) { return true; }
    template <class Q>
    static constexpr bool applies = true; // every problem offers the plain form and its Jacobian

    GeneralLinear(const P& problem, const MethodInfo& info, double h, Counters& counters)
        : prob_(problem), m_(checked(info)), d_(problem.dim()), h_(h), c_(counters), y_(d_, m_.r),
          yin_(d_, m_.r), yout_(d_, m_.r), f_(d_), w_(d_), J_(d_, d_), stage_newton_(d_),
          coupled_main_(main_size(m_, d_)), coupled_start_(start_size(m_, d_)) {
        const int smax = std::max(m_.s, m_.s0);
        Y_.resize(d_, smax);
        F_.resize(d_, smax);
        W_.resize(d_, smax);
        main_ = Plan::make(m_.A);
        start_ = Plan::make(m_.A0);
        if (!main_.triangular || !start_.triangular) { // buffers of the coupled Newton solve
            Fs_.resize(d_, smax);
            Js_.resize(d_, static_cast<Eigen::Index>(smax) * d_);
        }
    }

    StepStatus step(double t, Vec& z) {
        int iters = 0;
        if (!started_) {
            if (m_.s0 > 0) {
                // Starting stages: W = U₀ z₀, then y^{[0]} = h B₀ F + V₀ z₀.
                for (int i = 0; i < m_.s0; ++i) W_.col(i) = m_.U0[i] * z;
                if (!solve_stages(t, m_.A0, m_.c0, start_, m_.s0, iters))
                    return StepStatus::solve_failed;
                yin_.noalias() = (h_ * F_.leftCols(m_.s0)) * m_.B0.transpose();
            } else {
                yin_.setZero();
            }
            yin_.noalias() += z * m_.V0.transpose();
        } else {
            yin_ = y_;
            yin_.col(0) = z;
        }
        // Main stages: W = U y^{[n−1]}, then y^{[n]} = h B F + V y^{[n−1]}.
        W_.leftCols(m_.s).noalias() = yin_ * m_.U.transpose();
        if (!solve_stages(t, m_.A, m_.c, main_, m_.s, iters)) return StepStatus::solve_failed;
        yout_.noalias() = (h_ * F_.leftCols(m_.s)) * m_.B.transpose();
        yout_.noalias() += yin_ * m_.V.transpose();
        y_.swap(yout_);
        started_ = true;
        z = y_.col(0);
        c_.step_solved(iters);
        return StepStatus::ok;
    }

    // The r values after the last step (column k = y_{k+1}); for tests and diagnostics.
    const Mat& values() const { return y_; }

private:
    static const GlmCoefficients& checked(const MethodInfo& info) {
        const GlmCoefficients* glm = std::get<Data>(info.data).glm;
        if (glm == nullptr)
            throw std::invalid_argument("general-linear: method has no GLM coefficients");
        const GlmCoefficients& g = *glm;
        const bool ok = g.s >= 1 && g.r >= 1 && g.A.rows() == g.s && g.A.cols() == g.s &&
                        g.U.rows() == g.s && g.U.cols() == g.r && g.B.rows() == g.r &&
                        g.B.cols() == g.s && g.V.rows() == g.r && g.V.cols() == g.r &&
                        g.c.size() == g.s && g.s0 >= 0 && g.A0.rows() == g.s0 &&
                        g.A0.cols() == g.s0 && g.U0.size() == g.s0 && g.B0.rows() == g.r &&
                        g.B0.cols() == g.s0 && g.V0.size() == g.r && g.c0.size() == g.s0;
        if (!ok) throw std::invalid_argument("general-linear: inconsistent GLM coefficient sizes");
        return g;
    }

    // Unknowns of the coupled Newton solve of the main and the starting stages (0 if triangular).
    static Eigen::Index main_size(const GlmCoefficients& g, int d) {
        return Plan::make(g.A).triangular ? 0 : static_cast<Eigen::Index>(g.s) * d;
    }
    static Eigen::Index start_size(const GlmCoefficients& g, int d) {
        return Plan::make(g.A0).triangular ? 0 : static_cast<Eigen::Index>(g.s0) * d;
    }

    // How the stages of one tableau A are solved (decided once from the coefficients).
    struct Plan {
        bool triangular = true; // a_ij = 0 for j > i
        bool invertible = false;
        Mat A_inv_T; // (A⁻¹)ᵀ
        static Plan make(const Mat& A) {
            Plan p;
            for (Eigen::Index i = 0; i < A.rows(); ++i)
                for (Eigen::Index j = i + 1; j < A.cols(); ++j)
                    if (A(i, j) != 0.0) p.triangular = false;
            if (!p.triangular && A.rows() > 0) {
                Eigen::FullPivLU<Mat> lu(A);
                p.invertible = lu.isInvertible();
                if (p.invertible) p.A_inv_T = lu.inverse().transpose();
            }
            return p;
        }
    };

    // Solves Y = h A F + W (W_ holds U y on entry) for s stages at times t + c_i h; fills Y_, F_.
    bool solve_stages(double t, const Mat& A, const Vec& c, const Plan& plan, int s, int& iters) {
        if (plan.triangular) {
            for (int i = 0; i < s; ++i) {
                w_ = W_.col(i);
                for (int j = 0; j < i; ++j)
                    if (A(i, j) != 0.0) w_ += (h_ * A(i, j)) * F_.col(j);
                const double ti = t + c[i] * h_;
                if (A(i, i) == 0.0) { // explicit stage
                    Y_.col(i) = w_;
                    prob_.rhs(ti, w_, f_);
                    c_.rhs_evals += 1;
                    F_.col(i) = f_;
                    continue;
                }
                if (!newton_stage(ti, h_ * A(i, i), iters)) return false;
                Y_.col(i) = x_;
                F_.col(i) = (x_ - w_) / (h_ * A(i, i));
            }
            return true;
        }
        return newton_coupled(t, A, c, plan, s, iters);
    }

    // Newton for x − ha f(t_i, x) = w_, from x = w_; result in x_.
    bool newton_stage(double ti, double ha, int& iters) {
        Vec& x = stage_newton_.X;
        x = w_;
        const int it = stage_newton_.solve(NewtonPolicy::full, c_, [&](bool) {
            prob_.rhs(ti, x, f_);
            prob_.rhs_jacobian(ti, x, J_);
            c_.rhs_evals += 1;
            c_.jac_evals += 1;
            stage_newton_.S = Mat::Identity(d_, d_) - ha * J_;
            stage_newton_.R = x - w_ - ha * f_;
        });
        if (it == 0) return false;
        iters += it;
        x_ = x;
        return true;
    }

    // Newton on all stages at once (A not lower triangular): R_i = Y_i − W_i − h Σ_j a_ij f_j.
    bool newton_coupled(double t, const Mat& A, const Vec& c, const Plan& plan, int s, int& iters) {
        StageNewton& nw = &plan == &main_ ? coupled_main_ : coupled_start_;
        Vec& X = nw.X;
        for (int i = 0; i < s; ++i) X.segment(i * d_, d_) = W_.col(i);
        // The policy of the RK engine for the same coupled system: full Newton for one stage,
        // simplified (matrix at the predictor) for several.
        const NewtonPolicy policy = s >= 2 ? NewtonPolicy::simplified : NewtonPolicy::full;
        const int it = nw.solve(policy, c_, [&](bool refresh) {
            for (int j = 0; j < s; ++j) {
                const double tj = t + c[j] * h_;
                x_ = X.segment(j * d_, d_);
                prob_.rhs(tj, x_, f_);
                Fs_.col(j) = f_;
                if (refresh) {
                    prob_.rhs_jacobian(tj, x_, J_);
                    Js_.middleCols(j * d_, d_) = J_;
                }
            }
            c_.rhs_evals += s;
            if (refresh) c_.jac_evals += s;
            for (int i = 0; i < s; ++i) {
                auto Ri = nw.R.segment(i * d_, d_);
                Ri = X.segment(i * d_, d_) - W_.col(i);
                for (int j = 0; j < s; ++j) {
                    if (A(i, j) != 0.0) Ri -= (h_ * A(i, j)) * Fs_.col(j);
                    if (refresh)
                        nw.S.block(i * d_, j * d_, d_, d_) =
                            -(h_ * A(i, j)) * Js_.middleCols(j * d_, d_);
                }
                if (refresh) nw.S.block(i * d_, i * d_, d_, d_).diagonal().array() += 1.0;
            }
        });
        if (it == 0) return false;
        iters += it;
        for (int i = 0; i < s; ++i) Y_.col(i) = X.segment(i * d_, d_);
        if (plan.invertible) { // h F = (Y − W) A⁻ᵀ column-wise, i.e. hF = A⁻¹(Y − U y)
            W_.leftCols(s) = Y_.leftCols(s) - W_.leftCols(s);
            F_.leftCols(s).noalias() = (1.0 / h_) * (W_.leftCols(s) * plan.A_inv_T);
        } else {
            for (int i = 0; i < s; ++i) {
                x_ = Y_.col(i);
                prob_.rhs(t + c[i] * h_, x_, f_);
                F_.col(i) = f_;
            }
            c_.rhs_evals += s;
        }
        return true;
    }

    const P& prob_;
    const GlmCoefficients& m_;
    int d_;
    double h_;
    Counters& c_;
    bool started_ = false;
    Plan main_, start_;
    Mat y_, yin_, yout_; // d × r: the values after the last step, this step's input and output
    Mat Y_, F_, W_;      // d × s: stages, stage derivatives, U y (+ known explicit part)
    Vec f_, w_, x_;
    Mat J_;
    StageNewton stage_newton_;                 // one stage of a triangular A (d unknowns)
    StageNewton coupled_main_, coupled_start_; // all stages of a full A (s·d, s₀·d unknowns)
    Mat Fs_, Js_;                              // f and ∂f at the stages (coupled solve)
};

} // namespace dampsym
