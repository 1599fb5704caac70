// The one partitioned Runge–Kutta engine (HLW II.2; B(2.14)) behind the partitioned RK and the
// partitioned exponential RK kernels, for separable problems in the Rayleigh form
//   q' = g(p) = ∇T(p),   p' = F(t, q) − 2γ(t) p.
// With a tableau (Â, b̂, ĉ, φ̂, φ̂_0) for q and (Ã, b̃, φ̃, φ̃_0) for p, supplied per step by a
// coefficient provider, the stages and the update are
//   Q_i = φ̂_i q + h Σ_j â_ij g(P_j),
//   P_i = φ̃_i p + h Σ_j ã_ij (F(t_j, Q_j) − δ 2γ(t_j) P_j),        t_j = t + ĉ_j h,
//   q₁  = φ̂_0 q + h Σ_i b̂_i g(P_i),   p₁ = φ̃_0 p + h Σ_i b̃_i (F(t_i, Q_i) − δ 2γ(t_i) P_i),
// where δ = 1 when the damping is in the vector field (constant tableaux, partitioned_rk.hpp:
// φ = 1) and δ = 0 when the coefficients carry it (exponential coefficients,
// partitioned_exponential_rk.hpp). Time is a position variable (t' = 1 integrated with the q
// tableau), so the stage times use ĉ.
//
// Solution of the stages. p' is linear in p, so a P stage whose forces are known is a linear
// equation; when the stages can be ordered so that every Q_i needs only P stages already known and
// every P_i only forces already known (and, for δ = 1, P_j (j ≠ i) already known), the step is
// computed in that order (the schedule is found once, from the structurally non-zero coefficients),
// P_i by the exact linear solve
//   (1 + 2h ã_ii δγ(t_i)) P_i = φ̃_i p + h Σ_j ã_ij F_j − 2h δ Σ_{j≠i} ã_ij γ(t_j) P_j,
// with one force evaluation per Q stage whose force is used (a column of Ã or b̃ not zero). Any
// other pair is solved by the stage-Newton solver (newton.hpp, full policy) on all stages
// (Q_1..Q_s, P_1..P_s) with the analytic Jacobians hess_T and force_jacobian: s force evaluations
// per iteration plus s for the update; no convergence, or a NaN/inf, returns
// StepStatus::solve_failed with z unchanged.
//
// The scheduled path runs a flat program compiled from the schedule (compile_program: the
// structurally non-zero coefficients with their products of h, recompiled only when the provider
// changes the coefficients), and for a problem with a compile-time size (static_dof) the stage
// vectors are fixed-size. For such a problem the shapes of kShapes (schedule and coefficient
// structure of symplectic Euler, its adjoint and the Lobatto IIIA q tableau, with constant or
// exponential p coefficients) are also compiled as straight-line code with the same operations
// (partitioned_shapes.hpp), and the integration loop is compiled once per shape
// (specialised_steps, core/integrate.hpp); on the Lobatto IIIA-IIIB shape the force at Q₂ = q₁ is
// reused by the next step (ForceMemo).
//
// Exact step Jacobian: the implicit-function theorem on the stage equations at the computed
// stages (whichever path computed them), with hess_T and force_jacobian at the stages (s
// evaluations of each), right-hand side ∂Q_i/∂q = φ̂_i I, ∂P_i/∂p = φ̃_i I, then the derivative of
// the update.
#pragma once

#include "core/method.hpp"
#include "core/problem.hpp"
#include "methods/exponential_tableaux.hpp"
#include "methods/newton.hpp"
#include "methods/partitioned_program.hpp"
#include "methods/partitioned_shapes.hpp"

#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

namespace dampsym {

// Provider interface (partitioned_rk.hpp, partitioned_exponential_rk.hpp):
//   static constexpr bool rayleigh_damping;   δ above
//   int stages() const;
//   template <class P> void init(const P&, double h, ExponentialTableau& hat,
//                                ExponentialTableau& tilde);
//   template <class P> bool at_step(const P&, double t, double h, ExponentialTableau&,
//                                   ExponentialTableau&);   true when the coefficients changed
template <class P, class Provider>
class PartitionedEngine {
public:
    static constexpr bool has_step_jacobian = true;

    PartitionedEngine(const P& problem, Provider provider, double h, Counters& counters)
        : prob_(problem), pv_(std::move(provider)), s_(pv_.stages()), n_(problem.n()), h_(h),
          c_(counters), gam_(Vec::Zero(s_)), Q_(ui(s_), VecN::Zero(n_)), P_(ui(s_), VecN::Zero(n_)),
          F_(ui(s_), VecN::Zero(n_)), gP_(ui(s_), VecN::Zero(n_)), HT_(ui(s_), Mat(n_, n_)),
          JF_(ui(s_), Mat(n_, n_)), acc_(VecN::Zero(n_)), newton_(2 * s_ * n_),
          B_(Mat::Zero(2 * s_ * n_, 2 * n_)), dX2_(2 * s_ * n_, 2 * n_) {
        pv_.init(problem, h, hat_, tilde_);
        prog_.build(hat_, tilde_);
        compile_program();
    }

