// Exponential RK families of B §2.1: the ERK kernel (exponential_rk.hpp), the PERK kernel
// (partitioned_exponential_rk.hpp), their coefficient data (exponential_tableaux.hpp) and the
// coefficient-level conditions B(2.30), B(2.23) (exponential_conditions.hpp).
//  - cancellation-free coefficients at tiny γh (expm1 / sinh forms), x = 0 limits;
//  - B(2.30)/B(2.31) for etdrk2 and IF-Gauss, B(2.23)/Thm 2.10 for cse-if, csv1-perk hold to
//    round-off; etdprk2 fails B(2.23) (negative control); cse-etd and csv2-perk fail B(2.23) as B
//    says, and are conformal symplectic all the same (checked on Ψ below);
//  - csv1-perk == csv1 and csv2-perk == csv2 per step (pendulum, nbody); IF-Gauss ERK == glifrk;
//  - orders on the damped pendulum against the certified GSL reference;
//  - E_n (conformal_symplectic_defect) per step: conformal rows at round-off on the oscillator,
//    pendulum, driven pendulum and Hill (time-dependent γ, coefficients at x_n = ΔΓ_n), etdprk2
//    not;
//  - step_jacobian: same z as step() bitwise, Ψ against central differences;
//  - etdprk2 on the oscillator: det Ψ = e^{−2γh}(1 + γω²h³/4 + O(h⁴)), deviation ∝ h³;
//  - momentum laws on the n-body problem for the claims of the catalog rows;
//  - the Newton paths (implicit PERK pair, etdrk2) and solve_failed without throwing.
// Set DAMPSYM_TEST_VERBOSE=1 to print the measured numbers.
#include "diagnostics/conformal_symplectic.hpp"
#include "harness/problem_list.hpp"
#include "harness/run/kernel_ops.hpp"
#include "methods/exponential_conditions.hpp"
#include "methods/exponential_rk.hpp"
#include "methods/exponential_tableaux.hpp"
#include "methods/partitioned_exponential_rk.hpp"
#include "methods/tableaux.hpp"
#include "reference/gsl_reference.hpp"

#include "support/helpers.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using dampsym::Counters;
using dampsym::ExponentialTableau;
using dampsym::KernelMatch;
using dampsym::Mat;
using dampsym::MethodInfo;
using dampsym::StepStatus;
using dampsym::Vec;

namespace {

using dampsym::test::method;
using dampsym::test::pendulum;
using dampsym::test::verbose;

const std::vector<std::string> conformal_ids{"etdrk2", "cse-if", "cse-etd", "csv1-perk",
                                             "csv2-perk"};

dampsym::Oscillator oscillator(double gamma = 0.1, double omega = 1.0) {
    dampsym::Oscillator p;
    p.omega = omega;
    p.gamma = gamma;
    p.q0 = 1.0;
    p.p0 = 0.0;
    return p;
}
dampsym::DrivenPendulum driven_pendulum() {
    dampsym::DrivenPendulum p; // γ = 0.1, λ = 1, f = 1
    p.q0 = 0.3;
    p.p0 = -0.2;
    return p;
}

double rel_diff(const Vec& a, const Vec& b) {
    return (a - b).cwiseAbs().maxCoeff() / std::max(a.cwiseAbs().maxCoeff(), 1e-300);
}

double ls_slope(const std::vector<double>& x, const std::vector<double>& y) {
    double mx = 0, my = 0;
    const double n = static_cast<double>(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
        mx += std::log(x[i]) / n;
        my += std::log(y[i]) / n;
    }
    double sxy = 0, sxx = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        sxy += (std::log(x[i]) - mx) * (std::log(y[i]) - my);
        sxx += (std::log(x[i]) - mx) * (std::log(x[i]) - mx);
    }
    return sxy / sxx;
}

// A stepper of `info` on the registered problem type P from the library's compiled (kernel,
// problem) pairs (kernel_ops): the registry's choice, which must be one of the two exponential
// kernels of this file (ExponentialRK, PartitionedExponentialRK); the test instantiates none.
template <class P>
std::unique_ptr<dampsym::AnyStepper> exp_stepper(const P& prob, const MethodInfo& info, double h,
                                                 Counters& c) {
    auto k = dampsym::test::stepper_among(prob, info, h, c,
                                          {"exponential-rk", "partitioned-exponential-rk"});
    INFO(info.id << " on " << P::id);
    REQUIRE(k);
    return k;
}

// n steps of size h from t = 0 (exp_stepper); false on a failed step.
template <class P>
bool run(const P& prob, const MethodInfo& info, double h, int n, Vec& z, Counters& c) {
    return dampsym::test::steps_from_zero(exp_stepper(prob, info, h, c).get(), h, n, z);
}

