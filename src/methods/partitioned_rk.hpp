// Generic partitioned Runge–Kutta kernel (HLW II.2) for separable problems, on the full damped
// vector field in the Rayleigh form of SPEC §1:
//   q' = g(p) = ∇T(p),   p' = F(t, q) − 2γ(t) p,
// with a tableau (A, b, c) for q (MethodInfo::tableau) and (Â, b̂, ĉ) for p (tableau_p):
//   Q_i = q + h Σ_j a_ij g(P_j),
//   P_i = p + h Σ_j â_ij (F(t_j, Q_j) − 2γ(t_j) P_j),        t_j = t + c_j h,
//   q₁  = q + h Σ_i b_i g(P_i),   p₁ = p + h Σ_i b̂_i (F(t_i, Q_i) − 2γ(t_i) P_i).
// Time is a position variable (t' = 1 integrated with the q tableau), so the stage times are
// t + c_i h with c from the q tableau.
// Catalog rows (γ = 0 gives HLW's methods; with γ ≠ 0 they are the same schemes on the full field):
//   symplectic-euler          HLW(1.8): p₁ = p − h H_q(p₁, q), q₁ = q + h H_p(p₁, q);
//                             q: explicit Euler (A = 0, b = 1, c = 0), p: implicit Euler (Â = 1).
//                             With damping, P₁ = (p + h F(t, q)) / (1 + 2hγ(t)).
//   symplectic-euler-adjoint  HLW(1.9): q₁ = q + h H_p(p, q₁), p₁ = p − h H_q(p, q₁);
//                             q: implicit Euler (A = 1, c = 1), p: explicit Euler (Â = 0).
//   stormer-verlet            HLW(3.6): p½ = p − (h/2)∇V(q), q₁ = q + h ∇T(p½),
//                             p₁ = p½ − (h/2)∇V(q₁), as the Lobatto IIIA (q) – IIIB (p) pair.
//
// Solution of the stages. p' is linear in p, so a P stage whose forces F_j are known is a linear
// equation; when the pair can be ordered so that every Q_i needs only P stages already known and
// every P_i only forces already known and P_j (j ≠ i) already known, the step is computed in that
// order (the schedule is found once, in the constructor), P_i by the exact linear solve
//   (1 + 2h â_ii γ(t_i)) P_i = p + h Σ_j â_ij F_j − 2h Σ_{j≠i} â_ij γ(t_j) P_j,
// with one force evaluation per stage whose force is used (symplectic Euler and its adjoint: 1 per
// step; Störmer–Verlet: 2 per step, F(t, q_n) and F(t + h, q_{n+1}); no FSAL reuse). Any other
// pair (e.g. Gauss for both, or 3-stage Lobatto IIIA–IIIB) is solved by Newton's method on all
// stages (Q_1..Q_s, P_1..P_s) with the analytic Jacobians hess_T and force_jacobian, converged to
// round-off as in cimp.hpp, s force evaluations per iteration plus s for the update; no convergence
// in 50 iterations, or a NaN, returns StepStatus::solve_failed with z unchanged.
//
// Exact step Jacobian: the implicit-function theorem on the stage equations at the computed stages
// (whichever path computed them), with hess_T and force_jacobian at the stages (s evaluations of
// each), then the derivative of the update.
#pragma once

#include "core/method.hpp"
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
class PartitionedRK {
public:
    static constexpr std::string_view kernel_id = "partitioned-rk";
    template <class Q>
    static constexpr bool applies = Q::has_separable; // needs grad_T, force and their Jacobians
    static constexpr bool has_step_jacobian = true;
    static constexpr int max_iterations = 50;

