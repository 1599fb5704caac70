// Coefficient-level checks of the exponential families (ERK B(2.7), PERK B(2.14)), the same for a
// built-in row and a method file (coefficient_checks.hpp method_checks):
//  - at γh = 0 the coefficient functions reduce to a classical tableau (ERK: the underlying RK
//    method, e.g. etdrk2 → the implicit midpoint rule B(2.8); PERK: a partitioned RK pair, e.g.
//    csv1-perk → Lobatto IIIA–IIIB), which must satisfy c = A e and the order conditions through
//    the declared order: necessary, since the undamped problem is one the method must integrate
//    to its order (the order beyond it is not checked: damping may lower it);
//  - a method claiming conformal symplecticity: its γh = 0 limit must be symplectic (B(1.18);
//    HLW VI.4), its φ_0 the exact damping factor (B(2.31), B Thm 2.10), and the sufficient
//    conditions B(2.30) / B(2.23) at γh = 0.01, 0.1, 0.5 are reported — a violation of a
//    sufficient condition is inconclusive, not a refutation (cse-etd and csv2-perk violate B(2.23)
//    and are conformal symplectic: their E_n decides), and a method that satisfies them without
//    claiming conformal symplecticity is told it could.
#include "methods/coefficient_checks.hpp"
#include "methods/exponential_conditions.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>