// Per step from the same state: one step of method a and one of b (their kernels, the library's
// compiled pairs, must be ka_id and kb_id) from z_k; continues from a's. Returns the largest
// relative difference; counts bitwise-equal steps.
template <class P>
double compare_per_step(std::string_view ka_id, std::string_view kb_id, const P& prob,
                        const MethodInfo& a, const MethodInfo& b, double h, int n, int& bitwise,
                        Counters& ca, Counters& cb) {
    CHECK(dampsym::test::kernel<P>(a).kernel_id == ka_id);
    CHECK(dampsym::test::kernel<P>(b).kernel_id == kb_id);
    const auto pa = dampsym::test::stepper(prob, a, h, ca);
    const auto pb = dampsym::test::stepper(prob, b, h, cb);
    dampsym::AnyStepper &ka = *pa, &kb = *pb;
    Vec z = prob.initial_state();
    double worst = 0.0;
    bitwise = 0;
    for (int i = 0; i < n; ++i) {
        const double t = dampsym::time_at(0.0, h, i);
        Vec za = z, zb = z;
        REQUIRE(ka.step(t, za) == StepStatus::ok);
        REQUIRE(kb.step(t, zb) == StepStatus::ok);
        worst = std::max(worst, rel_diff(za, zb));
        bitwise += (za.array() == zb.array()).all() ? 1 : 0;
        z = za;
    }
    return worst;
}

// Separable q' = p, p' = NaN: every force is NaN (the Newton path must fail, not throw).
struct NanSeparable : dampsym::SeparableProblem<NanSeparable>,
                      dampsym::UnitMass,
                      dampsym::ConstantGamma<NanSeparable> {
    double gamma = 0.1;
    int n() const { return 1; }
    Vec initial_state() const { return Vec{{1.0, 0.0}}; }
    template <class In, class Out>
    void force(double, const In&, Out& out) const {
        out[0] = std::numeric_limits<double>::quiet_NaN();
    }
    template <class In, class Out>
    void force_jacobian(double, const In&, Out& out) const {
        out(0, 0) = 0.0;
    }
};

// A fully implicit PERK pair (exercises the Newton path of the PERK kernel): 2-stage Gauss for q
// (γ^1 = 0: plain), 2-stage Gauss under the integrating factor B(2.5) for p, in B's x_B. It
// satisfies B(2.23) (b̂_i φ̃_0/φ̃_i = β_i e^{−(1−c_i)x_B} = b̃_i, and the second family reduces to
// e^{−(1−c_j)x_B}(β_i α_ij + β_j α_ji − β_i β_j) = 0): conformal symplectic, order 4.
void if_gauss2_pair(double xB, ExponentialTableau& q, ExponentialTableau& p) {
    const dampsym::ButcherTableau& g = dampsym::gauss_tableau(2);
    for (int i = 0; i < 2; ++i) {
        const double ci = g.c[static_cast<std::size_t>(i)];
        q.c[i] = p.c[i] = ci;
        q.phi[i] = 1.0;
        q.b[i] = g.b[static_cast<std::size_t>(i)];
        p.phi[i] = std::exp(-ci * xB);
        p.b[i] = g.b[static_cast<std::size_t>(i)] * std::exp(-(1.0 - ci) * xB);
        for (int j = 0; j < 2; ++j) {
            const double cj = g.c[static_cast<std::size_t>(j)];
            q.A(i, j) = g.A(i, j);
            p.A(i, j) = g.A(i, j) * std::exp(-(ci - cj) * xB);
        }
    }
    q.phi0 = 1.0;
    p.phi0 = std::exp(-xB);
}
const dampsym::PartitionedExponentialRKData if_gauss2_pair_data{
    "if-gauss2-pair", "B(2.14) with Gauss / IF-Gauss", "integrating-factor", 2, if_gauss2_pair};
const MethodInfo if_gauss2_pair_info{
    .id = "if-gauss2-pair",
    .order = 4,
    .implicit = true,
    .form = dampsym::Form::separable,
    .claims = dampsym::claim_conformal_symplectic,
    .citation = "test",
    .data = dampsym::PartitionedExponentialCoefficients{&if_gauss2_pair_data}};

// B(2.21) exactly as printed (q tableau without e^{−x_B/4}), to show why the data is corrected.
void csv2_as_printed(double xB, ExponentialTableau& q, ExponentialTableau& p) {
    const dampsym::PartitionedExponentialRKData& good = dampsym::csv2_perk_data();
    good.coefficients_B(xB, q, p);
    q.A(1, 0) = q.A(1, 1) = q.b[0] = q.b[1] = 2.0 / (4.0 - xB);
}
const dampsym::PartitionedExponentialRKData csv2_printed_data{
    "csv2-as-printed", "B(2.21) as printed", "integrating-factor", 2, csv2_as_printed};
