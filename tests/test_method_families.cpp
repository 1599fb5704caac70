// The generic method-family kernels whose methods are coefficient data: implicit RK on the plain
// form (implicit_rk.hpp), integrating-factor RK B(2.5) (ifrk.hpp), partitioned RK (partitioned_rk
// .hpp), and the generated Gauss–Legendre coefficients (tableaux.hpp).
//  - Gauss coefficients: B(s), C(s) and symplecticity b_i a_ij + b_j a_ji − b_i b_j = 0;
//  - glifrk1 == cimp per step (pendulum; rigid body with time-dependent γ, ε = 0.5);
//  - observed orders on the damped pendulum against the certified GSL reference;
//  - step_jacobian: same z as step(), and Ψ against central differences;
//  - conformal symplecticity of glifrk1..3 on Hill's equation, gauss1..3 as negative controls;
//  - solve failure returns StepStatus::solve_failed with z unchanged;
//  - evaluation counts, the Newton path of the partitioned kernel, explicit tableaux.
// On the registered problems the steppers are the library's compiled (kernel, problem) pairs
// (family_stepper: the registry's choice, required to be one of the three family kernels); the
// test's own problems (Riccati) and the engines' internals (the partitioned engine's compiled
// shapes against its program) instantiate the kernels here.
// Set DAMPSYM_TEST_VERBOSE=1 to print the measured numbers.
#include "core/integrate.hpp"
#include "harness/problem_list.hpp"
#include "harness/registry.hpp" // with_kernel_among (the engines' internals)
#include "harness/run/kernel_ops.hpp"
#include "methods/newton.hpp"
#include "methods/tableaux.hpp"
#include "reference/gsl_reference.hpp"

#include "support/helpers.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using dampsym::ButcherTableau;
using dampsym::Counters;
using dampsym::Mat;
using dampsym::MethodInfo;
using dampsym::StepStatus;
using dampsym::Vec;

namespace {

using dampsym::test::method;
using dampsym::test::pendulum;
using dampsym::test::verbose;

// The (q) Butcher tableau of a row of the RK, IFRK or partitioned RK families.
const ButcherTableau* tableau_of(const MethodInfo& m) {
    if (const auto* d = dampsym::method_data<dampsym::RungeKuttaTableau>(m)) return d->tableau;
    if (const auto* d = dampsym::method_data<dampsym::IntegratingFactorTableau>(m))
        return d->tableau;
    if (const auto* d = dampsym::method_data<dampsym::PartitionedTableau>(m)) return d->q;
    return nullptr;
}

// 2-stage Gauss for both q and p: a partitioned pair the partitioned engine solves by Newton.
const MethodInfo& gauss2_pair() {
    static const MethodInfo m{
        "gauss2-pair",
        4,
        true,
        dampsym::Form::separable,
        0u,
        "test",
        dampsym::PartitionedTableau{&dampsym::gauss_tableau(2), &dampsym::gauss_tableau(2)}};
    return m;
}

dampsym::Hill hill(double epsilon) {
    dampsym::Hill p;
    p.epsilon = epsilon;
    p.kappa = 1.0;
    p.q0 = 1.0;
    p.p0 = 0.5;
    return p;
}
dampsym::RigidBody rigid_body(double epsilon) {
    dampsym::RigidBody p;
    p.epsilon = epsilon;
    return p;
}
dampsym::DrivenPendulum driven_pendulum() {
    dampsym::DrivenPendulum p;
    p.q0 = 0.3;
    p.p0 = -0.2;
    return p;
}

// Calls f.template operator()<K>() for the family kernel (implicit-rk, ifrk, partitioned-rk)
// that steps `info` on P, when it applies; instantiates only these kernels (they all provide
// step_jacobian). Returns whether f was called.
template <class P, class F>
bool with_family_kernel(const MethodInfo& info, F&& f) {
    bool called = false;
    const auto try_kernel = [&]<class K>() {
        if constexpr (K::template applies<P>) {
            const auto* data = std::get_if<typename K::Data>(&info.data);
            if (!called && data != nullptr && K::accepts(*data)) {
                f.template operator()<K>();
                called = true;
            }
        }
    };
    try_kernel.template operator()<dampsym::ImplicitRK<P>>();
    try_kernel.template operator()<dampsym::IFRK<P>>();
    try_kernel.template operator()<dampsym::PartitionedRK<P>>();
    return called;
}

// n steps of size h from t = 0 with kernel K; false on a failed step. Not inlined: GCC 12 reports
// a false -Wuse-after-free inside Eigen when the kernel's constructor is inlined into the lambda.
template <class K, class P>
[[gnu::noinline]] bool run_steps(const P& prob, const MethodInfo& info, double h, int n, Vec& z,
                                 Counters& c) {
    K k(prob, info, h, c);
    for (int i = 0; i < n; ++i)
        if (k.step(dampsym::time_at(0.0, h, i), z) != StepStatus::ok) return false;
    return true;
}

// A stepper of `info` on the registered problem type P from the library, or null when no kernel
// applies; the kernel must be one of the three family kernels of this file.
template <class P>
std::unique_ptr<dampsym::AnyStepper> family_stepper(const P& prob, const MethodInfo& info, double h,
                                                    Counters& c) {
    return dampsym::test::stepper_among(prob, info, h, c,
                                        {"implicit-rk", "ifrk", "partitioned-rk"});
}

// n steps of size h from t = 0 with the family kernel of `info`; false when none applies or a step
// fails.
template <class P>
bool run(const P& prob, const MethodInfo& info, double h, int n, Vec& z, Counters& c) {
    return dampsym::test::steps_from_zero(family_stepper(prob, info, h, c).get(), h, n, z);
}

double max_rel_diff(const Vec& a, const Vec& b) {
    return (a - b).cwiseAbs().maxCoeff() / std::max(a.cwiseAbs().maxCoeff(), 1e-300);
}

// Least-squares slope of log e against log h.
double ls_slope(const std::vector<double>& h, const std::vector<double>& e) {
    double mx = 0, my = 0;
    const double n = static_cast<double>(h.size());
    for (std::size_t i = 0; i < h.size(); ++i) {
        mx += std::log(h[i]) / n;
        my += std::log(e[i]) / n;
    }
    double sxy = 0, sxx = 0;
    for (std::size_t i = 0; i < h.size(); ++i) {
        sxy += (std::log(h[i]) - mx) * (std::log(e[i]) - my);
        sxx += (std::log(h[i]) - mx) * (std::log(h[i]) - mx);
    }
    return sxy / sxx;
}

// ‖Ψᵀ J⁻¹ Ψ − e^{−2ΔΓ} J⁻¹‖_max for z = [q; p] with one degree of freedom, J⁻¹ = [0 1; −1 0].
double conformal_defect(const Mat& Psi, double dGamma) {
    Mat Jinv(2, 2);
    Jinv << 0.0, 1.0, -1.0, 0.0;
    return (Psi.transpose() * Jinv * Psi - std::exp(-2.0 * dGamma) * Jinv).cwiseAbs().maxCoeff();
}

// A scalar test problem whose implicit stage equations have no real solution for large h:
// z' = z² + 1 (plain and conformal form with γ = 0). Implicit Euler: h Z² − Z + z + h = 0 has
// discriminant 1 − 4h(z + h) < 0 for h > ½ at z = 1.
struct Riccati {
    static constexpr bool has_separable = false;
    static constexpr bool has_conformal = true;
    int dim() const { return 1; }
    double dGamma(double, double) const { return 0.0; }
    void rhs(double, const Vec& z, Vec& out) const { out[0] = z[0] * z[0] + 1.0; }
    void rhs_jacobian(double, const Vec& z, Mat& J) const { J(0, 0) = 2.0 * z[0]; }
    void N(double t, const Vec& z, Vec& out) const { rhs(t, z, out); }
    void N_jacobian(double t, const Vec& z, Mat& J) const { rhs_jacobian(t, z, J); }
};

// Separable q' = p, p' = q² + 1 − 2γp: for the fully implicit partitioned pairs (Newton path).
struct RiccatiSeparable : dampsym::SeparableProblem<RiccatiSeparable>, dampsym::UnitMass {
    static constexpr bool constant_gamma = true;
    double gamma = 0.0;
    int n() const { return 1; }
    double gamma_at(double) const { return gamma; }
    double dGamma(double, double h) const { return gamma * h; }
    template <class In, class Out>
    void force(double, const In& q, Out& out) const {
        out[0] = q[0] * q[0] + 1.0;
    }
    template <class In, class Out>
    void force_jacobian(double, const In& q, Out& out) const {
        out(0, 0) = 2.0 * q[0];
    }
};

} // namespace

