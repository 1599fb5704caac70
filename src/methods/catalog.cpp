// The method catalog: one row per method (SPEC §3). Coefficients are exact fractions.
// Adding a method of an existing family = one row here (plus its tableau); the runner, the CLI and
// the reports pick it up from this list, and tests/test_methods.cpp loops over it.
#include "core/method.hpp"
#include "methods/exponential_tableaux.hpp"
#include "methods/glm_coefficients.hpp"
#include "methods/tableaux.hpp"

#include <cmath>

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

// ---- F ch.3 closed forms on the oscillator (our γ) ----
double beta2(double w, double g) {
    return (w - g) * (w + g);
}

// F(3.10): ½trM = e^{−γh}(1 − h²β²/4)/(1 + h²β²/4).
double cimp_half_trace(double w, double g, double h) {
    const double x = 0.25 * h * h * beta2(w, g);
    return std::exp(-g * h) * (1.0 - x) / (1.0 + x);
}
// F(3.12): ω > γ.
bool cimp_condition(double w, double g, double) {
    return w > g;
}
double cimp_h4(double w, double g) {
    return beta2(w, g) * beta2(w, g) / 12.0;
}

// F(3.15): ½trM = e^{−γh}(1 − h²ω²/2) cosh(γh).
double csv1_half_trace(double w, double g, double h) {
    return std::exp(-g * h) * (1.0 - 0.5 * h * h * w * w) * std::cosh(g * h);
}
// F(3.17): 1 − sech(γh) < h²ω²/2 < 1 + sech(γh).
bool csv1_condition(double w, double g, double h) {
    const double x = 0.5 * h * h * w * w;
    const double sech = 1.0 / std::cosh(g * h);
    return 1.0 - sech < x && x < 1.0 + sech;
}
double csv1_h4(double w, double g) {
    return w * w * (w * w + 4.0 * g * g) / 24.0;
}

// F(3.20): ½trM = e^{−γh}[(4+γ²h²)/(4−γ²h²) − 2h²ω² cosh(γh/2)/(4−γ²h²)].
double csv2_half_trace(double w, double g, double h) {
    const double gh2 = g * g * h * h;
    return std::exp(-g * h) *
           ((4.0 + gh2) / (4.0 - gh2) - 2.0 * h * h * w * w * std::cosh(0.5 * g * h) / (4.0 - gh2));
}
// F(3.22): γ² sech(γh/2) < ω² < 4 sech(γh/2)/h², derived by F multiplying |½trM| < e^{−γh} by
// 4 − γ²h², i.e. assuming γh < 2. For γh > 2 that factor is negative and the same condition on
// F(3.20) reverses to 4 sech(γh/2)/h² < ω² < γ² sech(γh/2); at γh = 2 the scheme is undefined.
bool csv2_condition(double w, double g, double h) {
    const double sech = 1.0 / std::cosh(0.5 * g * h);
    const double lo = g * g * sech, hi = 4.0 * sech / (h * h);
    if (g * h < 2.0) return lo < w * w && w * w < hi;
    if (g * h > 2.0) return hi < w * w && w * w < lo;
    return false;
}
double csv2_h4(double w, double g) {
    return (2.0 * w * w * w * w + 5.0 * g * g * w * w - 4.0 * g * g * g * g) / 48.0;
}

// GL-IFRK: conformal symplectic and conformal quadratic invariants (B Thm 2.6, 2.11); angular
// momentum is a conformal quadratic invariant of the n-body problem.
constexpr unsigned glifrk_claims =
    claim_conformal_symplectic | claim_conformal_quadratic | claim_angular_momentum;

constexpr unsigned csv_claims =
    claim_conformal_symplectic | claim_angular_momentum; // + linear momentum for csv1 (below)

} // namespace

