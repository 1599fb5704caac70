// Generic partitioned exponential Runge–Kutta kernel (PERK), B(2.14), for separable problems in the
// Rayleigh form of SPEC §1, q' = ∇T(p), p' = F(q, t) − 2γp (F = −∇_q V + forcing). B writes this
// system as B(2.17), q' = ∇T(p), p' = −∇V − γ_B p, i.e. B(1.2) with γ^1 = 0 and γ^2 = γ_B, where
// γ_B = 2γ: B's γ in (2.17)–(2.22) is TWICE ours. The data of B(2.18)–(2.22) are kept exactly as B
// prints them, as functions of x_B = γ_B h; the conversion x_B = 2γh is made once, in
// perk_coefficients() (src/methods/exponential_tableaux.cpp), called by this kernel's constructor.
// With the hat tableau (Â, b̂, φ̂, φ̂_0, ĉ) for q and the tilde tableau (Ã, b̃, φ̃, φ̃_0) for p,
// B(2.14) with F(Q, P) = ∇T(P) and G(Q, P) = F(Q, t) reads
//   Q_i     = φ̂_i q_n + h Σ_j â_ij ∇T(P_j),
//   P_i     = φ̃_i p_n + h Σ_j ã_ij F(Q_j, t_n + ĉ_j h),
//   q_{n+1} = φ̂_0 q_n + h Σ_i b̂_i ∇T(P_i),
//   p_{n+1} = φ̃_0 p_n + h Σ_i b̃_i F(Q_i, t_n + ĉ_i h).                                   B(2.14)
// The damping is carried entirely by the coefficients, so P_i depends on the Q stages only and
// Q_i on the P stages only. Stage times use ĉ (time integrated with the q tableau, as in
// partitioned_rk.hpp). Catalog rows (data in exponential_tableaux.hpp): cse-if B(2.18), cse-etd
// B(2.19), csv1-perk B(2.20) (= csv1 F(2.12)), csv2-perk B(2.21) (= csv2 F(2.16), with the
// e^{−γ_B h/4} that B's print drops from the q tableau), etdprk2 B(2.22) (negative control: not
// conformal symplectic, B after Thm 2.11).
//
// Damping argument: as exponential_rk.hpp. Constant γ: coefficients evaluated once at
// γh = problem.dGamma(0, h). Time-dependent γ (hill): re-evaluated at every step at
// x_n = Γ(t_n + h) − Γ(t_n) (γ frozen at its mean over the step), which keeps φ̂_0 φ̃_0 = e^{−2x_n}
// and the conformal symplectic structure at exactly the physical factor, with order min(p, 2).
// The stage schedule depends only on which coefficients are structurally non-zero, found once.
//
// Solution of the stages. When the stages can be ordered so that every Q_i needs only P stages
// already known and every P_i only forces of Q stages already known (all rows of B Example 2.2),
// the step is explicit in that order (found once, in the constructor); F is evaluated once for
// each Q stage whose force is used (column of Ã or b̃ not zero): 1 per step for cse-if/cse-etd,
// 2 for csv1-perk/csv2-perk/etdprk2, counted in Counters::rhs_evals as for csv1. Otherwise the
// 2s·n stage equations are solved by Newton's method with hess_T and force_jacobian, converged to
// round-off as in partitioned_rk.hpp; no convergence in 50 iterations, or a NaN, returns
// StepStatus::solve_failed with z unchanged (never throws).
//
// Exact step Jacobian: the implicit-function theorem on the stage equations at the computed
// stages, with ∂R_Q_i/∂P_j = −h â_ij ∇²T(P_j), ∂R_P_i/∂Q_j = −h ã_ij ∂F(Q_j), right-hand side
// ∂Q_i/∂q = φ̂_i I, ∂P_i/∂p = φ̃_i I, then
//   ∂q_{n+1} = [φ̂_0 I, 0] + h Σ b̂_i ∇²T(P_i) ∂P_i,   ∂p_{n+1} = [0, φ̃_0 I] + h Σ b̃_i ∂F(Q_i) ∂Q_i.
#pragma once

