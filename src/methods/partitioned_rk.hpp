// Generic partitioned Runge–Kutta kernel (HLW II.2) for separable problems, on the full damped
// vector field in the Rayleigh form of conventions §1:
//   q' = g(p) = ∇T(p),   p' = F(t, q) − 2γ(t) p,
// with a tableau (A, b, c) for q and (Â, b̂, ĉ) for p (the row's PartitionedTableau):
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
// Stepping: the partitioned engine (partitioned_engine.hpp) with the damping in the vector field
// (δ = 1 there, φ = 1): the scheduled explicit path with the exact linear solve of each P stage
//   (1 + 2h â_ii γ(t_i)) P_i = p + h Σ_j â_ij F_j − 2h Σ_{j≠i} â_ij γ(t_j) P_j
// (symplectic Euler and its adjoint: 1 force evaluation per step; Störmer–Verlet: 2 per step,
// F(t, q_n) and F(t + h, q_{n+1}); no FSAL reuse), or Newton's method on all stages for any other
// pair (e.g. Gauss for both, or 3-stage Lobatto IIIA–IIIB), and the exact step Jacobian. This file
// is its constant-tableau provider and the kernel adapter.
#pragma once

#include "core/method.hpp"
#include "methods/partitioned_engine.hpp"

#include <cstddef>
#include <stdexcept>
#include <string_view>

namespace dampsym {

// Constant pair (q tableau, p tableau) with φ = 1, φ_0 = 1; the damping −2γ(t)p is in the vector
// field. Set once.
class ConstantPairProvider {
public:
    static constexpr bool rayleigh_damping = true;
    ConstantPairProvider(const ButcherTableau& q, const ButcherTableau& p) : q_(q), p_(p) {
        if (q.stages != p.stages)
            throw std::invalid_argument("partitioned-rk: method needs two tableaux with the same "
                                        "number of stages");
    }
    int stages() const { return q_.stages; }
    template <class P>
    void init(const P&, double, ExponentialTableau& hat, ExponentialTableau& tilde) const {
        copy(q_, hat);
        copy(p_, tilde);
    }
    template <class P>
    bool at_step(const P&, double, double, ExponentialTableau&, ExponentialTableau&) const {
        return false;
    }

private:
    static void copy(const ButcherTableau& t, ExponentialTableau& out) {
        out.resize(t.stages);
        for (int i = 0; i < t.stages; ++i) {
            out.b[i] = t.b[static_cast<std::size_t>(i)];
            out.c[i] = t.c[static_cast<std::size_t>(i)];
            for (int j = 0; j < t.stages; ++j) out.A(i, j) = t.A(i, j);
        }
    }
    const ButcherTableau& q_;
    const ButcherTableau& p_;
};

template <class P>
class PartitionedRK : public PartitionedEngine<P, ConstantPairProvider> {
public:
    static constexpr std::string_view kernel_id = "partitioned-rk";
    using Data = PartitionedTableau;
    static bool accepts(const Data&) { return true; }
    template <class Q>
    static constexpr bool applies = Q::has_separable; // needs grad_T, force and their Jacobians

    PartitionedRK(const P& problem, const MethodInfo& info, double h, Counters& counters)
        : PartitionedRK(problem, *std::get<Data>(info.data).q, *std::get<Data>(info.data).p, h,
                        counters) {}
    PartitionedRK(const P& problem, const ButcherTableau& q, const ButcherTableau& p, double h,
                  Counters& counters)
        : PartitionedEngine<P, ConstantPairProvider>(problem, ConstantPairProvider(q, p), h,
                                                     counters) {}
};

} // namespace dampsym