const MethodInfo csv2_printed_info{
    .id = "csv2-as-printed",
    .order = 1,
    .implicit = false,
    .form = dampsym::Form::separable,
    .claims = dampsym::claim_none,
    .citation = "test",
    .data = dampsym::PartitionedExponentialCoefficients{&csv2_printed_data}};

// IF-Gauss as ERK data, stepped by the ERK kernel (compared with glifrk on the ifrk kernel).
MethodInfo if_gauss_info(int s) {
    return MethodInfo{.id = dampsym::if_gauss_data(s).name,
                      .order = 2 * s,
                      .implicit = true,
                      .form = dampsym::Form::conformal,
                      .claims = dampsym::claim_conformal_symplectic,
                      .citation = dampsym::if_gauss_data(s).source,
                      .data = dampsym::ExponentialCoefficients{&dampsym::if_gauss_data(s)}};
}

} // namespace

TEST_CASE("exponential coefficients: no cancellation at tiny gamma h, exact limits at 0",
          "[exponential]") {
    // exprel(x) = expm1(x)/x and sinh(x/2)/x against long double references.
    double worst_exprel = 0, worst_sinh = 0;
    for (const double x : {-1.0, -0.3, -1e-3, -1e-6, -1e-8, -1e-12, -1e-15, 1e-12, 1e-7, 0.5}) {
        const long double xl = x;
        const long double e_ref = std::expm1(xl) / xl;
        const long double s_ref = std::sinh(0.5L * xl) / xl;
        worst_exprel = std::max(
            worst_exprel, static_cast<double>(std::fabs((dampsym::exprel(x) - e_ref) / e_ref)));
        worst_sinh =
            std::max(worst_sinh,
                     static_cast<double>(std::fabs((dampsym::sinh_half_over(x) - s_ref) / s_ref)));
    }
    CHECK(worst_exprel <= 2.5e-16);
    CHECK(worst_sinh <= 2.5e-16);
    CHECK(dampsym::exprel(0.0) == 1.0);
    CHECK(dampsym::sinh_half_over(0.0) == 0.5);
    CHECK(std::isfinite(dampsym::exprel(-5e-324)));

    // etdrk2 at γh = 1e−12: a = ½ + x²/48, b = 1 − x/2 + x²/6 to the last bit; the naive
    // (1 − e^{−x})/x would be wrong in the 5th digit (shown, so the test has teeth).
    const double x = 1e-12;
    ExponentialTableau t;
    dampsym::erk_coefficients(dampsym::etdrk2_data(), x, t);
    CHECK_THAT(t.A(0, 0), WithinRel(0.5, 1e-16));
    CHECK_THAT(t.b[0], WithinRel(1.0 - 0.5 * x, 1e-16));
    CHECK_THAT(t.phi[0], WithinRel(1.0 - 0.5 * x, 1e-16));
    const double naive_b = (1.0 - std::exp(-x)) / x;
    CHECK(std::abs(naive_b - (1.0 - 0.5 * x)) > 1e-6);
    // At γ = 0 the data is the underlying method (B(2.8)): the implicit midpoint rule.
    dampsym::erk_coefficients(dampsym::etdrk2_data(), 0.0, t);
    CHECK(t.A(0, 0) == 0.5);
    CHECK(t.b[0] == 1.0);
    CHECK(t.phi[0] == 1.0);
    CHECK(t.phi0 == 1.0);
    // PERK ETD coefficients: cse-etd b̃ = (1 − e^{−x_B})/x_B, etdprk2 α = (1 − e^{−x_B/2})/x_B,
    // x_B = 2γh (B's γ is twice ours).
    ExponentialTableau q, p;
    dampsym::perk_coefficients(dampsym::cse_etd_data(), 0.5e-12, q, p); // x_B = 1e−12
    CHECK_THAT(p.b[0], WithinRel(1.0 - 0.5e-12, 1e-16));
    dampsym::perk_coefficients(dampsym::etdprk2_data(), 0.5e-12, q, p);
    CHECK_THAT(p.A(0, 0), WithinRel(0.5 * (1.0 - 0.25e-12), 1e-16));
    dampsym::perk_coefficients(dampsym::etdprk2_data(), 0.0, q, p);
    CHECK(p.A(0, 0) == 0.5);
    CHECK(p.A(1, 0) == 0.5);
    // The γ conversion: csv1-perk's half-step factor is e^{−γh} in our γ (csv1, F(2.12)).
    dampsym::perk_coefficients(dampsym::csv1_perk_data(), 0.3, q, p);
    CHECK_THAT(p.phi[0], WithinRel(std::exp(-0.3), 1e-15));
    CHECK_THAT(p.phi0, WithinRel(std::exp(-0.6), 1e-15));
}