TEST_CASE("generated Gauss-Legendre tableaux satisfy B(s), C(s) and symplecticity", "[families]") {
    for (int s = 1; s <= dampsym::max_gauss_stages; ++s) {
        const ButcherTableau& t = dampsym::gauss_tableau(s);
        REQUIRE(t.stages == s);
        double worst_b = 0, worst_c = 0, worst_symp = 0;
        for (int k = 1; k <= s; ++k) {
            double sb = 0;
            for (int j = 0; j < s; ++j) sb += t.b[j] * std::pow(t.c[j], k - 1);
            worst_b = std::max(worst_b, std::abs(sb - 1.0 / k));
            for (int i = 0; i < s; ++i) {
                double sa = 0;
                for (int j = 0; j < s; ++j) sa += t.A(i, j) * std::pow(t.c[j], k - 1);
                worst_c = std::max(worst_c, std::abs(sa - std::pow(t.c[i], k) / k));
            }
        }
        for (int i = 0; i < s; ++i)
            for (int j = 0; j < s; ++j)
                worst_symp = std::max(worst_symp, std::abs(t.b[i] * t.A(i, j) + t.b[j] * t.A(j, i) -
                                                           t.b[i] * t.b[j]));
        if (verbose())
            std::printf("gauss%d: B(s) %.1e  C(s) %.1e  symplecticity %.1e\n", s, worst_b, worst_c,
                        worst_symp);
        if (s <= 3) { // the catalog's methods: the bound of the brief
            CHECK(worst_b <= 1e-15);
            CHECK(worst_c <= 1e-15);
            CHECK(worst_symp <= 1e-16);
        } else { // round-off of the checks themselves grows with s
            CHECK(worst_b <= 1e-14);
            CHECK(worst_c <= 1e-14);
            CHECK(worst_symp <= 1e-15);
        }
    }
    // Closed forms: gauss1 is the midpoint rule, exactly; gauss2 nodes ½ ∓ √3/6, a12 = ¼ − √3/6.
    const ButcherTableau& g1 = dampsym::gauss_tableau(1);
    CHECK(g1.a[0] == 0.5);
    CHECK(g1.b[0] == 1.0);
    CHECK(g1.c[0] == 0.5);
    const ButcherTableau& g2 = dampsym::gauss_tableau(2);
    const double r3 = std::sqrt(3.0);
    CHECK_THAT(g2.c[0], WithinRel(0.5 - r3 / 6.0, 1e-15));
    CHECK_THAT(g2.c[1], WithinRel(0.5 + r3 / 6.0, 1e-15));
    CHECK_THAT(g2.A(0, 0), WithinAbs(0.25, 1e-16));
    CHECK_THAT(g2.A(0, 1), WithinAbs(0.25 - r3 / 6.0, 1e-16));
    CHECK_THAT(g2.b[1], WithinAbs(0.5, 1e-16));
    const ButcherTableau& g3 = dampsym::gauss_tableau(3);
    CHECK_THAT(g3.c[1], WithinAbs(0.5, 1e-16));
    CHECK_THAT(g3.b[0], WithinRel(5.0 / 18.0, 1e-15));
    CHECK_THAT(g3.b[1], WithinRel(8.0 / 18.0, 1e-15));
}

