// Coefficient-level checks: structure and order conditions verified on a method's coefficients
// alone, without running any problem (conventions §3, GeometricIntegrators-style).
//
// Runge–Kutta (A, b, c):
//  - symplecticity  b_i a_ij + b_j a_ji − b_i b_j = 0 for all i, j (B(1.18), BS "symplectic RK");
//  - row sums c = A e (the stage times of a non-autonomous problem);
//  - order conditions by rooted trees (Butcher; BS): for every rooted tree t with |t| ≤ p,
//      Φ(t) = bᵀ Ψ(t) = 1/γ(t),   Ψ(t) = Π_{children u} (A Ψ(u))  (componentwise; Ψ(•) = e),
//    γ(t) = |t| Π_{children u} γ(u). The trees are generated, not typed: a tree is a root with a
//    multiset of smaller trees, enumerated as non-increasing lists of tree indices whose orders
//    sum to n − 1 (1, 1, 2, 4, 9, 20 trees of orders 1..6, 37 in all). The elementary weights use
//    A alone (A Ψ(•) = A e); c = A e is checked separately.
// Partitioned RK, tableau (A, b) for q and (Â, b̂) for p (HLW II.2, VI.4):
//  - symplecticity  b_i â_ij + b̂_j a_ji − b_i b̂_j = 0 and b = b̂;
//  - order conditions by bi-coloured trees (colour 0 = q, 1 = p): a child u of colour k contributes
//    A^{(k)} Ψ(u), and the root of colour k is weighted by b^{(k)}; 2, 4, 14, 52, 214 trees of
//    orders 1..5. These are the conditions for a general partitioned system, which the kernel's
//    damped p' = F(q) − 2γp is. Row sums c = A e are required of the q tableau only (time is
//    integrated with it); Lobatto IIIB (the p part of Störmer–Verlet) has ĉ ≠ Â e.
// General linear method [A U; B V] (GlmCoefficients):
//  - G-symplecticity ‖DA + AᵀD − BᵀGB‖, ‖G − VᵀGV‖, ‖DU − BᵀGV‖ (max norm) with the G and D the
//    data gives, which must be symmetric / diagonal and positive definite (BS, BD §3);
//  - stability: V power-bounded, i.e. every eigenvalue of V in the closed unit disc and those on
//    the circle semisimple (BD Def 2.1); sup_k ‖V^k‖ over k ≤ 1000 is reported as well;
//  - pre-consistency: some u with V u = u and U u = e (BD Def 2.2);
//  - consistency: some v with B e + V v = u + v (BD Def 2.3).
//   u and v are found by least squares (complete orthogonal decomposition) and the residual of
//   the equations is what is checked.
//
// method_checks(info) runs the checks of the method's family: each family's traits
// (Family<D>::checks, src/methods/families.hpp) say which of the functions below apply and which
// properties are expected from the row's claims.
// Order conditions are expected to hold through the declared order and to fail at the next order
// (not checked for order ≥ 6, the largest tree order generated for RK).
#pragma once

#include "core/method.hpp"
#include "methods/glm_coefficients.hpp"

#include <string>
#include <string_view>
#include <vector>