TEST_CASE("coefficient conditions B(2.30), B(2.23) and the phi_0 laws", "[exponential]") {
    const std::vector<double> ghs{1e-12, 0.01, 0.1, 1.0};
    for (const double gh : ghs) {
        INFO("gamma h = " << gh);
        // ERK, B(2.30) + B(2.31): etdrk2 and IF-Gauss (B(2.11), B(2.12)).
        const double r_etd = dampsym::erk_condition_residual(dampsym::etdrk2_data(), gh);
        CHECK(r_etd <= 1e-15);
        CHECK(dampsym::erk_phi0_residual(dampsym::etdrk2_data(), gh) <= 1e-16);
        for (int s = 1; s <= 3; ++s) {
            CHECK(dampsym::erk_condition_residual(dampsym::if_gauss_data(s), gh) <= 1e-15);
            CHECK(dampsym::erk_phi0_residual(dampsym::if_gauss_data(s), gh) <= 1e-16);
        }
        // PERK, B(2.23) + Thm 2.10: cse-if and csv1-perk hold (B after Thm 2.4).
        const double r_if = dampsym::perk_condition_residual(dampsym::cse_if_data(), gh);
        const double r_sv1 = dampsym::perk_condition_residual(dampsym::csv1_perk_data(), gh);
        const double r_pair = dampsym::perk_condition_residual(if_gauss2_pair_data, gh);
        CHECK(r_if <= 1e-15);
        CHECK(r_sv1 <= 1e-15);
        CHECK(r_pair <= 1e-15);
        // φ̂_0 φ̃_0 = e^{−2γh} for every PERK row, etdprk2 included.
        for (const auto* d :
             {&dampsym::cse_if_data(), &dampsym::cse_etd_data(), &dampsym::csv1_perk_data(),
              &dampsym::csv2_perk_data(), &dampsym::etdprk2_data()})
            CHECK(dampsym::perk_phi0_residual(*d, gh) <= 2e-16);
        // Violations: etdprk2 (negative control) by (½ − α)·½e^{−x_B/2} ≈ x_B/32, α = (1 −
        // e^{−x_B/2})/x_B; cse-etd and csv2-perk too, as B says (yet conformal symplectic).
        const double r_etdp = dampsym::perk_condition_residual(dampsym::etdprk2_data(), gh);
        const double r_cse_etd = dampsym::perk_condition_residual(dampsym::cse_etd_data(), gh);
        const double r_sv2 = dampsym::perk_condition_residual(dampsym::csv2_perk_data(), gh);
        if (gh >= 0.01) {
            const double xB = 2.0 * gh;
            const double alpha = (1.0 - std::exp(-0.5 * xB)) / xB;
            CHECK_THAT(r_etdp, WithinRel((0.5 - alpha) * 0.5 * std::exp(-0.5 * xB), 1e-10));
            CHECK(r_etdp >= 5e-4);
            CHECK(r_cse_etd >= 5e-3);
            CHECK(r_sv2 >= 1e-3);
        }
        if (verbose())
            std::printf("[exponential] gh=%-6g B(2.30) etdrk2 %.1e | B(2.23) cse-if %.1e "
                        "csv1-perk %.1e if-gauss2-pair %.1e | violated: etdprk2 %.2e cse-etd "
                        "%.2e csv2-perk %.2e\n",
                        gh, r_etd, r_if, r_sv1, r_pair, r_etdp, r_cse_etd, r_sv2);
    }
}

TEST_CASE("catalog rows of the exponential families", "[exponential]") {
    struct Row {
        const char* id;
        const char* kernel;
        int order;
        bool conformal;
    };
    const Row rows[] = {
        {"etdrk2", "exponential-rk", 2, true},
        {"cse-if", "partitioned-exponential-rk", 1, true},
        {"cse-etd", "partitioned-exponential-rk", 1, true},
        {"csv1-perk", "partitioned-exponential-rk", 2, true},
        {"csv2-perk", "partitioned-exponential-rk", 2, true},
        {"etdprk2", "partitioned-exponential-rk", 2, false},
    };
    for (const Row& r : rows) {
        INFO(r.id);
        const MethodInfo& m = method(r.id);
        CHECK(dampsym::kernel_name(m) == r.kernel);
        CHECK(m.order == r.order);
        const bool has_data =
            dampsym::method_data<dampsym::ExponentialCoefficients>(m) != nullptr ||
            dampsym::method_data<dampsym::PartitionedExponentialCoefficients>(m) != nullptr;
        CHECK(has_data);
        CHECK(((m.claims & dampsym::claim_conformal_symplectic) != 0) == r.conformal);
        CHECK(dampsym::method_applies(r.id, "pendulum"));
        CHECK(dampsym::method_applies(r.id, "nbody"));
        // Time-dependent γ (Hill, γ(t) = ½ε cos 2t) through x_n = Γ(t_n + h) − Γ(t_n); the PERK
        // rows need a separable problem, so the rigid body takes only the ERK rows.
        CHECK(dampsym::method_applies(r.id, "hill"));
        CHECK(dampsym::method_applies(r.id, "rigid-body") ==
              (std::string_view(r.kernel) == "exponential-rk"));
        // The registry dispatches the row to its kernel.
        KernelMatch km = KernelMatch::unknown_kernel;
        const auto* ops = dampsym::kernel_ops<dampsym::Pendulum>(m, km);
        CHECK(km == KernelMatch::applied);
        REQUIRE(ops != nullptr);
        CHECK(ops->kernel_id == r.kernel);
    }
    CHECK(method("etdprk2").claims == dampsym::claim_none);
}