TEST_CASE("catalog rows of the family kernels", "[families]") {
    struct Row {
        const char* id;
        const char* kernel;
        const char* form;
        int order;
    };
    const Row rows[] = {
        {"implicit-euler", "implicit-rk", "plain", 1},
        {"implicit-midpoint", "implicit-rk", "plain", 2},
        {"gauss1", "implicit-rk", "plain", 2},
        {"gauss2", "implicit-rk", "plain", 4},
        {"gauss3", "implicit-rk", "plain", 6},
        {"symplectic-euler", "partitioned-rk", "separable", 1},
        {"symplectic-euler-adjoint", "partitioned-rk", "separable", 1},
        {"stormer-verlet", "partitioned-rk", "separable", 2},
        {"glifrk1", "ifrk", "conformal", 2},
        {"glifrk2", "ifrk", "conformal", 4},
        {"glifrk3", "ifrk", "conformal", 6},
    };
    for (const Row& r : rows) {
        const MethodInfo& m = method(r.id);
        CHECK(dampsym::kernel_name(m) == r.kernel);
        CHECK(dampsym::form_name(m.form) == r.form);
        CHECK(m.order == r.order);
        CHECK(tableau_of(m) != nullptr);
        CHECK((dampsym::method_data<dampsym::PartitionedTableau>(m) != nullptr) ==
              (dampsym::kernel_name(m) == "partitioned-rk"));
        const bool structure = (m.claims & dampsym::claim_conformal_symplectic) != 0;
        CHECK(structure == (dampsym::kernel_name(m) == "ifrk"));
    }
    CHECK(tableau_of(method("glifrk2")) == &dampsym::gauss_tableau(2));
    CHECK(dampsym::method_applies("stormer-verlet", "pendulum"));
    CHECK_FALSE(dampsym::method_applies("stormer-verlet", "rigid-body"));
    CHECK(dampsym::method_applies("glifrk3", "rigid-body"));
    CHECK(dampsym::method_applies("gauss2", "rigid-body"));
}

TEST_CASE("glifrk1 equals the hand-written cimp step for step", "[families]") {
    const auto compare = [](const auto& prob, double h, int n, const char* what) {
        Vec za = prob.initial_state(), zb = za;
        Counters ca, cb;
        double worst = 0;
        int bitwise = 0;
        using P = std::decay_t<decltype(prob)>;
        dampsym::Cimp<P> cimp(prob, method("cimp"), h, ca);
        dampsym::IFRK<P> ifrk(prob, method("glifrk1"), h, cb);
        for (int i = 0; i < n; ++i) {
            const double t = dampsym::time_at(0.0, h, i);
            REQUIRE(cimp.step(t, za) == StepStatus::ok);
            REQUIRE(ifrk.step(t, zb) == StepStatus::ok);
            worst = std::max(worst, max_rel_diff(za, zb));
            bitwise += (za.array() == zb.array()).all() ? 1 : 0;
        }
        if (verbose())
            std::printf("glifrk1 vs cimp, %s: max rel diff %.1e, bitwise equal steps %d/%d, "
                        "N evals %lld/%lld\n",
                        what, worst, bitwise, n, static_cast<long long>(cb.rhs_evals),
                        static_cast<long long>(ca.rhs_evals));
        CHECK(worst <= 1e-15);
        CHECK(bitwise == n); // same arithmetic (implicit_rk.hpp: update F (2Z − Y0), d = 2)
        CHECK(cb.rhs_evals == ca.rhs_evals);
        CHECK(cb.newton_iters == ca.newton_iters);
    };
    compare(pendulum(), 0.1, 300, "pendulum gamma 0.1");
    compare(rigid_body(0.5), 0.05, 400, "rigid body eps 0.5");
    compare(hill(1.0), 0.2, 200, "hill eps 1");
}

