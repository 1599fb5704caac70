// The method catalog: one row per method (conventions §3): id, order, implicit, form, claims,
// citation and one typed coefficient set (core/method.hpp), which selects the family engine that
// steps it. Coefficients are exact fractions. Adding a method of an existing family = one row here
// (plus its tableau); the runner, the CLI and the reports pick it up from this list, and
// tests/test_method_families.cpp and tests/test_coefficient_checks.cpp loop over it.
#include "core/method.hpp"
#include "methods/exponential_tableaux.hpp"
#include "methods/glm_coefficients.hpp"
#include "methods/runtime_methods.hpp"
#include "methods/tableaux.hpp"

namespace dampsym {
namespace {

// ---- Butcher tableaux (explicit RK) ----
// Explicit Euler, HLW(1.4).
const ButcherTableau euler_tableau{1, {0.0}, {1.0}, {0.0}};
// Heun's method (explicit trapezoidal rule), B(3.8).
const ButcherTableau heun_tableau{2, {0.0, 0.0, 1.0, 0.0}, {0.5, 0.5}, {0.0, 1.0}};
// Kutta's third-order method (F ch.4): c = (0, ½, 1), b = (⅙, ⅔, ⅙).
const ButcherTableau rk3_tableau{3,
                                 {0.0, 0.0, 0.0, 0.5, 0.0, 0.0, -1.0, 2.0, 0.0},
                                 {1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0},
                                 {0.0, 0.5, 1.0}};
// The classical fourth-order method.
const ButcherTableau rk4_tableau{
    4,
    {0.0, 0.0, 0.0, 0.0, 0.5, 0.0, 0.0, 0.0, 0.0, 0.5, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0},
    {1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0},
    {0.0, 0.5, 0.5, 1.0}};

// GL-IFRK: conformal symplectic and conformal quadratic invariants (B Thm 2.6, 2.11); angular
// momentum is a conformal quadratic invariant of the n-body problem.
constexpr unsigned glifrk_claims =
    claim_conformal_symplectic | claim_conformal_quadratic | claim_angular_momentum;

constexpr unsigned csv_claims =
    claim_conformal_symplectic | claim_angular_momentum; // + linear momentum for csv1 (below)

// Hand-written schemes (src/methods/cimp.hpp, csv1.hpp, csv2.hpp; B's Burgers schemes and the
// Klein–Gordon box scheme, each on its own semi-discretisation, pde/burgers/methods.hpp,
// pde/klein_gordon/methods.hpp; B's NLS schemes by FFT,
// pde/nls/methods.hpp; HLW (1.8) on (1.7), symplectic_euler_partitioned.hpp).
std::vector<MethodInfo> hand_written_rows() {
    using enum Form;
    return {
        {"cimp", 2, true, conformal,
         claim_conformal_symplectic | claim_conformal_quadratic | claim_angular_momentum |
             claim_linear_momentum_cayley,
         "F(2.3), B(2.11)", HandWrittenScheme{Scheme::cimp}},
        {"csv1", 2, false, separable, csv_claims | claim_linear_momentum, "F(2.12), B(2.20)",
         HandWrittenScheme{Scheme::csv1}},
        {"csv2", 2, false, separable, csv_claims | claim_linear_momentum_cayley, "F(2.16), B(2.21)",
         HandWrittenScheme{Scheme::csv2}},
        {"burgers-csv", 2, false, conformal, claim_none, "B(5.10)",
         HandWrittenScheme{Scheme::burgers_csv}},
        {"burgers-box", 2, true, conformal, claim_none, "B(5.12)",
         HandWrittenScheme{Scheme::burgers_box}},
        {"burgers-nsfd", 1, false, conformal, claim_none, "B(4.18)",
         HandWrittenScheme{Scheme::burgers_nsfd}},
        {"kg-box", 2, true, separable, claim_none, "B(5.5)", HandWrittenScheme{Scheme::kg_box}},
        {"nls-if", 2, true, conformal, claim_none, "B(4.15)", HandWrittenScheme{Scheme::nls_if}},
        {"nls-etd", 2, true, conformal, claim_none, "B(5.27)", HandWrittenScheme{Scheme::nls_etd}},
        {"nls-imp", 2, true, plain, claim_none, "B(5.28)", HandWrittenScheme{Scheme::nls_imp}},
        {"symplectic-euler-partitioned", 1, true, plain, claim_none, "HLW(1.8) on (1.7)",
         HandWrittenScheme{Scheme::symplectic_euler_partitioned}},
    };
}

} // namespace

const std::vector<MethodInfo>& method_catalog() {
    using enum Form;
    static const std::vector<MethodInfo> catalog = [] {
        std::vector<MethodInfo> rows = hand_written_rows();
        rows.insert(
            rows.end(),
            {
                // ---- explicit RK on the full vector field (src/methods/explicit_rk.hpp) ----
                {"euler", 1, false, plain, claim_none, "HLW(1.4)",
                 RungeKuttaTableau{&euler_tableau}},
                {"heun", 2, false, plain, claim_none, "B(3.8)", RungeKuttaTableau{&heun_tableau}},
                {"rk3", 3, false, plain, claim_none, "Kutta, F ch.4",
                 RungeKuttaTableau{&rk3_tableau}},
                {"rk4", 4, false, plain, claim_none, "classical RK4",
                 RungeKuttaTableau{&rk4_tableau}},
                // ---- implicit RK on the full vector field (RK engine,
                // src/methods/implicit_rk.hpp);
                // Gauss coefficients generated from the Legendre roots (src/methods/tableaux.cpp)
                // ----
                {"implicit-euler", 1, true, plain, claim_none, "HLW(1.5)",
                 RungeKuttaTableau{&implicit_euler_tableau()}},
                {"implicit-midpoint", 2, true, plain, claim_symplectic_if_undamped,
                 "HLW(1.6) (= gauss1)", RungeKuttaTableau{&gauss_tableau(1)}},
                {"gauss1", 2, true, plain, claim_symplectic_if_undamped,
                 "1-stage Gauss-Legendre, HLW II.1, BS", RungeKuttaTableau{&gauss_tableau(1)}},
                {"gauss2", 4, true, plain, claim_symplectic_if_undamped,
                 "2-stage Gauss-Legendre, B Fig. 3.3, BS", RungeKuttaTableau{&gauss_tableau(2)}},
                {"gauss3", 6, true, plain, claim_symplectic_if_undamped,
                 "3-stage Gauss-Legendre, B Fig. 3.3", RungeKuttaTableau{&gauss_tableau(3)}},
                // ---- partitioned RK (partitioned engine, partitioned_rk.hpp): q tableau, p
                // tableau ----
                {"symplectic-euler", 1, false, separable, claim_symplectic_if_undamped, "HLW(1.8)",
                 PartitionedTableau{&explicit_euler_tableau(), &implicit_euler_tableau()}},
                {"symplectic-euler-adjoint", 1, false, separable, claim_symplectic_if_undamped,
                 "HLW(1.9)",
                 PartitionedTableau{&implicit_euler_tableau(), &explicit_euler_tableau()}},
                {"stormer-verlet", 2, false, separable, claim_symplectic_if_undamped,
                 "HLW(3.6), Lobatto IIIA-IIIB",
                 PartitionedTableau{&lobatto_iiia2_tableau(), &lobatto_iiib2_tableau()}},
                // ---- Gauss-Legendre under the integrating factor, B(2.5) (RK engine, ifrk.hpp)
                // ----
                {"glifrk1", 2, true, conformal, glifrk_claims, "B(2.5), B(2.11)",
                 IntegratingFactorTableau{&gauss_tableau(1)}},
                {"glifrk2", 4, true, conformal, glifrk_claims, "B(2.5), B(2.12)",
                 IntegratingFactorTableau{&gauss_tableau(2)}},
                {"glifrk3", 6, true, conformal, glifrk_claims, "B(2.5), 3-stage Gauss",
                 IntegratingFactorTableau{&gauss_tableau(3)}},
                // ---- general linear methods (src/methods/general_linear.hpp) ----
                {"glm4", 4, true, plain, claim_g_symplectic,
                 "BS: 2-stage 2-value G-symplectic GLM with starting method",
                 GeneralLinearCoefficients{&butcher_glm4()}},
                // ---- exponential RK, B §2.1 (RK engine, exponential_rk.hpp; partitioned engine,
                // partitioned_exponential_rk.hpp; coefficients in exponential_tableaux.hpp) ----
                // B(2.30), B(2.31) hold: B Thm 2.11 and Thm 2.6 (angular momentum is quadratic).
                {"etdrk2", 2, true, conformal,
                 claim_conformal_symplectic | claim_conformal_quadratic | claim_angular_momentum,
                 "B(2.13)", ExponentialCoefficients{&etdrk2_data()}},
                // B(2.18), B(2.19) are PERK methods (B Example 2.2: symplectic Euler under the
                // integrating
                // factor / ETD), so they are stepped by the partitioned engine.
                {"cse-if", 1, false, separable, csv_claims | claim_linear_momentum, "B(2.18)",
                 PartitionedExponentialCoefficients{&cse_if_data()}},
                {"cse-etd", 1, false, separable, csv_claims | claim_linear_momentum, "B(2.19)",
                 PartitionedExponentialCoefficients{&cse_etd_data()}},
                {"csv1-perk", 2, false, separable, csv_claims | claim_linear_momentum, // = csv1
                 "B(2.20) (= csv1, F(2.12))",
                 PartitionedExponentialCoefficients{&csv1_perk_data()}},
                {"csv2-perk", 2, false, separable,
                 csv_claims | claim_linear_momentum_cayley, // = csv2
                 "B(2.21) with F(2.16)'s e^{-gamma_B h/4} in the q tableau (= csv2)",
                 PartitionedExponentialCoefficients{&csv2_perk_data()}},
                // Negative control: det Ψ = e^{−2γh}(1 + γω²h³/4 + O(h⁴)).
                {"etdprk2", 2, false, separable, claim_none, "B(2.22)",
                 PartitionedExponentialCoefficients{&etdprk2_data()}},
            });
        return rows;
    }();
    return catalog;
}

const MethodInfo* find_method(std::string_view id) {
    for (const auto& m : method_catalog())
        if (m.id == id) return &m;
    return find_loaded_method(id); // method files (src/harness/user_methods/method_files.hpp)
}

} // namespace dampsym