    PartitionedRK(const P& problem, const MethodInfo& info, double h, Counters& counters)
        : prob_(problem), tq_(checked(info)), tp_(*info.tableau_p), s_(tq_.stages), n_(problem.n()),
          h_(h), c_(counters), gam_(s_), Q_(ui(s_), Vec(n_)), P_(ui(s_), Vec(n_)),
          F_(ui(s_), Vec(n_)), gP_(ui(s_), Vec(n_)), HT_(ui(s_), Mat(n_, n_)),
          JF_(ui(s_), Mat(n_, n_)), acc_(n_), X_(2 * s_ * n_), R_(2 * s_ * n_), dX_(2 * s_ * n_),
          S_(2 * s_ * n_, 2 * s_ * n_), lu_(2 * s_ * n_), B_(Mat::Zero(2 * s_ * n_, 2 * n_)),
          dX2_(2 * s_ * n_, 2 * n_) {
        for (int i = 0; i < s_; ++i) {
            bool used = tp_.b[ui(i)] != 0.0;
            for (int k = 0; k < s_; ++k) used = used || tp_.A(k, i) != 0.0;
            need_force_.push_back(used);
        }
        build_schedule();
        // ∂R/∂z for the implicit-function theorem: R_Q_i depends on q (−I), R_P_i on p (−I).
        for (int i = 0; i < s_; ++i) {
            B_.block(i * n_, 0, n_, n_).setIdentity();
            B_.block((s_ + i) * n_, n_, n_, n_).setIdentity();
        }
    }

    bool scheduled() const { return !schedule_.empty(); }

    StepStatus step(double t, Vec& z) {
        for (int i = 0; i < s_; ++i) gam_[i] = prob_.gamma_at(stage_time(t, i));
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
        // q₁ = q + h Σ b_i g(P_i),  p₁ = p + h Σ b̂_i (F_i − 2γ_i P_i).
        auto q = z.head(n_);
        auto p = z.tail(n_);
        for (int i = 0; i < s_; ++i) {
            if (tq_.b[ui(i)] != 0.0) q += (h_ * tq_.b[ui(i)]) * gP_[ui(i)];
            if (tp_.b[ui(i)] != 0.0) {
                acc_ = F_[ui(i)] - (2.0 * gam_[i]) * P_[ui(i)];
                p += (h_ * tp_.b[ui(i)]) * acc_;
            }
        }
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
        Psi.resize(2 * n_, 2 * n_);
        Psi.setIdentity();
        for (int i = 0; i < s_; ++i) {
            const auto dQ = dX2_.middleRows(i * n_, n_);
            const auto dP = dX2_.middleRows((s_ + i) * n_, n_);
            if (tq_.b[ui(i)] != 0.0)
                Psi.topRows(n_).noalias() += (h_ * tq_.b[ui(i)]) * HT_[ui(i)] * dP;
            if (tp_.b[ui(i)] != 0.0) {
                Psi.bottomRows(n_).noalias() += (h_ * tp_.b[ui(i)]) * JF_[ui(i)] * dQ;
                Psi.bottomRows(n_) -= (2.0 * h_ * tp_.b[ui(i)] * gam_[i]) * dP;
            }
        }
        return StepStatus::ok;
    }

private:
    static std::size_t ui(int i) { return static_cast<std::size_t>(i); }

    static const ButcherTableau& checked(const MethodInfo& info) {
        if (info.tableau == nullptr || info.tableau_p == nullptr ||
            info.tableau->stages != info.tableau_p->stages)
            throw std::invalid_argument("partitioned-rk: method needs two tableaux with the same "
                                        "number of stages");
        return *info.tableau;
    }