TEST_CASE("observed orders on the damped pendulum against the certified GSL reference",
          "[families]") {
    const dampsym::Pendulum prob = pendulum(); // q'' + 2γq' + sin q = 0, γ = 0.1, q0 = 1
    const double t_end = 10.0;
    const dampsym::ReferenceSolution ref = dampsym::test::pendulum_reference(prob, t_end);
    const Vec zref = ref.states.col(0);
    const double floor = std::max(100.0 * ref.error_estimate, 1e-13);
    if (verbose()) std::printf("GSL reference error estimate %.1e\n", ref.error_estimate);

    struct Case {
        const char* id;
        double expected;
        std::vector<int> steps; // step counts n, h = t_end / n
    };
    const std::vector<Case> cases{
        {"implicit-euler", 1, {800, 1600, 3200, 6400}},
        {"symplectic-euler", 1, {400, 800, 1600, 3200}},
        {"symplectic-euler-adjoint", 1, {400, 800, 1600, 3200}},
        {"implicit-midpoint", 2, {100, 200, 400, 800}},
        {"gauss1", 2, {100, 200, 400, 800}},
        {"stormer-verlet", 2, {100, 200, 400, 800}},
        {"glifrk1", 2, {100, 200, 400, 800}},
        {"gauss2", 4, {20, 40, 80, 160}},
        {"glifrk2", 4, {20, 40, 80, 160}},
        {"gauss3", 6, {10, 16, 20, 32}},
        {"glifrk3", 6, {10, 16, 20, 32}},
    };
    for (const Case& c : cases) {
        std::vector<double> hs, errs;
        Counters counters;
        for (const int n : c.steps) {
            const double h = t_end / n;
            Vec z = prob.initial_state();
            REQUIRE(run(prob, method(c.id), h, n, z, counters));
            hs.push_back(h);
            errs.push_back((z - zref).cwiseAbs().maxCoeff());
        }
        const double order = ls_slope(hs, errs);
        if (verbose()) {
            std::printf("%-26s order %.3f  errors", c.id, order);
            for (const double e : errs) std::printf(" %.2e", e);
            std::printf("\n");
        }
        INFO(c.id);
        for (const double e : errs) CHECK(e >= floor); // above the reference and round-off floor
        CHECK_THAT(order, WithinAbs(c.expected, 0.1));
    }
}