    const ExponentialTableau& hat() const { return hat_; }
    const ExponentialTableau& tilde() const { return tilde_; }
    bool scheduled() const { return prog_.scheduled(); }

    // One step by the program (every caller but the bare integration loop, which runs the
    // compiled shape when there is one: the same numbers).
    StepStatus step(double t, Vec& z) { return step_program(t, z); }

    // The bare integration loop (core/integrate.hpp, no observer) runs on the compiled shape's
    // step: one loop per shape.
    static constexpr bool specialised_steps = static_dof<P>() != Eigen::Dynamic;
    template <class F>
    [[gnu::always_inline]] inline decltype(auto) with_specialised_step(F&& f) {
        return with_shape(std::forward<F>(f));
    }

    // The schedule run by the interpreted program (or Newton), stages kept in the members.
    StepStatus step_program(double t, Vec& z) {
        if (pv_.at_step(prob_, t, h_, hat_, tilde_)) compile_program();
        return step_program_now(t, z);
    }
    StepStatus step_program_now(double t, Vec& z) {
        if constexpr (damped)
            for (int i = 0; i < s_; ++i) gam_[i] = prob_.gamma_at(stage_time(t, i));
        if (scheduled()) {
            for (const Task& task : prog_.program) {
                if (task.q)
                    q_stage(t, z, task);
                else
                    p_stage(z, task);
            }
        } else {
            if (!solve_stages(t, z)) return StepStatus::solve_failed;
            for (int i = 0; i < s_; ++i) {
                if (prog_.need_force[ui(i)]) force(t, i);
                prob_.grad_T(P_[ui(i)], gP_[ui(i)]);
            }
        }
        update(z);
        return StepStatus::ok;
    }

    // Advances z exactly as step() and writes Psi = ∂z₁/∂z₀ (implicit-function theorem).
    StepStatus step_jacobian(double t, Vec& z, Mat& Psi) {
        const StepStatus st = step_program(t, z);
        if (st != StepStatus::ok) return st;
        stage_jacobians(t);
        assemble_newton_matrix();
        for (int i = 0; i < s_; ++i) {
            B_.block(i * n_, 0, n_, n_).diagonal().setConstant(hat_.phi[i]);
            B_.block((s_ + i) * n_, n_, n_, n_).diagonal().setConstant(tilde_.phi[i]);
        }
        newton_.factor_and_solve(B_, dX2_); // rows: dQ_1..dQ_s, dP_1..dP_s, each n × 2n
        Psi.setZero(2 * n_, 2 * n_);
        Psi.topLeftCorner(n_, n_).diagonal().setConstant(hat_.phi0);
        Psi.bottomRightCorner(n_, n_).diagonal().setConstant(tilde_.phi0);
        for (int i = 0; i < s_; ++i) {
            const auto dQ = dX2_.middleRows(i * n_, n_);
            const auto dP = dX2_.middleRows((s_ + i) * n_, n_);
            if (hat_.b[i] != 0.0) Psi.topRows(n_).noalias() += (h_ * hat_.b[i]) * HT_[ui(i)] * dP;
            if (tilde_.b[i] != 0.0) {
                Psi.bottomRows(n_).noalias() += (h_ * tilde_.b[i]) * JF_[ui(i)] * dQ;
                if constexpr (damped) Psi.bottomRows(n_) -= (2.0 * h_ * tilde_.b[i] * gam_[i]) * dP;
            }
        }
        return StepStatus::ok;
    }

private:
    static constexpr bool damped = Provider::rayleigh_damping;
    static constexpr int N = static_dof<P>();
    using VecN = Eigen::Matrix<double, N, 1>;

    using Task = PartitionedProgram::Task;
    using Term = PartitionedProgram::Term;
    using Weight = PartitionedProgram::Weight;

    static std::size_t ui(int i) { return static_cast<std::size_t>(i); }

    double stage_time(double t, int i) const { return t + hat_.c[i] * h_; }
    auto q_of(Vec& z) const { return z.template head<N>(n_); }
    auto p_of(Vec& z) const { return z.template segment<N>(n_, n_); }

    void force(double t, int i) {
        prob_.force(stage_time(t, i), Q_[ui(i)], F_[ui(i)]);
        c_.rhs_evals += 1;
    }