    double stage_time(double t, int i) const { return t + tq_.c[ui(i)] * h_; }

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
                        if (tq_.A(i, j) != 0.0 && !pd[ui(j)]) ready = false;
                    if (ready) {
                        qd[ui(i)] = true;
                        order.push_back(i);
                        progress = true;
                    }
                }
                if (!pd[ui(i)]) {
                    bool ready = true;
                    for (int j = 0; j < s_; ++j)
                        if (tp_.A(i, j) != 0.0 && (!qd[ui(j)] || (j != i && !pd[ui(j)])))
                            ready = false;
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

    // Q_i = q + h Σ_j a_ij g(P_j) (all needed P_j known), then F_i if it is used.
    void q_stage(double t, const Vec& z, int i) {
        Q_[ui(i)] = z.head(n_);
        for (int j = 0; j < s_; ++j)
            if (tq_.A(i, j) != 0.0) Q_[ui(i)] += (h_ * tq_.A(i, j)) * gP_[ui(j)];
        if (need_force_[ui(i)]) force(t, i);
    }

    // (1 + 2h â_ii γ_i) P_i = p + h Σ_j â_ij F_j − 2h Σ_{j≠i} â_ij γ_j P_j, then g(P_i).
    void p_stage(const Vec& z, int i) {
        acc_ = z.tail(n_);
        for (int j = 0; j < s_; ++j) {
            const double a = tp_.A(i, j);
            if (a == 0.0) continue;
            acc_ += (h_ * a) * F_[ui(j)];
            if (j != i) acc_ -= (2.0 * h_ * a * gam_[j]) * P_[ui(j)];
        }
        P_[ui(i)] = acc_ / (1.0 + 2.0 * h_ * tp_.A(i, i) * gam_[i]);
        prob_.grad_T(P_[ui(i)], gP_[ui(i)]);
    }

    void stage_jacobians(double t) {
        for (int i = 0; i < s_; ++i) {
            prob_.hess_T(P_[ui(i)], HT_[ui(i)]);
            prob_.force_jacobian(stage_time(t, i), Q_[ui(i)], JF_[ui(i)]);
        }
        c_.jac_evals += s_;
    }

    // Jacobian of the stage residuals R = (R_Q, R_P) with respect to (Q_1..Q_s, P_1..P_s):
    //   ∂R_Q_i/∂Q_k = δ_ik I,  ∂R_Q_i/∂P_j = −h a_ij ∇²T(P_j),
    //   ∂R_P_i/∂Q_j = −h â_ij ∂F(t_j, Q_j),  ∂R_P_i/∂P_j = δ_ij I + 2h â_ij γ_j I.
    void assemble_newton_matrix() {
        S_.setIdentity();
        for (int i = 0; i < s_; ++i)
            for (int j = 0; j < s_; ++j) {
                S_.block(i * n_, (s_ + j) * n_, n_, n_) = -(h_ * tq_.A(i, j)) * HT_[ui(j)];
                S_.block((s_ + i) * n_, j * n_, n_, n_) = -(h_ * tp_.A(i, j)) * JF_[ui(j)];
                S_.block((s_ + i) * n_, (s_ + j) * n_, n_, n_).diagonal().array() +=
                    2.0 * h_ * tp_.A(i, j) * gam_[j];
            }
    }

    bool newton(double t, const Vec& z) {
        for (int i = 0; i < s_; ++i) {
            Q_[ui(i)] = z.head(n_);
            P_[ui(i)] = z.tail(n_);
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
                acc_ = Q_[ui(i)] - z.head(n_);
                for (int j = 0; j < s_; ++j) acc_ -= (h_ * tq_.A(i, j)) * gP_[ui(j)];
                R_.segment(i * n_, n_) = acc_;
                acc_ = P_[ui(i)] - z.tail(n_);
                for (int j = 0; j < s_; ++j) {
                    acc_ -= (h_ * tp_.A(i, j)) * F_[ui(j)];
                    acc_ += (2.0 * h_ * tp_.A(i, j) * gam_[j]) * P_[ui(j)];
                }
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
    const ButcherTableau& tq_;
    const ButcherTableau& tp_;
    int s_, n_;
    double h_;
    Counters& c_;
    std::vector<int> schedule_;
    std::vector<bool> need_force_;
    Vec gam_;
    std::vector<Vec> Q_, P_, F_, gP_;
    std::vector<Mat> HT_, JF_;
    Vec acc_, X_, R_, dX_;
    Mat S_;
    Eigen::PartialPivLU<Mat> lu_;
    Mat B_, dX2_;
};

} // namespace dampsym