namespace dampsym {
namespace {

// Damping arguments γh (our γ) at which the conditions that depend on it are evaluated.
constexpr double kArgs[] = {0.01, 0.1, 0.5};

ButcherTableau classical(const ExponentialTableau& t) {
    ButcherTableau out{t.stages, {}, {}, {}};
    for (int i = 0; i < t.stages; ++i) {
        for (int j = 0; j < t.stages; ++j) out.a.push_back(t.A(i, j));
        out.b.push_back(t.b[i]);
        out.c.push_back(t.c[i]);
    }
    return out;
}

std::string brief(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2e", v);
    return buf;
}

// Order conditions through `order` (capped at the trees generated) of the γh = 0 limit.
void limit_order(const OrderConditions& oc, int order, int max_order, const std::string& trees,
                 std::vector<CoefficientCheck>& out) {
    const int p = std::min(order, max_order);
    double worst = 0.0;
    int count = 0;
    for (int k = 1; k <= p; ++k) {
        worst = std::max(worst, oc.residual[static_cast<std::size_t>(k - 1)]);
        count += oc.trees[static_cast<std::size_t>(k - 1)];
    }
    out.push_back({"order-conditions-" + std::to_string(p) + "-at-0",
                   "at γh = 0: Φ(t) = 1/γ(t) for the " + std::to_string(count) + " " + trees +
                       " of order ≤ " + std::to_string(p) + " (measured order " +
                       std::to_string(oc.measured_order) + ")",
                   true, worst <= coefficient_tolerance, worst, coefficient_tolerance});
}

// |φ_i(0) − 1| and |φ_0(0) − 1| over the tableaux: at γh = 0 there is no damping to integrate, and
// the method is its classical limit only if every exponential factor is 1 there.
double unit_factors_at_0(std::initializer_list<const ExponentialTableau*> ts) {
    double worst = 0.0;
    for (const ExponentialTableau* t : ts) {
        worst = std::max(worst, std::abs(t->phi0 - 1.0));
        for (int i = 0; i < t->stages; ++i) worst = std::max(worst, std::abs(t->phi[i] - 1.0));
    }
    return worst;
}

void conformal_condition(const std::string& what, double cond, bool claimed,
                         std::vector<CoefficientCheck>& out) {
    CoefficientCheck c{"conformal-condition",         what, claimed,
                       cond <= coefficient_tolerance, cond, coefficient_tolerance};
    c.sufficient_only = true;
    out.push_back(c);
}

} // namespace

void erk_checks(const ExponentialRKData& data, int order, unsigned claims,
                std::vector<CoefficientCheck>& out) {
    const double tol = coefficient_tolerance;
    const bool claimed = (claims & claim_conformal_symplectic) != 0;
    ExponentialTableau t0;
    erk_coefficients(data, 0.0, t0);
    const ButcherTableau rk = classical(t0);
    const double rs = row_sum_residual(rk);
    out.push_back({"row-sums-at-0", "at γh = 0: c = A e (stage times)", true, rs <= tol, rs, tol});
    const double u0 = unit_factors_at_0({&t0});
    out.push_back({"factors-at-0", "at γh = 0: φ_i = φ_0 = 1 (the classical limit)", true,
                   u0 <= tol, u0, tol});
    limit_order(rk_order_conditions(rk), order, rk_max_tree_order, "rooted trees", out);
    double cond = 0.0, phi0 = 0.0;
    for (const double x : kArgs) {
        cond = std::max(cond, erk_condition_residual(data, x));
        phi0 = std::max(phi0, erk_phi0_residual(data, x));
    }
    conformal_condition("b_i a_ij φ0/φ_i + b_j a_ji φ0/φ_j − b_i b_j = 0 at γh = 0.01, 0.1, 0.5 "
                        "(B(2.30), B Thm 2.11; sufficient, not necessary) [" +
                            brief(cond) + "]",
                        cond, claimed, out);
    if (!claimed) return; // necessary for the claim; silent about a method that does not claim it
    out.push_back({"conformal-factor", "φ0 = e^{−γh} (B(2.31))", true, phi0 <= tol, phi0, tol});
    const double sr = rk_symplecticity_residual(rk);
    out.push_back(
        {"symplectic-at-0",
         "at γh = 0 the method is symplectic: b_i a_ij + b_j a_ji − b_i b_j = 0 (B(1.18))", true,
         sr <= tol, sr, tol});
}

void perk_checks(const PartitionedExponentialRKData& data, int order, unsigned claims,
                 std::vector<CoefficientCheck>& out) {
    const double tol = coefficient_tolerance;
    const bool claimed = (claims & claim_conformal_symplectic) != 0;
    ExponentialTableau q0, p0;
    perk_coefficients(data, 0.0, q0, p0);
    const ButcherTableau q = classical(q0), p = classical(p0);
    const double rs = row_sum_residual(q);
    out.push_back({"row-sums-at-0", "at γh = 0: c = A e for the q tableau (stage times)", true,
                   rs <= tol, rs, tol});
    const double u0 = unit_factors_at_0({&q0, &p0});
    out.push_back({"factors-at-0", "at γh = 0: φ̂_i = φ̃_i = φ̂_0 = φ̃_0 = 1 (the classical limit)",
                   true, u0 <= tol, u0, tol});
    limit_order(prk_order_conditions(q, p), order, prk_max_tree_order, "bi-coloured trees", out);
    double cond = 0.0, phi0 = 0.0;
    for (const double x : kArgs) {
        cond = std::max(cond, perk_condition_residual(data, x));
        phi0 = std::max(phi0, perk_phi0_residual(data, x));
    }
    conformal_condition("B(2.23) at γh = 0.01, 0.1, 0.5 (B Thm 2.4, 2.10; sufficient, not "
                        "necessary: cse-etd and csv2-perk violate it and are conformal "
                        "symplectic) [" +
                            brief(cond) + "]",
                        cond, claimed, out);
    if (!claimed) return;
    out.push_back(
        {"conformal-factor", "φ̂0 φ̃0 = e^{−2γh} (B Thm 2.10)", true, phi0 <= tol, phi0, tol});
    const PrkSymplecticity ps = prk_symplecticity(q, p);
    const double v = std::max(ps.condition, ps.weights);
    out.push_back({"symplectic-at-0",
                   "at γh = 0 the pair is symplectic: b_i â_ij + b̂_j a_ji − b_i b̂_j = 0, b = b̂ "
                   "(HLW VI.4)",
                   true, v <= tol, v, tol});
}

} // namespace dampsym