#include "core/method.hpp"
#include "core/problem.hpp" // detail::declares_constant_gamma
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
class PartitionedExponentialRK {
public:
    static constexpr std::string_view kernel_id = "partitioned-exponential-rk";
    template <class Q>
    static constexpr bool applies = [] {
        if constexpr (requires { Q::has_separable; })
            return Q::has_separable;
        else
            return false;
    }();
    static constexpr bool has_step_jacobian = true;
    static constexpr int max_iterations = 50;

    PartitionedExponentialRK(const P& problem, const MethodInfo& info, double h, Counters& counters)
        : prob_(problem), s_(checked(info).stages), n_(problem.n()), h_(h), c_(counters),
          Q_(ui(s_), Vec(n_)), P_(ui(s_), Vec(n_)), F_(ui(s_), Vec(n_)), gP_(ui(s_), Vec(n_)),
          HT_(ui(s_), Mat(n_, n_)), JF_(ui(s_), Mat(n_, n_)), acc_(n_), X_(2 * s_ * n_),
          R_(2 * s_ * n_), dX_(2 * s_ * n_), S_(2 * s_ * n_, 2 * s_ * n_), lu_(2 * s_ * n_),
          B_(Mat::Zero(2 * s_ * n_, 2 * n_)), dX2_(2 * s_ * n_, 2 * n_), data_(checked(info)) {
        set_argument(problem.dGamma(0.0, h));
        for (int j = 0; j < s_; ++j) {
            bool force_used = tilde_.b[j] != 0.0;
            for (int i = 0; i < s_; ++i) force_used = force_used || tilde_.A(i, j) != 0.0;
            need_force_.push_back(force_used);
        }
        build_schedule();
    }

    const ExponentialTableau& hat() const { return hat_; }
    const ExponentialTableau& tilde() const { return tilde_; }
    bool scheduled() const { return !schedule_.empty(); }

    StepStatus step(double t, Vec& z) {
        if constexpr (!detail::declares_constant_gamma<P>()) set_argument(prob_.dGamma(t, h_));
        if (scheduled()) {
            for (const int task : schedule_) {
                if (task < s_)
                    q_stage(t, z, task);
                else
                    p_stage(z, task - s_);
            }
        } else {
            if (!newton(t, z)) return StepStatus::solve_failed;
            for (int i = 0; i < s_; ++i) {
                if (need_force_[ui(i)]) force(t, i);
                prob_.grad_T(P_[ui(i)], gP_[ui(i)]);
            }
        }
        // q₁ = φ̂_0 q + h Σ b̂_i ∇T(P_i),  p₁ = φ̃_0 p + h Σ b̃_i F_i.
        auto q = z.head(n_);
        auto p = z.tail(n_);
        acc_.setZero();
        for (int i = 0; i < s_; ++i)
            if (hat_.b[i] != 0.0) acc_ += hat_.b[i] * gP_[ui(i)];
        q = hat_.phi0 * q + h_ * acc_;
        acc_.setZero();
        for (int i = 0; i < s_; ++i)
            if (tilde_.b[i] != 0.0) acc_ += (h_ * tilde_.b[i]) * F_[ui(i)];
        p = tilde_.phi0 * p + acc_;
        return StepStatus::ok;
    }

    // Advances z exactly as step() and writes Psi = ∂z₁/∂z₀ (implicit-function theorem).
    StepStatus step_jacobian(double t, Vec& z, Mat& Psi) {
        const StepStatus st = step(t, z);
        if (st != StepStatus::ok) return st;
        stage_jacobians(t);
        assemble_newton_matrix();
        lu_.compute(S_);
        dX2_ = lu_.solve(B_); // rows: dQ_1..dQ_s, dP_1..dP_s, each n × 2n
        Psi.setZero(2 * n_, 2 * n_);
        Psi.topLeftCorner(n_, n_).diagonal().setConstant(hat_.phi0);
        Psi.bottomRightCorner(n_, n_).diagonal().setConstant(tilde_.phi0);
        for (int i = 0; i < s_; ++i) {
            const auto dQ = dX2_.middleRows(i * n_, n_);
            const auto dP = dX2_.middleRows((s_ + i) * n_, n_);
            if (hat_.b[i] != 0.0) Psi.topRows(n_).noalias() += (h_ * hat_.b[i]) * HT_[ui(i)] * dP;
            if (tilde_.b[i] != 0.0)
                Psi.bottomRows(n_).noalias() += (h_ * tilde_.b[i]) * JF_[ui(i)] * dQ;
        }
        return StepStatus::ok;
    }

private:
    static std::size_t ui(int i) { return static_cast<std::size_t>(i); }