TEST_CASE("csv1-perk == csv1 and csv2-perk == csv2 per step, IF-Gauss ERK == glifrk",
          "[exponential]") {
    const auto check = [](const auto& prob, const char* what, double h, int n) {
        int bitwise = 0;
        Counters ca, cb;
        const double d1 =
            compare_per_step("csv1", "partitioned-exponential-rk", prob, method("csv1"),
                             method("csv1-perk"), h, n, bitwise, ca, cb);
        CHECK(d1 <= 1e-15);
        CHECK(ca.rhs_evals == cb.rhs_evals); // two force evaluations per step, as csv1
        const int bitwise1 = bitwise;
        Counters cc, cd;
        const double d2 =
            compare_per_step("csv2", "partitioned-exponential-rk", prob, method("csv2"),
                             method("csv2-perk"), h, n, bitwise, cc, cd);
        CHECK(d2 <= 1e-15);
        CHECK(cc.rhs_evals == cd.rhs_evals);
        if (verbose())
            std::printf("[exponential] %s: csv1-perk vs csv1 max rel %.1e (bitwise %d/%d), "
                        "csv2-perk vs csv2 max rel %.1e (bitwise %d/%d)\n",
                        what, d1, bitwise1, n, d2, bitwise, n);
    };
    check(pendulum(), "pendulum gamma 0.1", 0.1, 500);
    dampsym::Pendulum strong = pendulum(0.8);
    strong.q0 = 2.5;
    check(strong, "pendulum gamma 0.8", 0.2, 200);
    check(dampsym::NBody{}, "nbody (default, gamma 0.01)", 0.01, 500);

    // The ERK kernel with IF-Gauss data (integrating-factor construction B(2.5)) against the
    // ifrk kernel (glifrk1, glifrk2) on the pendulum.
    const dampsym::Pendulum prob = pendulum();
    for (int s = 1; s <= 2; ++s) {
        int bitwise = 0;
        Counters ca, cb;
        const MethodInfo info = if_gauss_info(s);
        const double d =
            compare_per_step("ifrk", "exponential-rk", prob, method(s == 1 ? "glifrk1" : "glifrk2"),
                             info, 0.1, 300, bitwise, ca, cb);
        CHECK(d <= 1e-14);
        if (verbose())
            std::printf("[exponential] if-gauss%d (ERK kernel) vs glifrk%d: max rel %.1e "
                        "(bitwise %d/300)\n",
                        s, s, d, bitwise);
    }
}

TEST_CASE("exponential methods: orders on the damped pendulum against the certified reference",
          "[exponential]") {
    const dampsym::Pendulum prob = pendulum(); // q'' + 2γq' + sin q = 0, γ = 0.1, q0 = 1
    const double t_end = 10.0;
    const dampsym::ReferenceSolution ref = dampsym::test::pendulum_reference(prob, t_end);
    const Vec zref = ref.states.col(0);
    const double floor = std::max(100.0 * ref.error_estimate, 1e-13);

    struct Case {
        std::string id;
        double expected;
        std::vector<int> steps;
        const MethodInfo* info = nullptr; // not a catalog row
    };
    const MethodInfo g2 = if_gauss_info(2);
    const std::vector<Case> cases{
        {"cse-if", 1, {400, 800, 1600, 3200}},
        {"cse-etd", 1, {400, 800, 1600, 3200}},
        {"etdrk2", 2, {100, 200, 400, 800}},
        {"etdprk2", 2, {100, 200, 400, 800}},
        {"csv1-perk", 2, {100, 200, 400, 800}},
        {"csv2-perk", 2, {100, 200, 400, 800}},
        {"if-gauss2 (ERK kernel)", 4, {20, 40, 80, 160}, &g2},
        {"if-gauss2-pair (PERK Newton)", 4, {20, 40, 80, 160}, &if_gauss2_pair_info},
        {"B(2.21) as printed", 1, {400, 800, 1600, 3200}, &csv2_printed_info},
    };
    for (const Case& c : cases) {
        const MethodInfo& info = c.info != nullptr ? *c.info : method(c.id);
        std::vector<double> hs, errs;
        Counters counters;
        for (const int n : c.steps) {
            const double h = t_end / n;
            Vec z = prob.initial_state();
            REQUIRE(run(prob, info, h, n, z, counters));
            hs.push_back(h);
            errs.push_back((z - zref).cwiseAbs().maxCoeff());
        }
        const double order = ls_slope(hs, errs);
        if (verbose()) {
            std::printf("[exponential] %-30s order %.3f  errors", c.id.c_str(), order);
            for (const double e : errs) std::printf(" %.2e", e);
            std::printf("\n");
        }
        INFO(c.id);
        for (const double e : errs) CHECK(e >= floor);
        CHECK_THAT(order, WithinAbs(c.expected, 0.1));
    }
}