const std::vector<MethodInfo>& method_catalog() {
    static const std::vector<MethodInfo> catalog{
        {"cimp",
         "cimp",
         2,
         true,
         "conformal",
         claim_conformal_symplectic | claim_conformal_quadratic | claim_angular_momentum |
             claim_linear_momentum_cayley,
         "F(2.3), B(2.11)",
         nullptr,
         {cimp_half_trace, cimp_condition, cimp_h4, "F(3.10), F(3.12)"}},
        {"csv1",
         "csv1",
         2,
         false,
         "separable",
         csv_claims | claim_linear_momentum,
         "F(2.12), B(2.20)",
         nullptr,
         {csv1_half_trace, csv1_condition, csv1_h4, "F(3.15), F(3.17)"}},
        {"csv2",
         "csv2",
         2,
         false,
         "separable",
         csv_claims | claim_linear_momentum_cayley,
         "F(2.16), B(2.21)",
         nullptr,
         {csv2_half_trace, csv2_condition, csv2_h4, "F(3.20), F(3.22)"}},
        {"euler", "explicit-rk", 1, false, "plain", claim_none, "HLW(1.4)", &euler_tableau, {}},
        {"heun", "explicit-rk", 2, false, "plain", claim_none, "B(3.8)", &heun_tableau, {}},
        {"rk3", "explicit-rk", 3, false, "plain", claim_none, "Kutta, F ch.4", &rk3_tableau, {}},
        {"rk4", "explicit-rk", 4, false, "plain", claim_none, "classical RK4", &rk4_tableau, {}},
        // ---- implicit RK on the full vector field (kernel implicit-rk,
        // src/methods/implicit_rk.hpp); Gauss coefficients generated from the Legendre roots
        // (src/methods/tableaux.cpp) ----
        {"implicit-euler",
         "implicit-rk",
         1,
         true,
         "plain",
         claim_none,
         "HLW(1.5)",
         &implicit_euler_tableau(),
         {}},
        {"implicit-midpoint",
         "implicit-rk",
         2,
         true,
         "plain",
         claim_symplectic_if_undamped,
         "HLW(1.6) (= gauss1)",
         &gauss_tableau(1),
         {}},
        {"gauss1",
         "implicit-rk",
         2,
         true,
         "plain",
         claim_symplectic_if_undamped,
         "1-stage Gauss-Legendre, HLW II.1, BS",
         &gauss_tableau(1),
         {}},
        {"gauss2",
         "implicit-rk",
         4,
         true,
         "plain",
         claim_symplectic_if_undamped,
         "2-stage Gauss-Legendre, B Fig. 3.3, BS",
         &gauss_tableau(2),
         {}},
        {"gauss3",
         "implicit-rk",
         6,
         true,
         "plain",
         claim_symplectic_if_undamped,
         "3-stage Gauss-Legendre, B Fig. 3.3",
         &gauss_tableau(3),
         {}},
        // ---- partitioned RK on the full vector field (kernel partitioned-rk): tableau = q part,
        // tableau_p = p part ----
        {"symplectic-euler",
         "partitioned-rk",
         1,
         false,
         "separable",
         claim_symplectic_if_undamped,
         "HLW(1.8)",
         &explicit_euler_tableau(),
         {},
         &implicit_euler_tableau()},
        {"symplectic-euler-adjoint",
         "partitioned-rk",
         1,
         false,
         "separable",
         claim_symplectic_if_undamped,
         "HLW(1.9)",
         &implicit_euler_tableau(),
         {},
         &explicit_euler_tableau()},
        {"stormer-verlet",
         "partitioned-rk",
         2,
         false,
         "separable",
         claim_symplectic_if_undamped,
         "HLW(3.6), Lobatto IIIA-IIIB",
         &lobatto_iiia2_tableau(),
         {},
         &lobatto_iiib2_tableau()},
        // ---- Gauss-Legendre under the integrating factor, B(2.5) (kernel ifrk) ----
        {"glifrk1",
         "ifrk",
         2,
         true,
         "conformal",
         glifrk_claims,
         "B(2.5), B(2.11)",
         &gauss_tableau(1),
         {}},
        {"glifrk2",
         "ifrk",
         4,
         true,
         "conformal",
         glifrk_claims,
         "B(2.5), B(2.12)",
         &gauss_tableau(2),
         {}},
        {"glifrk3",
         "ifrk",
         6,
         true,
         "conformal",
         glifrk_claims,
         "B(2.5), 3-stage Gauss",
         &gauss_tableau(3),
         {}},
        // ---- general linear methods (kernel general-linear, src/methods/general_linear.hpp) ----
        {.id = "glm4",
         .kernel = "general-linear",
         .order = 4,
         .implicit = true,
         .form = "plain",
         .claims = claim_g_symplectic,
         .citation = "BS: 2-stage 2-value G-symplectic GLM with starting method",
         .glm = &butcher_glm4()},
        // ---- exponential RK, B §2.1 (kernels exponential-rk, src/methods/exponential_rk.hpp, and
        // partitioned-exponential-rk, src/methods/partitioned_exponential_rk.hpp); coefficient
        // functions in src/methods/exponential_tableaux.hpp. Constant γ only. ----
        {.id = "etdrk2",
         .kernel = "exponential-rk",
         .order = 2,
         .implicit = true,
         .form = "conformal",
         // B(2.30), B(2.31) hold: B Thm 2.11 and Thm 2.6 (angular momentum is quadratic).
         .claims = claim_conformal_symplectic | claim_conformal_quadratic | claim_angular_momentum,
         .citation = "B(2.13)",
         .family_data = &etdrk2_data()},
        // B(2.18), B(2.19) are PERK methods (B Example 2.2: symplectic Euler under the integrating
        // factor / ETD), so they are stepped by the partitioned kernel.
        {.id = "cse-if",
         .kernel = "partitioned-exponential-rk",
         .order = 1,
         .implicit = false,
         .form = "separable",
         .claims = csv_claims | claim_linear_momentum,
         .citation = "B(2.18)",
         .family_data = &cse_if_data()},
        {.id = "cse-etd",
         .kernel = "partitioned-exponential-rk",
         .order = 1,
         .implicit = false,
         .form = "separable",
         .claims = csv_claims | claim_linear_momentum,
         .citation = "B(2.19)",
         .family_data = &cse_etd_data()},
        {.id = "csv1-perk",
         .kernel = "partitioned-exponential-rk",
         .order = 2,
         .implicit = false,
         .form = "separable",
         .claims = csv_claims | claim_linear_momentum, // = csv1
         .citation = "B(2.20) (= csv1, F(2.12))",
         .oscillator = {csv1_half_trace, csv1_condition, csv1_h4, "F(3.15), F(3.17)"},
         .family_data = &csv1_perk_data()},
        {.id = "csv2-perk",
         .kernel = "partitioned-exponential-rk",
         .order = 2,
         .implicit = false,
         .form = "separable",
         .claims = csv_claims | claim_linear_momentum_cayley, // = csv2
         .citation = "B(2.21) with F(2.16)'s e^{-gamma_B h/4} in the q tableau (= csv2)",
         .oscillator = {csv2_half_trace, csv2_condition, csv2_h4, "F(3.20), F(3.22)"},
         .family_data = &csv2_perk_data()},
        {.id = "etdprk2",
         .kernel = "partitioned-exponential-rk",
         .order = 2,
         .implicit = false,
         .form = "separable",
         .claims = claim_none, // negative control: det Ψ = e^{−2γh}(1 + γω²h³/4 + O(h⁴))
         .citation = "B(2.22)",
         .family_data = &etdprk2_data()},
    };
    return catalog;
}

const MethodInfo* find_method(std::string_view id) {
    for (const auto& m : method_catalog())
        if (m.id == id) return &m;
    return nullptr;
}

} // namespace dampsym
