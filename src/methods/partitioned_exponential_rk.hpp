// Generic partitioned exponential Runge–Kutta kernel (PERK), B(2.14), for separable problems in the
// Rayleigh form of conventions §1, q' = ∇T(p), p' = F(q, t) − 2γp (F = −∇_q V + forcing). B writes
// this system as B(2.17), q' = ∇T(p), p' = −∇V − γ_B p, i.e. B(1.2) with γ^1 = 0 and γ^2 = γ_B,
// where γ_B = 2γ: B's γ in (2.17)–(2.22) is TWICE ours. The data of B(2.18)–(2.22) are kept exactly
// as B prints them, as functions of x_B = γ_B h; the conversion x_B = 2γh is made once, in
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
// Stepping: the partitioned engine (partitioned_engine.hpp) with the damping in the coefficients
// (δ = 0 there): P_i depends on the Q stages only and Q_i on the P stages only. When the stages can
// be ordered (all rows of B Example 2.2) the step is explicit in that order; F is evaluated once
// for each Q stage whose force is used (column of Ã or b̃ not zero): 1 per step for
// cse-if/cse-etd, 2 for csv1-perk/csv2-perk/etdprk2, counted in Counters::rhs_evals as for csv1.
// Otherwise the 2s·n stage equations are solved by the stage-Newton solver. Exact step Jacobian
// by the implicit-function theorem. This file is its exponential-coefficient provider and the
// kernel adapter.
#pragma once

#include "core/method.hpp"
#include "core/problem.hpp" // detail::declares_constant_gamma
#include "methods/exponential_tableaux.hpp"
#include "methods/partitioned_engine.hpp"

#include <limits>
#include <stdexcept>
#include <string_view>

namespace dampsym {

// Both tableaux at the damping argument x (our γh, or ΔΓ_n); perk_coefficients converts to B's
// x_B = 2x (the one place). Recomputed only when x changes; nothing is allocated.
class PartitionedExponentialProvider {
public:
    static constexpr bool rayleigh_damping = false;
    explicit PartitionedExponentialProvider(const PartitionedExponentialRKData& data)
        : data_(data) {
        if (data.stages < 1 || data.coefficients_B == nullptr)
            throw std::invalid_argument(
                "partitioned-exponential-rk: method row has no PERK coefficient data");
    }
    int stages() const { return data_.stages; }
    template <class P>
    void init(const P& problem, double h, ExponentialTableau& hat, ExponentialTableau& tilde) {
        set_argument(problem.dGamma(0.0, h), hat, tilde);
    }
    template <class P>
    bool at_step(const P& problem, double t, double h, ExponentialTableau& hat,
                 ExponentialTableau& tilde) {
        if constexpr (!detail::declares_constant_gamma<P>())
            return set_argument(problem.dGamma(t, h), hat, tilde);
        else
            return false;
    }

private:
    bool set_argument(double x, ExponentialTableau& hat, ExponentialTableau& tilde) {
        if (x == x_) return false;
        x_ = x;
        perk_coefficients(data_, x, hat, tilde);
        return true;
    }
    const PartitionedExponentialRKData& data_;
    double x_ = std::numeric_limits<double>::quiet_NaN();
};

template <class P>
class PartitionedExponentialRK : public PartitionedEngine<P, PartitionedExponentialProvider> {
public:
    static constexpr std::string_view kernel_id = "partitioned-exponential-rk";
    using Data = PartitionedExponentialCoefficients;
    static bool accepts(const Data&) { return true; }
    template <class Q>
    static constexpr bool applies = [] {
        if constexpr (requires { Q::has_separable; })
            return Q::has_separable;
        else
            return false;
    }();

    PartitionedExponentialRK(const P& problem, const MethodInfo& info, double h, Counters& counters)
        : PartitionedExponentialRK(problem, *std::get<Data>(info.data).data, h, counters) {}
    PartitionedExponentialRK(const P& problem, const PartitionedExponentialRKData& data, double h,
                             Counters& counters)
        : PartitionedEngine<P, PartitionedExponentialProvider>(
              problem, PartitionedExponentialProvider(data), h, counters) {}
};

} // namespace dampsym