TEST_CASE("conformal symplecticity E_n per step: conformal rows at round-off, etdprk2 not",
          "[exponential]") {
    const double h = 0.1;
    const std::int64_t n = 1000;
    const auto check_problem = [&](const auto& prob, const char* what, bool damped) {
        std::vector<std::string> ids = conformal_ids;
        ids.push_back("etdprk2");
        for (const std::string& id : ids) {
            const MethodInfo& info = method(id);
            Counters c;
            const auto pass = dampsym::test::stepper(prob, info, h, c); // the library's kernel
            Vec z = prob.initial_state();
            const auto st = dampsym::conformal_symplectic_defect(*pass, prob, z, 0.0, h, n);
            INFO(what << " / " << id);
            REQUIRE(st.applicable());
            CHECK(st.status == dampsym::RunStatus::ok);
            CHECK(st.steps_measured == n);
            if (id != "etdprk2")
                CHECK(st.max_rel <= 1e-13);
            else if (damped)
                CHECK(st.max_rel >= 1e-8);
            if (verbose())
                std::printf("[exponential] E_n %-16s %-10s max rel %.2e\n", what, id.c_str(),
                            st.max_rel);
        }
    };
    check_problem(oscillator(), "oscillator", true);
    check_problem(pendulum(), "pendulum", true);
    check_problem(driven_pendulum(), "driven-pendulum", true);
    // etdprk2 with γ = 0 is Störmer–Verlet: symplectic.
    check_problem(pendulum(0.0), "pendulum gamma 0", false);
    // The implicit PERK pair (Newton path) satisfies B(2.23): conformal symplectic too.
    const dampsym::Pendulum prob = pendulum();
    Counters pair_counters;
    dampsym::StepperOf<dampsym::PartitionedExponentialRK<dampsym::Pendulum>> pair(
        prob, if_gauss2_pair_info, h, pair_counters);
    CHECK_FALSE(pair.kernel().scheduled());
    Vec z = prob.initial_state();
    const auto st = dampsym::conformal_symplectic_defect(pair, prob, z, 0.0, h, 200);
    CHECK(st.max_rel <= 1e-13);

    // Time-dependent γ (Hill, γ(t) = 0.2 cos 2t): coefficients at x_n = Γ(t_n + h) − Γ(t_n) each
    // step keep E_n at round-off against the factor e^{−2ΔΓ_n}; etdprk2 stays a negative control.
    dampsym::Hill hill;
    hill.epsilon = 0.4;
    check_problem(hill, "hill", true);
}

TEST_CASE("exponential kernels: step_jacobian advances like step() and matches central "
          "differences",
          "[exponential]") {
    double worst_all = 0;
    int checked = 0;
    const auto check_problem = [&](const auto& prob, const char* what, const Vec& z0) {
        std::vector<const MethodInfo*> infos;
        for (const std::string& id : conformal_ids) infos.push_back(&method(id));
        infos.push_back(&method("etdprk2"));
        infos.push_back(&if_gauss2_pair_info);
        const MethodInfo g2 = if_gauss_info(2);
        infos.push_back(&g2);
        for (const MethodInfo* info : infos) {
            {
                // (stepped below through AnyStepper)
                const double h = 0.1, t = 0.7;
                Counters c;
                const auto k_owner = exp_stepper(prob, *info, h, c);
                dampsym::AnyStepper& k = *k_owner;
                Vec za = z0, zb = z0;
                Mat Psi;
                REQUIRE(k.step(t, za) == StepStatus::ok);
                REQUIRE(k.step_jacobian(t, zb, Psi) == StepStatus::ok);
                INFO(info->id << " on " << what);
                CHECK((za.array() == zb.array()).all());
                const int d = static_cast<int>(z0.size());
                REQUIRE(Psi.rows() == d);
                REQUIRE(Psi.cols() == d);
                double worst = 0;
                for (int j = 0; j < d; ++j) {
                    const double delta = 1e-5 * std::max(1.0, std::abs(z0[j]));
                    Vec zp = z0, zm = z0;
                    zp[j] += delta;
                    zm[j] -= delta;
                    const double width = zp[j] - zm[j];
                    REQUIRE(k.step(t, zp) == StepStatus::ok);
                    REQUIRE(k.step(t, zm) == StepStatus::ok);
                    const Vec col = (zp - zm) / width;
                    worst = std::max(worst, (col - Psi.col(j)).cwiseAbs().maxCoeff());
                }
                CHECK(worst <= 1e-7);
                worst_all = std::max(worst_all, worst);
                ++checked;
            }
        }
    };
    check_problem(pendulum(), "pendulum", Vec{{1.1, -0.4}});
    check_problem(driven_pendulum(), "driven-pendulum", Vec{{0.3, -0.2}});
    const dampsym::NBody nb;
    check_problem(nb, "nbody", nb.initial_state());
    CHECK(checked == 3 * 8);
    if (verbose())
        std::printf("[exponential] step_jacobian vs central differences: %d pairs, worst %.1e\n",
                    checked, worst_all);
}

