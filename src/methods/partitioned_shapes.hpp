// Compiled shapes of the partitioned engine (partitioned_engine.hpp) for problems with a
// compile-time size (static_dof). A shape is what the engine's interpreted program depends on: the
// schedule of its stage tasks and which coefficients are structurally present (and which φ and
// weights are exactly 1, so that the product is skipped: 1·x = x). For the shapes of kShapes the
// step is also compiled as straight-line code: stage indices and terms known at compile time, the
// stage vectors locals that the compiler keeps in registers instead of the program's stage storage
// and term lists (whose loads, stores and branches lie on the step's dependency chain). The
// operations are the program's (q_stage, p_stage, update), in its order, on the same coefficient
// values (Coefficients, taken from the compiled program), so the results are the same bit for bit
// (tests/test_method_families.cpp, "compiled partitioned shapes ..."). The engine matches the
// shape whenever the coefficients change and runs any other shape by its program.
#pragma once

#include "core/method.hpp"
#include "core/problem.hpp"
#include "methods/exponential_tableaux.hpp"

#include <array>
#include <bit>
#include <cstdint>
#include <utility>

namespace dampsym::partitioned_shapes {

inline constexpr int kStages = 2; // at most this many stages are compiled

struct Shape {
    bool rayleigh = false; // δ = 1: the damping in the vector field (constant tableaux)
    int s = 0;
    std::array<int, 2 * kStages> order{}; // the schedule: i for Q_i, s + i for P_i
    unsigned q_terms = 0, p_terms = 0;    // bit kStages·i + j: â_ij (ã_ij) present
    unsigned bq = 0, bp = 0, force = 0;   // bit i: b̂_i, b̃_i present; F_i evaluated
    unsigned unit_q = 0, unit_p = 0; // bit i: φ̂_i (φ̃_i) = 1; bit kStages: φ̂_0 (φ̃_0) = 1
    unsigned unit_bq = 0;            // bit i: the weight of ∇T(P_i) in q₁ is 1 (δ = 0)
    bool fsal = false;               // the last Q stage is q₁ computed alike: try the force memo
    constexpr bool operator==(const Shape&) const = default;
};

constexpr bool bit(unsigned mask, int k) {
    return ((mask >> k) & 1u) != 0;
}
constexpr unsigned pair_bit(int i, int j) {
    return 1u << (kStages * i + j);
}

constexpr Shape make_shape(bool rayleigh, int s, std::array<int, 2 * kStages> order,
                           unsigned q_terms, unsigned p_terms, unsigned unit_q, unsigned unit_p,
                           unsigned unit_bq, bool fsal) {
    const unsigned all = (1u << s) - 1u; // every stage has weights and its force
    return {rayleigh, s, order, q_terms, p_terms, all, all, all, unit_q, unit_p, unit_bq, fsal};
}

inline constexpr unsigned kUnit1 = 0b101u, kUnit2 = 0b111u; // φ_1 (, φ_2) and φ_0 equal 1
inline constexpr unsigned kLobattoQ = pair_bit(1, 0) | pair_bit(1, 1);
inline constexpr unsigned kLobattoP = pair_bit(0, 0) | pair_bit(1, 0);
inline constexpr std::array<Shape, 6> kShapes{{
    // Q₁ P₁: explicit Q₁, P₁ a linear solve (symplectic Euler HLW(1.8))
    make_shape(true, 1, {0, 1}, 0u, pair_bit(0, 0), kUnit1, kUnit1, 0u, false),
    // P₁ Q₁: its adjoint (HLW(1.9))
    make_shape(true, 1, {1, 0}, pair_bit(0, 0), 0u, kUnit1, kUnit1, 0u, false),
    // Q₁ P₁ under exponential p coefficients (cse-if B(2.18), cse-etd B(2.19))
    make_shape(false, 1, {0, 1}, 0u, pair_bit(0, 0), kUnit1, 0u, 1u, false),
    // Q₁ P₁ P₂ Q₂: Lobatto IIIA-IIIB in the Rayleigh form (stormer-verlet HLW(3.6)); Q₂ and q₁
    // are the same sums, so the next step's F(Q₁) is this step's F(Q₂)
    make_shape(true, 2, {0, 2, 3, 1}, kLobattoQ, kLobattoP, kUnit2, kUnit2, 0u, true),
    // the same schedule under exponential p coefficients (csv1-perk B(2.20), etdprk2 B(2.22))
    make_shape(false, 2, {0, 2, 3, 1}, kLobattoQ, kLobattoP, kUnit2, 0u, 0u, false),
    // and with φ̂₂, φ̂₀ ≠ 1 (csv2-perk B(2.21))
    make_shape(false, 2, {0, 2, 3, 1}, kLobattoQ, kLobattoP, 0b001u, 0u, 0u, false),
}};

// Whether compiled shape c runs coefficients of shape sh: the same structure, and 1 in sh wherever
// c skips the product (where c multiplies and sh has 1, 1·x is the same value). fsal is c's
// choice (the memo is checked bit for bit either way).
constexpr bool compiles(const Shape& c, const Shape& sh) {
    Shape structure = sh;
    structure.unit_q = c.unit_q;
    structure.unit_p = c.unit_p;
    structure.unit_bq = c.unit_bq;
    structure.fsal = c.fsal;
    return c == structure && (sh.unit_q & c.unit_q) == c.unit_q &&
           (sh.unit_p & c.unit_p) == c.unit_p && (sh.unit_bq & c.unit_bq) == c.unit_bq;
}

// The program's coefficient values by stage index (zero where the shape has no term).
struct Coefficients {
    double q[kStages][kStages]{}, p[kStages][kStages]{};       // h â_ij, h ã_ij
    double damping[kStages][kStages]{}, damping_ii[kStages]{}; // 2h ã_ij (δ = 1)
    double phi_q[kStages]{}, phi_p[kStages]{};
    double bq[kStages]{}, bp[kStages]{}; // the program's update weights
};

// The last force evaluated, F(t_i, Q_i), reused when a later stage (the next step's first, for the
// Lobatto IIIA q tableau, whose last stage is q_{n+1}) has the same Q bit for bit and the same
// time, or any time when the force does not depend on t (autonomous_potential): the value is then
// the one the evaluation would return. Counted in rhs_evals all the same: the counters count the
// method's evaluations, as csv1 does for the one the compiler shares. Kept as bit patterns
// (integers, which a store to the state's doubles cannot alias), so the compiler carries the value
// from one step to the next in a register, as it does for csv1.
template <class P>
struct ForceMemo {
    static constexpr int N = static_dof<P>();
    using VecN = Eigen::Matrix<double, N, 1>;
    static constexpr bool any_time = [] {
        if constexpr (requires { P::autonomous_potential; })
            return P::autonomous_potential;
        else
            return false;
    }();
    bool valid = false;
    std::uint64_t t = 0, q[N > 0 ? N : 1] = {}, f[N > 0 ? N : 1] = {};
    static std::uint64_t bits(double x) { return std::bit_cast<std::uint64_t>(x); }
    // F = the kept force when (ti, Q) is the kept point.
    [[gnu::always_inline]] inline bool take(double ti, const VecN& Q, VecN& F) const {
        if (!valid || (!any_time && bits(ti) != t)) return false;
        for (int k = 0; k < N; ++k)
            if (bits(Q[k]) != q[k]) return false;
        for (int k = 0; k < N; ++k) F[k] = std::bit_cast<double>(f[k]);
        return true;
    }
    [[gnu::always_inline]] inline void keep(double ti, const VecN& Q, const VecN& F) {
        valid = true;
        t = bits(ti);
        for (int k = 0; k < N; ++k) {
            q[k] = bits(Q[k]);
            f[k] = bits(F[k]);
        }
    }
};

// The stages of one step (locals of run: the compiler keeps them in registers).
template <class P, int S>
struct Stages {
    using VecN = Eigen::Matrix<double, static_dof<P>(), 1>;
    VecN Qs[S], Ps[S], Fs[S], Gs[S]; // Gs_i = ∇T(Ps_i)
    double gam[S];
};

// What a compiled step reads and writes of the engine.
template <class P>
struct Context {
    const P& prob;
    double h;
    const ExponentialTableau &hat, &tilde; // ĉ for the stage times; φ̂_0, φ̃_0
    const Coefficients& fc;
    ForceMemo<P>& memo;
    Counters& counters;
    double stage_time(double t, int i) const { return t + hat.c[i] * h; }
};

template <int S, class F>
[[gnu::always_inline]] inline void for_stages(F&& f) {
    [&]<int... J>(std::integer_sequence<int, J...>) __attribute__((always_inline)) {
        (f.template operator()<J>(), ...);
    }
    (std::make_integer_sequence<int, S>{});
}

// q_stage with stage index I: Q_I = φ̂_I q + Σ_j h â_Ij ∇T(P_j), then F_I if used.
template <int Idx, int I, class P, int S>
[[gnu::always_inline]] inline void q_stage(const Context<P>& cx, double t,
                                           const typename Stages<P, S>::VecN& q, Stages<P, S>& x) {
    constexpr int N = static_dof<P>();
    constexpr Shape sh = kShapes[Idx];
    if constexpr (bit(sh.unit_q, I))
        x.Qs[I] = q; // 1·x = x exactly, as the program's φ̂_i q
    else
        for (int k = 0; k < N; ++k) x.Qs[I][k] = cx.fc.phi_q[I] * q[k];
    for_stages<S>([&]<int J>() __attribute__((always_inline)) {
        if constexpr (bit(sh.q_terms, kStages * I + J))
            for (int k = 0; k < N; ++k) x.Qs[I][k] += cx.fc.q[I][J] * x.Gs[J][k];
    });
    if constexpr (bit(sh.force, I)) {
        const double ti = cx.stage_time(t, I);
        if constexpr (sh.fsal) {
            if (!cx.memo.take(ti, x.Qs[I], x.Fs[I])) cx.prob.force(ti, x.Qs[I], x.Fs[I]);
            cx.counters.rhs_evals += 1; // before keep: the count's store comes before the memo's
            cx.memo.keep(ti, x.Qs[I], x.Fs[I]);
        } else {
            cx.prob.force(ti, x.Qs[I], x.Fs[I]);
            cx.counters.rhs_evals += 1;
        }
    }
}

// p_stage with stage index I: (1 + 2h ã_II δγ_I) P_I = φ̃_I p + Σ_j h ã_Ij F_j − δ Σ_{j≠I} 2h ã_Ij
// γ_j P_j, then ∇T(P_I).
template <int Idx, int I, bool Damped, class P, int S>
[[gnu::always_inline]] inline void p_stage(const Context<P>& cx,
                                           const typename Stages<P, S>::VecN& p, Stages<P, S>& x) {
    constexpr int N = static_dof<P>();
    constexpr Shape sh = kShapes[Idx];
    typename Stages<P, S>::VecN acc;
    if constexpr (bit(sh.unit_p, I))
        acc = p;
    else
        for (int k = 0; k < N; ++k) acc[k] = cx.fc.phi_p[I] * p[k];
    for_stages<S>([&]<int J>() __attribute__((always_inline)) {
        if constexpr (bit(sh.p_terms, kStages * I + J)) {
            for (int k = 0; k < N; ++k) acc[k] += cx.fc.p[I][J] * x.Fs[J][k];
            if constexpr (Damped && J != I) {
                const double d = cx.fc.damping[I][J] * x.gam[J];
                for (int k = 0; k < N; ++k) acc[k] -= d * x.Ps[J][k];
            }
        }
    });
    if constexpr (Damped) {
        const double denominator = 1.0 + cx.fc.damping_ii[I] * x.gam[I];
        if (denominator != 1.0) // x / 1 = x exactly: the division is skipped, as in the program
            for (int k = 0; k < N; ++k) x.Ps[I][k] = acc[k] / denominator;
        else
            x.Ps[I] = acc;
    } else {
        x.Ps[I] = acc;
    }
    cx.prob.grad_T(x.Ps[I], x.Gs[I]);
}

// The update: q₁ = φ̂_0 q + Σ w_i ∇T(P_i), p₁ = φ̃_0 p + Σ w_i (F_i − δ 2γ_i P_i), each sum from
// its first term, as the program's update().
template <int Idx, bool Damped, class P, int S>
[[gnu::always_inline]] inline void update(const Context<P>& cx, typename Stages<P, S>::VecN& q,
                                          typename Stages<P, S>::VecN& p, const Stages<P, S>& x) {
    constexpr int N = static_dof<P>();
    constexpr Shape sh = kShapes[Idx];
    if constexpr (Damped) { // φ̂_0 = φ̃_0 = 1: the increments are added stage by stage
        for_stages<S>([&]<int I>() __attribute__((always_inline)) {
            if constexpr (bit(sh.bq, I))
                for (int k = 0; k < N; ++k) q[k] += cx.fc.bq[I] * x.Gs[I][k];
        });
        for_stages<S>([&]<int I>() __attribute__((always_inline)) {
            if constexpr (bit(sh.bp, I))
                for (int k = 0; k < N; ++k)
                    p[k] += cx.fc.bp[I] * (x.Fs[I][k] - (2.0 * x.gam[I]) * x.Ps[I][k]);
        });
    } else {
        typename Stages<P, S>::VecN acc;
        if constexpr (sh.bq == 0u) acc.setZero();
        for_stages<S>([&]<int I>() __attribute__((always_inline)) {
            if constexpr (bit(sh.bq, I))
                for (int k = 0; k < N; ++k) {
                    const double term = bit(sh.unit_bq, I) ? x.Gs[I][k] : cx.fc.bq[I] * x.Gs[I][k];
                    if constexpr (I == std::countr_zero(sh.bq))
                        acc[k] = term;
                    else
                        acc[k] += term;
                }
        });
        for (int k = 0; k < N; ++k)
            q[k] = (bit(sh.unit_q, kStages) ? q[k] : cx.hat.phi0 * q[k]) + cx.h * acc[k];
        if constexpr (sh.bp == 0u) acc.setZero();
        for_stages<S>([&]<int I>() __attribute__((always_inline)) {
            if constexpr (bit(sh.bp, I))
                for (int k = 0; k < N; ++k) {
                    if constexpr (I == std::countr_zero(sh.bp))
                        acc[k] = cx.fc.bp[I] * x.Fs[I][k];
                    else
                        acc[k] += cx.fc.bp[I] * x.Fs[I][k];
                }
        });
        for (int k = 0; k < N; ++k)
            p[k] = (bit(sh.unit_p, kStages) ? p[k] : cx.tilde.phi0 * p[k]) + acc[k];
    }
}

// One step of compiled shape Idx on z: the stages in the schedule's order, then the update; the
// stages are left in x.
template <int Idx, bool Damped, class P, int S = kShapes[Idx].s>
[[gnu::always_inline]] inline void step(const Context<P>& cx, double t, Vec& z, Stages<P, S>& x) {
    constexpr int N = static_dof<P>();
    constexpr Shape sh = kShapes[Idx];
    typename Stages<P, S>::VecN q, p;
    for (int k = 0; k < N; ++k) {
        q[k] = z[k];
        p[k] = z[N + k];
    }
    for (int i = 0; i < S; ++i) {
        x.Qs[i].setZero();
        x.Ps[i].setZero();
        x.Fs[i].setZero();
        x.Gs[i].setZero();
        x.gam[i] = 0.0;
    }
    if constexpr (Damped)
        for (int i = 0; i < S; ++i) x.gam[i] = cx.prob.gamma_at(cx.stage_time(t, i));
    [&]<int... K>(std::integer_sequence<int, K...>) __attribute__((always_inline)) {
        (
            [&]() __attribute__((always_inline)) {
                constexpr int code = sh.order[K];
                if constexpr (code < S)
                    q_stage<Idx, code>(cx, t, q, x);
                else
                    p_stage<Idx, code - S, Damped>(cx, p, x);
            }(),
            ...);
    }
    (std::make_integer_sequence<int, 2 * S>{});
    update<Idx, Damped>(cx, q, p, x);
    for (int k = 0; k < N; ++k) {
        z[k] = q[k];
        z[N + k] = p[k];
    }
}

} // namespace dampsym::partitioned_shapes