    static const PartitionedExponentialRKData& checked(const MethodInfo& info) {
        const auto* data = static_cast<const PartitionedExponentialRKData*>(info.family_data);
        if (data == nullptr || data->stages < 1 || data->coefficients_B == nullptr)
            throw std::invalid_argument(
                "partitioned-exponential-rk: method row has no PERK coefficient data");
        return *data;
    }

    // Both tableaux at the damping argument x (our γh, or ΔΓ_n); perk_coefficients converts to
    // B's x_B = 2x (the one place). Recomputed only when x changes; nothing is allocated.
    void set_argument(double x) {
        if (x == x_) return;
        x_ = x;
        perk_coefficients(data_, x, hat_, tilde_);
        for (int i = 0; i < s_; ++i) {
            B_.block(i * n_, 0, n_, n_).diagonal().setConstant(hat_.phi[i]);
            B_.block((s_ + i) * n_, n_, n_, n_).diagonal().setConstant(tilde_.phi[i]);
        }
    }

    double stage_time(double t, int i) const { return t + hat_.c[i] * h_; }

    // Greedy order of the tasks Q_i (code i: Q_i and its force) and P_i (code s + i); empty when
    // no order exists (then Newton).
    void build_schedule() {
        std::vector<bool> qd(ui(s_), false), pd(ui(s_), false);
        std::vector<int> order;
        bool progress = true;
        while (progress && static_cast<int>(order.size()) < 2 * s_) {
            progress = false;
            for (int i = 0; i < s_; ++i) {
                if (!qd[ui(i)]) {
                    bool ready = true;
                    for (int j = 0; j < s_; ++j)
                        if (hat_.A(i, j) != 0.0 && !pd[ui(j)]) ready = false;
                    if (ready) {
                        qd[ui(i)] = true;
                        order.push_back(i);
                        progress = true;
                    }
                }
                if (!pd[ui(i)]) {
                    bool ready = true;
                    for (int j = 0; j < s_; ++j)
                        if (tilde_.A(i, j) != 0.0 && !qd[ui(j)]) ready = false;
                    if (ready) {
                        pd[ui(i)] = true;
                        order.push_back(s_ + i);
                        progress = true;
                    }
                }
            }
        }
        if (static_cast<int>(order.size()) == 2 * s_) schedule_ = order;
    }

    void force(double t, int i) {
        prob_.force(stage_time(t, i), Q_[ui(i)], F_[ui(i)]);
        c_.rhs_evals += 1;
    }

    // Q_i = φ̂_i q + h Σ_j â_ij ∇T(P_j), then F(Q_i) if it is used.
    void q_stage(double t, const Vec& z, int i) {
        Q_[ui(i)] = hat_.phi[i] * z.head(n_);
        for (int j = 0; j < s_; ++j)
            if (hat_.A(i, j) != 0.0) Q_[ui(i)] += (h_ * hat_.A(i, j)) * gP_[ui(j)];
        if (need_force_[ui(i)]) force(t, i);
    }

    // P_i = φ̃_i p + h Σ_j ã_ij F_j, then ∇T(P_i).
    void p_stage(const Vec& z, int i) {
        P_[ui(i)] = tilde_.phi[i] * z.tail(n_);
        for (int j = 0; j < s_; ++j)
            if (tilde_.A(i, j) != 0.0) P_[ui(i)] += (h_ * tilde_.A(i, j)) * F_[ui(j)];
        prob_.grad_T(P_[ui(i)], gP_[ui(i)]);
    }