TEST_CASE("etdprk2 on the oscillator: det of the one-step map is e^{-2 gamma h}(1 + O(h^3))",
          "[exponential]") {
    // det Ψ = e^{−2γh}(1 + h²ω²(½ − α)), α = (1 − e^{−γh})/(2γh) (x_B = 2γh), i.e.
    // e^{−2γh}(1 + γω²h³/4 + O(h⁴)); the conformal rows have det Ψ = e^{−2γh}.
    const double gamma = 0.1, omega = 2.0;
    const dampsym::Oscillator prob = oscillator(gamma, omega);
    std::vector<double> hs, devs;
    for (const double h : {0.2, 0.1, 0.05, 0.025, 0.0125}) {
        const MethodInfo& info = method("etdprk2");
        double det = 0;
        {
            Counters c;
            const auto k_owner = exp_stepper(prob, info, h, c);
            dampsym::AnyStepper& k = *k_owner;
            Vec z = prob.initial_state();
            Mat Psi;
            REQUIRE(k.step_jacobian(0.0, z, Psi) == StepStatus::ok);
            det = Psi.determinant();
        }
        const double dev = det / std::exp(-2.0 * gamma * h) - 1.0;
        const double alpha = (1.0 - std::exp(-gamma * h)) / (2.0 * gamma * h);
        CHECK_THAT(dev, WithinRel(h * h * omega * omega * (0.5 - alpha), 1e-8));
        const double leading = gamma * omega * omega * h * h * h / 4.0;
        CHECK_THAT(dev / leading, WithinAbs(1.0, 0.5 * gamma * h + 1e-3));
        hs.push_back(h);
        devs.push_back(dev);
        if (verbose())
            std::printf("[exponential] etdprk2 det: h %-7g det/e^{-2gh} - 1 = %.4e, "
                        "/(gamma omega^2 h^3/4) = %.5f\n",
                        h, dev, dev / leading);
    }
    const double slope = ls_slope(hs, devs);
    CHECK_THAT(slope, WithinAbs(3.0, 0.05));
    if (verbose()) std::printf("[exponential] etdprk2 det deviation slope %.4f\n", slope);
    for (const std::string& id : conformal_ids) {
        const MethodInfo& info = method(id);
        {
            Counters c;
            const auto k_owner = exp_stepper(prob, info, 0.1, c);
            dampsym::AnyStepper& k = *k_owner;
            Vec z = prob.initial_state();
            Mat Psi;
            REQUIRE(k.step_jacobian(0.0, z, Psi) == StepStatus::ok);
            INFO(id);
            CHECK_THAT(Psi.determinant(), WithinRel(std::exp(-0.2 * gamma), 1e-14));
        }
    }
}

TEST_CASE("exponential methods at tiny gamma h keep full accuracy", "[exponential]") {
    // γh = 1e−12: etdrk2 differs from cimp/glifrk1 only by a_11 − ½ = x²/48 ≈ 2e−26, so the two
    // agree to round-off; the naive b = (1 − e^{−x})/x would put a 1e−5 relative error in b.
    const double h = 0.1;
    const dampsym::Pendulum prob = pendulum(1e-11);
    int bitwise = 0;
    Counters ca, cb;
    const double d = compare_per_step("cimp", "exponential-rk", prob, method("cimp"),
                                      method("etdrk2"), h, 200, bitwise, ca, cb);
    CHECK(d <= 1e-14);
    // cse-etd B(2.19), one step at γh = 1e−12 (x_B = 2e−12) against the same step evaluated in
    // long double: p₁ = e^{−x_B} p − h (1 − e^{−x_B})/x_B sin q, q₁ = q + h p₁.
    const MethodInfo& info = method("cse-etd");
    double d2 = 0;
    {
        Counters c;
        const auto k_owner = exp_stepper(prob, info, h, c);
        dampsym::AnyStepper& k = *k_owner;
        Vec z{{1.3, -0.7}};
        REQUIRE(k.step(0.0, z) == StepStatus::ok);
        const long double xB = 2.0L * static_cast<long double>(prob.gamma) * h;
        const long double w = -std::expm1(-xB) / xB;
        const long double p1 = std::exp(-xB) * -0.7L - h * w * std::sin(1.3L);
        const long double q1 = 1.3L + h * p1;
        d2 = static_cast<double>(std::max(std::fabs(z[0] - q1), std::fabs(z[1] - p1)) /
                                 std::fabs(q1));
    }
    CHECK(d2 <= 4e-16);
    if (verbose())
        std::printf("[exponential] gamma h = 1e-12: etdrk2 vs cimp max rel %.1e, one cse-etd "
                    "step vs long double %.1e\n",
                    d, d2);
}