namespace dampsym {

// Tolerance of every coefficient check (residuals of exact identities in double coefficients).
inline constexpr double coefficient_tolerance = 1e-13;
// Largest tree order generated for RK (uncoloured) and PRK (bi-coloured) order conditions.
inline constexpr int rk_max_tree_order = 6;
inline constexpr int prk_max_tree_order = 5;

// ---- rooted trees ----
struct RootedTree {
    int order;                 // number of vertices |t|
    int colour;                // colour of the root (0 for uncoloured trees)
    std::vector<int> children; // indices of the subtrees in the same list, non-increasing
    double gamma;              // density γ(t)
};

// Every rooted tree with 1 ≤ |t| ≤ max_order whose vertices carry one of `colours` colours, in
// non-decreasing order of |t| (children always precede their parent).
std::vector<RootedTree> rooted_trees(int max_order, int colours = 1);

// ---- order conditions ----
struct OrderConditions {
    std::vector<double> residual; // residual[p − 1] = max over trees of order p of |Φ(t) − 1/γ(t)|
    std::vector<int> trees;       // trees[p − 1] = number of trees of order p
    int measured_order = 0;       // largest p with residual ≤ tol for every order ≤ p
};
OrderConditions rk_order_conditions(const ButcherTableau& t, int max_order = rk_max_tree_order,
                                    double tol = coefficient_tolerance);
OrderConditions prk_order_conditions(const ButcherTableau& q, const ButcherTableau& p,
                                     int max_order = prk_max_tree_order,
                                     double tol = coefficient_tolerance);

// ---- symplecticity ----
// max_ij |b_i a_ij + b_j a_ji − b_i b_j| (B(1.18), BS).
double rk_symplecticity_residual(const ButcherTableau& t);
// max_i |c_i − Σ_j a_ij|.
double row_sum_residual(const ButcherTableau& t);
struct PrkSymplecticity {
    double condition; // max_ij |b_i â_ij + b̂_j a_ji − b_i b̂_j|
    double weights;   // max_i |b_i − b̂_i|
};
PrkSymplecticity prk_symplecticity(const ButcherTableau& q, const ButcherTableau& p);

// ---- general linear methods ----
struct GSymplecticity {
    double stages;          // ‖DA + AᵀD − BᵀGB‖_max
    double values;          // ‖G − VᵀGV‖_max
    double coupling;        // ‖DU − BᵀGV‖_max
    bool certificate_valid; // G symmetric positive definite, D diagonal positive definite
    double max() const;
};
// Requires the data's G and D (certificate_valid is false and the residuals are NaN without them).
GSymplecticity glm_g_symplecticity(const GlmCoefficients& m);

struct GlmStability {
    double spectral_radius;
    bool power_bounded;    // eigenvalues in the closed unit disc, semisimple on the circle
    double max_power_norm; // max over k ≤ 1000 of ‖V^k‖_∞
};
GlmStability glm_stability(const GlmCoefficients& m);

struct GlmVectorCondition {
    Vec vector;      // least-squares solution (u for pre-consistency, v for consistency)
    double residual; // max-norm residual of the equations at it
};
// BD Def 2.2: [V − I; U] u = [0; e].
GlmVectorCondition glm_preconsistency(const GlmCoefficients& m);
// BD Def 2.3: (V − I) v = u − B e, with u from glm_preconsistency.
GlmVectorCondition glm_consistency(const GlmCoefficients& m);

// ---- per-method checks (dampsym methods --check, tests) ----
struct CoefficientCheck {
    std::string name; // e.g. "order-conditions-4", "symplectic", "g-symplectic"
    std::string what; // one-line description with the citation
    bool expected;    // what the method's declaration (order, claims) implies
    bool holds;       // what the coefficients give
    double value;     // the residual (or measured quantity) behind `holds`
    double tolerance;
    // A sufficient condition only (B(2.30), B(2.23)): its failure on a method that claims the
    // property is inconclusive (the property may hold for another reason; E_n decides), never a
    // disagreement.
    bool sufficient_only = false;
    bool inconclusive() const { return sufficient_only && expected && !holds; }
    bool agrees() const { return expected == holds || inconclusive(); }
};
// The checks of the method's family (empty: no coefficient-level check applies); defined with the
// family traits (methods/families.cpp).
std::vector<CoefficientCheck> method_checks(const MethodInfo& info);

// The checks of one family's coefficients (appended to out): a Runge–Kutta tableau (row sums,
// order conditions through `order` and their failure at the next, symplecticity expected as
// given, described by symplectic_what); a partitioned pair; a general linear method's order on
// the linear test with its starting method and its stage abscissae; its G-symplecticity (expected
// as given), stability, pre-consistency and consistency.
void rk_checks(const ButcherTableau& t, int order, bool symplectic_expected,
               const std::string& symplectic_what, std::vector<CoefficientCheck>& out);
void prk_checks(const ButcherTableau& q, const ButcherTableau& p, int order, bool expected,
                std::vector<CoefficientCheck>& out);
void glm_order_checks(const GlmCoefficients& m, int order, std::vector<CoefficientCheck>& out);
void glm_checks(const GlmCoefficients& m, bool g_expected, std::vector<CoefficientCheck>& out);

// The exponential families' checks (methods/exponential_checks.cpp): the γh = 0 limit's row sums
// and order conditions, and for a conformal symplectic claim B(2.30)/(2.31) resp. B(2.23)/Thm 2.10
// and the limit's symplecticity.
struct ExponentialRKData;
struct PartitionedExponentialRKData;
void erk_checks(const ExponentialRKData& data, int order, unsigned claims,
                std::vector<CoefficientCheck>& out);
void perk_checks(const PartitionedExponentialRKData& data, int order, unsigned claims,
                 std::vector<CoefficientCheck>& out);

// Claim bits decoded to words ("conformal-symplectic", …; unknown bits as "claim-bit-N").
std::vector<std::string> claim_words(unsigned claims);

} // namespace dampsym