    void stage_jacobians(double t) {
        for (int i = 0; i < s_; ++i) {
            HT_[ui(i)].setZero(); // problems may fill a part (as SeparableProblem::N_jacobian)
            prob_.hess_T(P_[ui(i)], HT_[ui(i)]);
            JF_[ui(i)].setZero();
            prob_.force_jacobian(stage_time(t, i), Q_[ui(i)], JF_[ui(i)]);
        }
        c_.jac_evals += s_;
    }

    // ∂R/∂(Q_1..Q_s, P_1..P_s): identity plus −h â_ij ∇²T(P_j) (Q rows, P columns) and
    // −h ã_ij ∂F(Q_j) (P rows, Q columns).
    void assemble_newton_matrix() {
        S_.setIdentity();
        for (int i = 0; i < s_; ++i)
            for (int j = 0; j < s_; ++j) {
                S_.block(i * n_, (s_ + j) * n_, n_, n_) = -(h_ * hat_.A(i, j)) * HT_[ui(j)];
                S_.block((s_ + i) * n_, j * n_, n_, n_) = -(h_ * tilde_.A(i, j)) * JF_[ui(j)];
            }
    }

    bool newton(double t, const Vec& z) {
        for (int i = 0; i < s_; ++i) {
            Q_[ui(i)] = hat_.phi[i] * z.head(n_);
            P_[ui(i)] = tilde_.phi[i] * z.tail(n_);
            X_.segment(i * n_, n_) = Q_[ui(i)];
            X_.segment((s_ + i) * n_, n_) = P_[ui(i)];
        }
        double previous = std::numeric_limits<double>::infinity();
        for (int it = 1; it <= max_iterations; ++it) {
            for (int j = 0; j < s_; ++j) {
                prob_.force(stage_time(t, j), Q_[ui(j)], F_[ui(j)]);
                prob_.grad_T(P_[ui(j)], gP_[ui(j)]);
            }
            c_.rhs_evals += s_;
            stage_jacobians(t);
            c_.newton_iters += 1;
            for (int i = 0; i < s_; ++i) {
                acc_ = Q_[ui(i)] - hat_.phi[i] * z.head(n_);
                for (int j = 0; j < s_; ++j) acc_ -= (h_ * hat_.A(i, j)) * gP_[ui(j)];
                R_.segment(i * n_, n_) = acc_;
                acc_ = P_[ui(i)] - tilde_.phi[i] * z.tail(n_);
                for (int j = 0; j < s_; ++j) acc_ -= (h_ * tilde_.A(i, j)) * F_[ui(j)];
                R_.segment((s_ + i) * n_, n_) = acc_;
            }
            assemble_newton_matrix();
            lu_.compute(S_);
            dX_ = lu_.solve(R_);
            X_ -= dX_;
            for (int i = 0; i < s_; ++i) {
                Q_[ui(i)] = X_.segment(i * n_, n_);
                P_[ui(i)] = X_.segment((s_ + i) * n_, n_);
            }
            const double step_norm = dX_.cwiseAbs().maxCoeff();
            const double scale = std::max(X_.cwiseAbs().maxCoeff(), 1e-300);
            if (!(step_norm == step_norm) || !std::isfinite(scale)) return false;
            if (newton_converged(step_norm, scale, previous)) {
                c_.max_newton_iters_per_step = std::max(c_.max_newton_iters_per_step, it);
                return true;
            }
            previous = step_norm;
        }
        return false;
    }

    const P& prob_;
    int s_, n_;
    double h_;
    Counters& c_;
    ExponentialTableau hat_, tilde_;
    std::vector<int> schedule_;
    std::vector<bool> need_force_;
    std::vector<Vec> Q_, P_, F_, gP_;
    std::vector<Mat> HT_, JF_;
    Vec acc_, X_, R_, dX_;
    Mat S_;
    Eigen::PartialPivLU<Mat> lu_;
    Mat B_, dX2_;
    const PartitionedExponentialRKData& data_;
    double x_ = std::numeric_limits<double>::quiet_NaN();
};

} // namespace dampsym