TEST_CASE("momentum laws on the n-body problem for the claims of the exponential rows",
          "[exponential]") {
    // Total linear momentum: e^{−2γh} per step (claim_linear_momentum) or e^{−γh}(2−γh)/(2+γh)
    // (claim_linear_momentum_cayley); angular momentum Σ q_i × p_i: e^{−2γh} per step.
    dampsym::NBody prob;
    prob.gamma = 0.05;
    const double h = 0.01;
    const int n = 300;
    for (const std::string& id : conformal_ids) {
        const MethodInfo& info = method(id);
        {
            Counters c;
            const auto k_owner = exp_stepper(prob, info, h, c);
            dampsym::AnyStepper& k = *k_owner;
            Vec z = prob.initial_state();
            Vec L0(3), L1(3), P0(3), P1(3);
            const double gh = prob.gamma * h;
            const double lin = (info.claims & dampsym::claim_linear_momentum_cayley)
                                   ? std::exp(-gh) * (2.0 - gh) / (2.0 + gh)
                                   : std::exp(-2.0 * gh);
            double worst_L = 0, worst_P = 0;
            for (int i = 0; i < n; ++i) {
                prob.angular_momentum(z, L0);
                prob.linear_momentum(z, P0);
                REQUIRE(k.step(dampsym::time_at(0.0, h, i), z) == StepStatus::ok);
                prob.angular_momentum(z, L1);
                prob.linear_momentum(z, P1);
                worst_L = std::max(worst_L, (L1 - std::exp(-2.0 * gh) * L0).cwiseAbs().maxCoeff() /
                                                L0.cwiseAbs().maxCoeff());
                worst_P = std::max(worst_P, (P1 - lin * P0).cwiseAbs().maxCoeff() /
                                                P0.cwiseAbs().maxCoeff());
            }
            INFO(id);
            REQUIRE((info.claims & dampsym::claim_angular_momentum) != 0);
            CHECK(worst_L <= 1e-12);
            if (info.claims &
                (dampsym::claim_linear_momentum | dampsym::claim_linear_momentum_cayley))
                CHECK(worst_P <= 1e-13);
            if (verbose())
                std::printf("[exponential] nbody %-10s angular law %.1e  linear law %.1e\n",
                            id.c_str(), worst_L, worst_P);
        }
    }
}

TEST_CASE("exponential kernels report failed solves without throwing", "[exponential]") {
    // PERK Newton path (implicit pair) on a NaN force: solve_failed, z unchanged.
    const NanSeparable prob;
    Counters c;
    dampsym::PartitionedExponentialRK<NanSeparable> pair(prob, if_gauss2_pair_info, 0.1, c);
    Vec z = prob.initial_state();
    CHECK(pair.step(0.0, z) == StepStatus::solve_failed);
    CHECK(z[0] == 1.0);
    CHECK(z[1] == 0.0);
    Mat Psi;
    CHECK(pair.step_jacobian(0.0, z, Psi) == StepStatus::solve_failed);
    // ERK Newton (etdrk2) on the same NaN field: solve_failed, z unchanged, work counted.
    Counters c2;
    dampsym::ExponentialRK<NanSeparable> etd(prob, method("etdrk2"), 0.1, c2);
    CHECK(etd.step(0.0, z) == StepStatus::solve_failed);
    CHECK(z[0] == 1.0);
    CHECK(c2.newton_iters >= 1);
    // etdrk2 on the pendulum: Newton converges in a few iterations and counts them.
    const dampsym::Pendulum pend = pendulum();
    Counters c3;
    Vec zp = pend.initial_state();
    REQUIRE(run(pend, method("etdrk2"), 0.1, 100, zp, c3));
    CHECK(c3.newton_iters >= 100);
    CHECK(c3.max_newton_iters_per_step <= 10);
    CHECK(c3.rhs_evals == c3.newton_iters); // one stage: one N per iteration, no extra update
    if (verbose())
        std::printf("[exponential] etdrk2 pendulum: %lld Newton iterations / 100 steps, max %d\n",
                    static_cast<long long>(c3.newton_iters), c3.max_newton_iters_per_step);
}