TEST_CASE("step_jacobian advances z like step() and matches central differences", "[families]") {
    const std::vector<const char*> ids{
        "implicit-euler",   "implicit-midpoint",        "gauss1",         "gauss2",  "gauss3",
        "symplectic-euler", "symplectic-euler-adjoint", "stormer-verlet", "glifrk1", "glifrk2",
        "glifrk3"};
    double worst_all = 0;
    int checked = 0;
    const auto check_problem = [&](const auto& prob, const char* what, const Vec& z0) {
        for (const char* id : ids) {
            const MethodInfo& info = method(id);
            const double h = 0.1, t = 0.7;
            Counters c;
            if (const auto stepper = family_stepper(prob, info, h, c)) {
                dampsym::AnyStepper& k = *stepper;
                REQUIRE(k.has_step_jacobian());
                Vec za = z0, zb = z0;
                Mat Psi;
                REQUIRE(k.step(t, za) == StepStatus::ok);
                REQUIRE(k.step_jacobian(t, zb, Psi) == StepStatus::ok);
                INFO(id << " on " << what);
                CHECK((za.array() == zb.array()).all());
                const int d = static_cast<int>(z0.size());
                REQUIRE(Psi.rows() == d);
                REQUIRE(Psi.cols() == d);
                const double delta = 1e-5;
                double worst = 0;
                for (int j = 0; j < d; ++j) {
                    Vec zp = z0, zm = z0;
                    zp[j] += delta;
                    zm[j] -= delta;
                    REQUIRE(k.step(t, zp) == StepStatus::ok);
                    REQUIRE(k.step(t, zm) == StepStatus::ok);
                    const Vec col = (zp - zm) / (2.0 * delta);
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
    check_problem(hill(1.0), "hill eps 1", Vec{{1.0, 0.5}});
    check_problem(rigid_body(0.5), "rigid-body eps 0.5", Vec{{4.0, 3.0, 0.5}});
    if (verbose())
        std::printf("step_jacobian vs central differences: %d (method, problem) pairs, worst "
                    "%.1e\n",
                    checked, worst_all);
    CHECK(checked == 3 * 11 + 8); // the partitioned methods do not apply to the rigid body
}

TEST_CASE("conformal symplecticity on Hill's equation: glifrk1..3 exact, gauss1..3 not",
          "[families]") {
    const dampsym::Hill prob = hill(1.0); // γ(t) = ½ cos 2t
    const double h = 0.5;
    const int n = 60;
    for (const char* id : {"glifrk1", "glifrk2", "glifrk3", "gauss1", "gauss2", "gauss3"}) {
        const MethodInfo& info = method(id);
        double worst = 0, least = std::numeric_limits<double>::infinity();
        Counters c;
        const auto k = family_stepper(prob, info, h, c);
        REQUIRE(k);
        Vec z = prob.initial_state();
        Mat Psi;
        for (int i = 0; i < n; ++i) {
            const double t = dampsym::time_at(0.0, h, i);
            REQUIRE(k->step_jacobian(t, z, Psi) == StepStatus::ok);
            const double e = conformal_defect(Psi, prob.dGamma(t, h));
            worst = std::max(worst, e);
            least = std::min(least, e);
        }
        if (verbose())
            std::printf("%-8s conformal defect on hill (eps 1, h 0.5): max %.1e, min %.1e\n", id,
                        worst, least);
        INFO(id);
        if (dampsym::method_data<dampsym::IntegratingFactorTableau>(info) != nullptr)
            CHECK(worst <= 1e-13);
        else
            CHECK(least >= 1e-8); // negative control, at every step: Gauss on the full field
    }
}

TEST_CASE("the stage-Newton solver: policies, counters, failure on NaN, inf and no convergence",
          "[families][newton]") {
    // x² − 2 = 0 from x = 1 (the solver every implicit kernel uses, methods/newton.hpp).
    const auto solve = [](dampsym::NewtonPolicy policy, double x0, auto&& residual, int& refreshes,
                          Counters& c) {
        dampsym::StageNewton nw(1);
        nw.X[0] = x0;
        refreshes = 0;
        const int it = nw.solve(policy, c, [&](bool refresh) {
            const double x = nw.X[0];
            nw.R[0] = residual(x);
            if (refresh) {
                nw.S(0, 0) = 2.0 * x;
                ++refreshes;
            }
        });
        return std::pair{it, nw.X[0]};
    };
    const auto sq = [](double x) { return x * x - 2.0; };
    int refreshes = 0;
    Counters c;
    const auto [it_full, x_full] = solve(dampsym::NewtonPolicy::full, 1.0, sq, refreshes, c);
    CHECK(it_full >= 4);
    CHECK(it_full <= 8);
    CHECK(refreshes == it_full); // full: the matrix at every iteration
    CHECK(c.newton_iters == it_full);
    CHECK_THAT(x_full, WithinRel(std::sqrt(2.0), 4e-16));
    Counters c2;
    const auto [it_simpl, x_simpl] =
        solve(dampsym::NewtonPolicy::simplified, 1.4, sq, refreshes, c2);
    CHECK(refreshes == 1); // simplified: once, at the predictor
    CHECK(it_simpl > 4);   // linear convergence
    CHECK(c2.newton_iters == it_simpl);
    CHECK_THAT(x_simpl, WithinRel(std::sqrt(2.0), 4e-16));
    // Negative controls: a NaN residual, an infinite iterate, and x² + 1 = 0 (no real root) fail.
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    Counters c3;
    CHECK(solve(
              dampsym::NewtonPolicy::full, 1.0, [&](double) { return nan; }, refreshes, c3)
              .first == 0);
    CHECK(c3.newton_iters == 1);
    CHECK(solve(
              dampsym::NewtonPolicy::full, 1.0, [&](double) { return inf; }, refreshes, c3)
              .first == 0);
    Counters c4;
    // (from 0.7 the iteration x ← (x² − 1)/(2x) wanders without converging)
    CHECK(solve(
              dampsym::NewtonPolicy::full, 0.7, [](double x) { return x * x + 1.0; }, refreshes, c4)
              .first == 0);
    CHECK(c4.newton_iters == dampsym::StageNewton::max_iterations);
}

TEST_CASE("the stage-Newton solver runs a slowly contracting iteration to round-off",
          "[families][newton]") {
    // R(x) = x − x*, S = 1/(1 − θ): the simplified iteration contracts the error by exactly θ per
    // iteration. A rule that accepts an update below 1e-10 |x| because it no longer halves stops
    // up to θ/(1−θ)·1e-10 |x| short (θ ≥ 0.5); the rule of newton.hpp stops when the update is
    // within 4 ulps (error ≤ θ/(1−θ)·4ε|x|) or the estimate θ/(1−θ)|Δx| ≤ ε|x| holds.
    struct Run {
        double theta, offset; // contraction, relative start offset (≤ 50 iterations to round-off)
    };
    for (const Run r : {Run{0.3, 1e-9}, Run{0.55, 1e-9}, Run{0.7, 1e-9}, Run{0.8, 1e-12}}) {
        const double xs = 1.0 / 3.0;
        dampsym::StageNewton nw(1);
        nw.X[0] = xs * (1.0 + r.offset);
        Counters c;
        const int it = nw.solve(dampsym::NewtonPolicy::simplified, c, [&](bool refresh) {
            nw.R[0] = nw.X[0] - xs;
            if (refresh) nw.S(0, 0) = 1.0 / (1.0 - r.theta);
        });
        INFO("theta " << r.theta << ", iterations " << it << ", error "
                      << (nw.X[0] - xs) / (std::numeric_limits<double>::epsilon() * xs) << " eps");
        REQUIRE(it > 0);
        const double bound =
            (r.theta / (1.0 - r.theta) * 4.0 + 2.0) * std::numeric_limits<double>::epsilon() * xs;
        CHECK(std::abs(nw.X[0] - xs) <= bound);
    }
    // The individual clauses of the test (ε = 2.2e-16, scale 1).
    const double e = std::numeric_limits<double>::epsilon();
    const double inf = std::numeric_limits<double>::infinity();
    CHECK(dampsym::newton_converged(2.0 * e, 1.0, inf));         // a few ulps
    CHECK_FALSE(dampsym::newton_converged(1e-12, 1.0, inf));     // first iteration: θ unknown
    CHECK(dampsym::newton_converged(2e-15, 1.0, 1e-12));         // θ = 0.002: error ≈ 4e-18 left
    CHECK_FALSE(dampsym::newton_converged(6e-11, 1.0, 1.1e-10)); // θ = 0.55: 7e-11 left
    CHECK(dampsym::newton_converged(3e-15, 1.0, 2e-15));         // stopped decreasing, at round-off
    CHECK_FALSE(dampsym::newton_converged(1e-3, 1.0, 1e-4));     // growing: not converged
}

TEST_CASE("Gauss methods keep the rigid body's quadratic invariants to round-off over many steps",
          "[families][newton]") {
    // BS's rigid body (I = (4, 3, 2), z0 = (4, 3, 0), γ = 0), h = 0.1: Gauss methods preserve the
    // Casimir and the energy exactly (quadratic invariants), so |E_n/E_0 − 1| and |F_n/F_0 − 1|
    // may only random-walk at round-off (~√n ε). A per-step bias of one ulp (the rounded
    // stage-combination update the RK engine used for s >= 2, implicit_rk.hpp) drifted gauss2
    // linearly to 4.4e-12 here. Negative control: implicit Euler drifts at O(h) per unit time.
    const dampsym::RigidBody prob = rigid_body(0.0);
    const auto invariants = [](const Vec& z) {
        const long double a = z[0], b = z[1], c = z[2];
        return std::pair{0.5L * (a * a + b * b + c * c),
                         0.5L * (a * a / 4.0L + b * b / 3.0L + c * c / 2.0L)};
    };
    const auto max_dev = [&](const char* id, int n) {
        const MethodInfo& info = method(id);
        Vec z = prob.initial_state();
        // (not a structured binding: clang 14, the sanitizer build's compiler, cannot capture one)
        const auto inv0 = invariants(z);
        const auto f0 = inv0.first, e0 = inv0.second;
        double dev = 0.0;
        Counters c;
        const auto k = family_stepper(prob, info, 0.1, c);
        REQUIRE(k);
        for (int i = 0; i < n; ++i) {
            REQUIRE(k->step(dampsym::time_at(0.0, 0.1, i), z) == StepStatus::ok);
            const auto [f, e] = invariants(z);
            dev = std::max({dev, static_cast<double>(std::abs(f / f0 - 1.0L)),
                            static_cast<double>(std::abs(e / e0 - 1.0L))});
        }
        if (verbose()) std::printf("%-14s %d steps: max |I_n/I_0 - 1| = %.2e\n", id, n, dev);
        return dev;
    };
    CHECK(max_dev("gauss2", 10000) <= 5e-13);
    CHECK(max_dev("glifrk2", 10000) <= 5e-13);
    CHECK(max_dev("gauss3", 5000) <= 5e-13);
    CHECK(max_dev("implicit-euler", 1000) >= 1e-3); // negative control
}

TEST_CASE("a stage solve that cannot converge returns solve_failed and leaves z unchanged",
          "[families]") {
    // z' = z² + 1 at z = 1 with h = 2: the stage equations have no real solution.
    const Riccati prob;
    for (const char* id : {"implicit-euler", "gauss2", "glifrk1", "glifrk3"}) {
        const MethodInfo& info = method(id);
        with_family_kernel<Riccati>(info, [&]<class K>() {
            Counters c;
            K k(prob, info, 2.0, c);
            Vec z{{1.0}};
            Mat Psi;
            INFO(id);
            CHECK(k.step(0.0, z) == StepStatus::solve_failed);
            CHECK(z[0] == 1.0);
            CHECK(k.step_jacobian(0.0, z, Psi) == StepStatus::solve_failed);
            CHECK(z[0] == 1.0);
            CHECK(c.newton_iters > 0);
            // Through the integration loop: reported as a failed solve at step 1.
            const dampsym::IntegrateOutcome out = dampsym::integrate(k, z, 0.0, 2.0, 5);
            CHECK(out.status == dampsym::RunStatus::solve_failed);
            CHECK(out.failed_step == 1);
            // A small step on the same problem converges.
            K small(prob, info, 0.01, c);
            CHECK(small.step(0.0, z) == StepStatus::ok);
        });
    }
    // Partitioned kernel, Newton path (Gauss pair): q'' = q² + 1 with a huge step.
    const MethodInfo& gauss_pair = gauss2_pair();
    const RiccatiSeparable sep;
    Counters c;
    dampsym::PartitionedRK<RiccatiSeparable> k(sep, gauss_pair, 5.0, c);
    REQUIRE_FALSE(k.scheduled());
    Vec z{{1.0, 1.0}};
    CHECK(k.step(0.0, z) == StepStatus::solve_failed);
    CHECK(z[0] == 1.0);
    CHECK(z[1] == 1.0);
}

TEST_CASE("evaluation counts per step", "[families]") {
    const dampsym::Pendulum prob = pendulum();
    const int n = 100;
    const auto per_step = [&](const char* id) {
        Counters c;
        Vec z = prob.initial_state();
        REQUIRE(run(prob, method(id), 0.1, n, z, c));
        return c;
    };
    // Partitioned: one force evaluation per used force stage, no Newton.
    CHECK(per_step("symplectic-euler").rhs_evals == 1 * n);
    CHECK(per_step("symplectic-euler-adjoint").rhs_evals == 1 * n);
    CHECK(per_step("stormer-verlet").rhs_evals == 2 * n);
    CHECK(per_step("stormer-verlet").newton_iters == 0);
    // Implicit: s evaluations per Newton iteration; one stage: nothing else (update from the
    // stage, exact coefficients), s >= 2: s more per step (the update from evaluations,
    // implicit_rk.hpp). s Jacobians per iteration for one stage (full Newton), s per step for
    // s >= 2 (simplified Newton).
    for (const char* id :
         {"implicit-euler", "gauss1", "gauss2", "gauss3", "glifrk1", "glifrk2", "glifrk3"}) {
        const Counters c = per_step(id);
        const int s = tableau_of(method(id))->stages;
        INFO(id);
        CHECK(c.rhs_evals == s * c.newton_iters + (s == 1 ? 0 : s * n));
        CHECK(c.jac_evals == (s == 1 ? s * c.newton_iters : s * n));
        CHECK(c.max_newton_iters_per_step >= 2);
        CHECK(c.max_newton_iters_per_step <= 10);
        if (verbose())
            std::printf(
                "%-16s per step: %.2f Newton iterations (max %d), %.2f evaluations of f/N\n", id,
                static_cast<double>(c.newton_iters) / n, c.max_newton_iters_per_step,
                static_cast<double>(c.rhs_evals) / n);
    }
}

namespace {
// Every partitioned (PRK, PERK) catalog method on problem `prob`: n steps through integrate()
// (the loop on the compiled shape's step, core/integrate.hpp), through the step_program() loop
// (the interpreted program) and through step_jacobian(); the states must agree bit for bit and
// the evaluation counts exactly. Returns the methods that ran on a compiled shape.
template <class P>
std::vector<std::string> compiled_equals_program(const P& prob, double t0, double h, int n) {
    using List = dampsym::KernelList<dampsym::PartitionedRK, dampsym::PartitionedExponentialRK>;
    std::vector<std::string> compiled;
    for (const MethodInfo& info : dampsym::method_catalog()) {
        dampsym::with_kernel_among<P, List>(info, [&]<class K>() {
            INFO(info.id << " on " << P::id);
            Counters ca, cb, cc;
            K a(prob, info, h, ca), b(prob, info, h, cb), c(prob, info, h, cc);
            Vec za = prob.initial_state(), zb = za, zc = za;
            Mat psi;
            const auto outcome = dampsym::integrate(a, za, t0, h, n);
            REQUIRE(outcome.status == dampsym::RunStatus::ok);
            for (int k = 0; k < n; ++k) {
                REQUIRE(b.step_program(dampsym::time_at(t0, h, k), zb) == StepStatus::ok);
                REQUIRE(c.step_jacobian(dampsym::time_at(t0, h, k), zc, psi) == StepStatus::ok);
            }
            for (Eigen::Index i = 0; i < za.size(); ++i) {
                CHECK(std::bit_cast<std::uint64_t>(za[i]) == std::bit_cast<std::uint64_t>(zb[i]));
                CHECK(std::bit_cast<std::uint64_t>(zc[i]) == std::bit_cast<std::uint64_t>(zb[i]));
            }
            CHECK(ca.rhs_evals == cb.rhs_evals);
            if (a.compiled_shape() >= 0) compiled.emplace_back(info.id);
        });
    }
    return compiled;
}
} // namespace

TEST_CASE("compiled partitioned shapes step bit for bit as the interpreted program", "[families]") {
    // Constant γ (pendulum: the force memo of stormer-verlet hits), time-dependent γ (Hill: the
    // PERK coefficients change every step), a t-dependent force (the memo must check the time),
    // two degrees of freedom (Kepler), and a start time other than 0.
    dampsym::Pendulum pendulum;
    pendulum.gamma = 0.1;
    const auto on_pendulum = compiled_equals_program(pendulum, 0.3, 0.01, 2000);
    for (const char* id : {"symplectic-euler", "symplectic-euler-adjoint", "stormer-verlet",
                           "cse-if", "cse-etd", "csv1-perk", "csv2-perk", "etdprk2"})
        CHECK(std::count(on_pendulum.begin(), on_pendulum.end(), std::string(id)) == 1);
    const auto on_hill = compiled_equals_program(hill(0.5), 0.0, 0.05, 500);
    CHECK(!on_hill.empty());
    dampsym::DrivenPendulum driven;
    driven.f = 1.2;
    CHECK(!compiled_equals_program(driven, 1.7, 0.02, 1000).empty());
    CHECK(!compiled_equals_program(dampsym::Kepler{}, 0.0, 0.01, 1000).empty());

    // Negative controls: the adjoint pair (Lobatto IIIB for q, IIIA for p) is scheduled (P₁ Q₁ Q₂
    // P₂) but has no compiled shape, so the program runs it; and the comparison sees a change of h
    // in the 12th digit.
    Counters c1, c2;
    dampsym::PartitionedRK<dampsym::Pendulum> adjoint(pendulum, dampsym::lobatto_iiib2_tableau(),
                                                      dampsym::lobatto_iiia2_tableau(), 0.01, c1);
    CHECK(adjoint.scheduled());
    CHECK(adjoint.compiled_shape() == -1);
    const MethodInfo* sv = dampsym::find_method("stormer-verlet");
    REQUIRE(sv != nullptr);
    dampsym::PartitionedRK<dampsym::Pendulum> a(pendulum, *sv, 0.01, c1),
        b(pendulum, *sv, 0.01 * (1.0 + 1e-12), c2);
    Vec za = pendulum.initial_state(), zb = za;
    dampsym::integrate(a, za, 0.0, 0.01, 100);
    dampsym::integrate(b, zb, 0.0, 0.01, 100);
    CHECK(std::bit_cast<std::uint64_t>(za[0]) != std::bit_cast<std::uint64_t>(zb[0]));
    CHECK(std::bit_cast<std::uint64_t>(za[1]) != std::bit_cast<std::uint64_t>(zb[1]));
}

TEST_CASE("partitioned and Runge-Kutta kernels agree where the methods coincide", "[families]") {
    const dampsym::Pendulum prob = pendulum();
    const double h = 0.1;
    const int n = 100;
    // Gauss for both q and p (Newton path of the partitioned kernel) is gauss2 on the full field.
    const MethodInfo& gauss_pair = gauss2_pair();
    Counters c1, c2;
    Vec za = prob.initial_state(), zb = za;
    REQUIRE(run(prob, gauss_pair, h, n, za, c1));
    REQUIRE(run(prob, method("gauss2"), h, n, zb, c2));
    // Same method, different stage unknowns and update formula: round-off differences only
    // (measured 2.4e-14 relative after 100 steps).
    INFO("gauss pair vs gauss2: " << max_rel_diff(za, zb));
    CHECK(max_rel_diff(za, zb) <= 1e-13);

    // Störmer–Verlet by hand (HLW(3.6), γ = 0): the Lobatto IIIA–IIIB pair is the same map.
    dampsym::Pendulum undamped = prob;
    undamped.gamma = 0.0;
    Vec zs = undamped.initial_state();
    Counters c3;
    REQUIRE(run(undamped, method("stormer-verlet"), h, n, zs, c3));
    double q = undamped.q0, p = undamped.p0;
    for (int i = 0; i < n; ++i) {
        const double ph = p - 0.5 * h * std::sin(q);
        q += h * ph;
        p = ph - 0.5 * h * std::sin(q);
    }
    CHECK_THAT(zs[0], WithinRel(q, 1e-14));
    CHECK_THAT(zs[1], WithinRel(p, 1e-14));

    // Symplectic Euler HLW(1.8) with damping treated by the implicit p stage.
    Vec ze = prob.initial_state();
    Counters c4;
    REQUIRE(run(prob, method("symplectic-euler"), h, 1, ze, c4));
    const double p1 = (prob.p0 - h * std::sin(prob.q0)) / (1.0 + 2.0 * h * prob.gamma);
    CHECK_THAT(ze[1], WithinRel(p1, 1e-15));
    CHECK_THAT(ze[0], WithinRel(prob.q0 + h * p1, 1e-15));

    // An explicit tableau through the implicit-rk engine is the classical RK4 loop.
    static const MethodInfo rk4_engine{"rk4-engine",
                                       4,
                                       false,
                                       dampsym::Form::plain,
                                       0u,
                                       "test",
                                       dampsym::RungeKuttaTableau{tableau_of(method("rk4"))}};
    Vec zr = prob.initial_state();
    Counters c5;
    // (the registry steps an explicit tableau with explicit-rk; the engine is called directly)
    REQUIRE(run_steps<dampsym::ImplicitRK<dampsym::Pendulum>>(prob, rk4_engine, h, n, zr, c5));
    CHECK(c5.rhs_evals == 4 * n);
    CHECK(c5.newton_iters == 0);
    Vec y = prob.initial_state(), k1(2), k2(2), k3(2), k4(2);
    for (int i = 0; i < n; ++i) {
        const double t = dampsym::time_at(0.0, h, i);
        prob.rhs(t, y, k1);
        prob.rhs(t + 0.5 * h, Vec(y + 0.5 * h * k1), k2);
        prob.rhs(t + 0.5 * h, Vec(y + 0.5 * h * k2), k3);
        prob.rhs(t + h, Vec(y + h * k3), k4);
        y += (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
    INFO("rk4 engine vs loop: " << max_rel_diff(zr, y)); // measured 1.2e-15 after 100 steps
    CHECK(max_rel_diff(zr, y) <= 1e-14);
}

TEST_CASE("IFRK from an explicit tableau (rk4 under the integrating factor) has order 4",
          "[families]") {
    // Hill's equation, time-dependent γ, reference from glifrk3 at a small step.
    const dampsym::Hill prob = hill(1.0);
    static const MethodInfo if_rk4{"if-rk4",
                                   4,
                                   false,
                                   dampsym::Form::conformal,
                                   0u,
                                   "test",
                                   dampsym::IntegratingFactorTableau{tableau_of(method("rk4"))}};
    const double t_end = 5.0;
    Vec zref = prob.initial_state();
    Counters c;
    REQUIRE(run(prob, method("glifrk3"), t_end / 400, 400, zref, c));
    std::vector<double> hs, errs;
    for (const int n : {40, 80, 160}) {
        Vec z = prob.initial_state();
        REQUIRE(run(prob, if_rk4, t_end / n, n, z, c));
        hs.push_back(t_end / n);
        errs.push_back((z - zref).cwiseAbs().maxCoeff());
    }
    const double order = ls_slope(hs, errs);
    if (verbose()) std::printf("IF-rk4 on hill: order %.3f\n", order);
    CHECK_THAT(order, WithinAbs(4.0, 0.1));
}