    // Q_i = φ̂_i q + h Σ_j â_ij g(P_j) (all needed P_j known), then F_i if it is used.
    void q_stage(double t, Vec& z, const Task& task) {
        VecN& Q = Q_[ui(task.i)];
        Q = task.phi * q_of(z);
        for (std::size_t k = task.first; k < task.last; ++k)
            Q += prog_.terms[k].coef * gP_[ui(prog_.terms[k].j)];
        if (task.force) force(t, task.i);
    }

    // (1 + 2h ã_ii δγ_i) P_i = φ̃_i p + h Σ_j ã_ij F_j − 2h δ Σ_{j≠i} ã_ij γ_j P_j, then g(P_i).
    void p_stage(Vec& z, const Task& task) {
        const int i = task.i;
        acc_ = task.phi * p_of(z);
        for (std::size_t k = task.first; k < task.last; ++k) {
            const Term& term = prog_.terms[k];
            acc_ += term.coef * F_[ui(term.j)];
            if constexpr (damped)
                if (term.j != i) acc_ -= (term.damping * gam_[term.j]) * P_[ui(term.j)];
        }
        if constexpr (damped) {
            const double denominator = 1.0 + task.damping_ii * gam_[i];
            if (denominator != 1.0) // x / 1 = x exactly: the division is skipped, not rounded
                P_[ui(i)] = acc_ / denominator;
            else
                P_[ui(i)] = acc_;
        } else {
            P_[ui(i)] = acc_;
        }
        prob_.grad_T(P_[ui(i)], gP_[ui(i)]);
    }

    // q₁ = φ̂_0 q + h Σ b̂_i g(P_i),  p₁ = φ̃_0 p + h Σ b̃_i (F_i − δ 2γ_i P_i).
    void update(Vec& z) {
        auto q = q_of(z);
        auto p = p_of(z);
        if constexpr (damped) { // φ̂_0 = φ̃_0 = 1: the increments are added stage by stage
            for (const Weight& b : prog_.bq) q += b.w * gP_[ui(b.i)];
            for (const Weight& b : prog_.bp) {
                acc_ = F_[ui(b.i)] - (2.0 * gam_[b.i]) * P_[ui(b.i)];
                p += b.w * acc_;
            }
        } else {
            weighted_sum(prog_.bq, gP_);
            q = hat_.phi0 * q + h_ * acc_;
            weighted_sum(prog_.bp, F_);
            p = tilde_.phi0 * p + acc_;
        }
    }

    // acc_ = Σ w_i X_i from its first term (0 + x would only turn −0 into +0); 0 when empty.
    void weighted_sum(const std::vector<Weight>& weights, const std::vector<VecN>& X) {
        if (weights.empty()) {
            acc_.setZero();
            return;
        }
        acc_ = weights[0].w * X[ui(weights[0].i)];
        for (std::size_t k = 1; k < weights.size(); ++k) acc_ += weights[k].w * X[ui(weights[k].i)];
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

    // ∂R/∂(Q_1..Q_s, P_1..P_s): identity plus −h â_ij ∇²T(P_j) (Q rows, P columns),
    // −h ã_ij ∂F(Q_j) (P rows, Q columns) and, for δ = 1, 2h ã_ij γ_j I (P rows, P columns).
    void assemble_newton_matrix() {
        Mat& S = newton_.S;
        S.setIdentity();
        for (int i = 0; i < s_; ++i)
            for (int j = 0; j < s_; ++j) {
                S.block(i * n_, (s_ + j) * n_, n_, n_) = -(h_ * hat_.A(i, j)) * HT_[ui(j)];
                S.block((s_ + i) * n_, j * n_, n_, n_) = -(h_ * tilde_.A(i, j)) * JF_[ui(j)];
                if constexpr (damped)
                    S.block((s_ + i) * n_, (s_ + j) * n_, n_, n_).diagonal().array() +=
                        2.0 * h_ * tilde_.A(i, j) * gam_[j];
            }
    }

    // ---- Shapes compiled ahead (partitioned_shapes.hpp; problems with a compile-time size) ----
public:
    // The shape of the current coefficients and the index of its compiled shape (-1: the program).
    partitioned_shapes::Shape current_shape() const { return prog_.shape(hat_, tilde_); }
    int compiled_shape() const { return fixed_ - 1; }

private:
    static constexpr const auto& kShapes = partitioned_shapes::kShapes;

    // The program for the current coefficients, and its compiled shape (static size only).
    void compile_program() {
        prog_.compile(hat_, tilde_, h_);
        if constexpr (N != Eigen::Dynamic) fixed_ = prog_.compile_shape(hat_, tilde_, fc_);
    }

    // Shape I's step: the coefficients may change (time-dependent γ) to another shape, which the
    // program then runs.
    template <int I>
    [[gnu::always_inline]] inline StepStatus step_shape(double t, Vec& z) {
        if (pv_.at_step(prob_, t, h_, hat_, tilde_)) {
            compile_program();
            if (fixed_ != I + 1) return step_program_now(t, z);
        }
        partitioned_shapes::Stages<P, kShapes[I].s> x;
        const partitioned_shapes::Context<P> cx{prob_, h_, hat_, tilde_, fc_, fsal_, c_};
        partitioned_shapes::step<I, damped>(cx, t, z, x);
        return StepStatus::ok;
    }

    // The steps handed to with_shape's f, inlined into its loop (a lambda's call operator may not
    // be): shape I's, and the program's.
    template <int I>
    struct ShapeStep {
        PartitionedEngine& e;
        [[gnu::always_inline]] inline StepStatus operator()(double t, Vec& z) const {
            return e.template step_shape<I>(t, z);
        }
    };
    struct ProgramStep {
        PartitionedEngine& e;
        StepStatus operator()(double t, Vec& z) const { return e.step_program(t, z); }
    };

    // f(step) with step the shape in use, among the shapes of this provider (δ).
    template <class F, int... I>
    [[gnu::always_inline]] inline decltype(auto) with_shape(F&& f,
                                                            std::integer_sequence<int, I...>) {
        using R = decltype(f(ProgramStep{*this}));
        R r{};
        const bool done =
            ((kShapes[I].rayleigh == damped && fixed_ == I + 1 ? (r = call_shape<I>(f), true)
                                                               : false) ||
             ...);
        if (!done) r = f(ProgramStep{*this});
        return r;
    }
    template <int I, class F>
    [[gnu::always_inline]] inline decltype(auto) call_shape(F& f) {
        if constexpr (kShapes[I].rayleigh == damped)
            return f(ShapeStep<I>{*this});
        else
            return f(ProgramStep{*this});
    }
    template <class F>
    [[gnu::always_inline]] inline decltype(auto) with_shape(F&& f) {
        return with_shape(std::forward<F>(f),
                          std::make_integer_sequence<int, int(kShapes.size())>{});
    }

    bool solve_stages(double t, Vec& z) {
        Vec& X = newton_.X;
        for (int i = 0; i < s_; ++i) {
            X.segment(i * n_, n_) = hat_.phi[i] * q_of(z);
            X.segment((s_ + i) * n_, n_) = tilde_.phi[i] * p_of(z);
        }
        const bool solved = newton_.solve_step(NewtonPolicy::full, c_, [&](bool) {
            for (int j = 0; j < s_; ++j) {
                Q_[ui(j)] = X.segment(j * n_, n_);
                P_[ui(j)] = X.segment((s_ + j) * n_, n_);
                prob_.force(stage_time(t, j), Q_[ui(j)], F_[ui(j)]);
                prob_.grad_T(P_[ui(j)], gP_[ui(j)]);
            }
            c_.rhs_evals += s_;
            stage_jacobians(t);
            for (int i = 0; i < s_; ++i) {
                acc_ = Q_[ui(i)] - hat_.phi[i] * q_of(z);
                for (int j = 0; j < s_; ++j) acc_ -= (h_ * hat_.A(i, j)) * gP_[ui(j)];
                newton_.R.segment(i * n_, n_) = acc_;
                acc_ = P_[ui(i)] - tilde_.phi[i] * p_of(z);
                for (int j = 0; j < s_; ++j) {
                    acc_ -= (h_ * tilde_.A(i, j)) * F_[ui(j)];
                    if constexpr (damped) acc_ += (2.0 * h_ * tilde_.A(i, j) * gam_[j]) * P_[ui(j)];
                }
                newton_.R.segment((s_ + i) * n_, n_) = acc_;
            }
            assemble_newton_matrix();
        });
        if (!solved) return false;
        for (int i = 0; i < s_; ++i) {
            Q_[ui(i)] = X.segment(i * n_, n_);
            P_[ui(i)] = X.segment((s_ + i) * n_, n_);
        }
        return true;
    }

    const P& prob_;
    Provider pv_;
    int s_, n_;
    double h_;
    Counters& c_;
    ExponentialTableau hat_, tilde_;
    PartitionedProgram prog_{s_, damped}; // schedule and program (partitioned_program.hpp)
    Vec gam_;
    std::vector<VecN> Q_, P_, F_, gP_;
    std::vector<Mat> HT_, JF_;
    VecN acc_;
    StageNewton newton_;
    Mat B_, dX2_;
    int fixed_ = 0; // 1 + the index of the compiled shape in use (kShapes), 0: the program
    partitioned_shapes::Coefficients fc_;
    partitioned_shapes::ForceMemo<P> fsal_;
};

} // namespace dampsym
