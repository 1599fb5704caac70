// Coefficient-level checks (src/methods/coefficient_checks.hpp) and the general linear method
// kernel (src/methods/general_linear.hpp, BS):
//  - rooted trees: 1, 1, 2, 4, 9, 20 trees of orders 1..6 (37), bi-coloured 2, 4, 14, 52, 214;
//  - every registered method: its family's checks agree with its declaration; order conditions
//    confirm the declared order and fail at the next (RK, IFRK underlying tableau, PRK);
//  - symplecticity B(1.18) holds for gauss1..3 and the symplectic PRKs, fails for rk3, rk4, heun;
//  - glm4: G-symplectic (≤ 1e−15), a perturbed GLM is not; stable, pre-consistent, consistent;
//  - the GLM kernel: Gauss as a one-value GLM equals implicit-rk (coupled Newton path), a failed
//    solve leaves everything unchanged; glm4 on BS's rigid body (I = (4,3,2), z0 = (4,3,0), ε = 0)
//    has order 4 against RigidBody::exact, and over 10 000 steps of h = 0.1 keeps E_n/E_0 and
//    F_n/F_0 near 1 without drift, while rk4's ratios drift;
//  - `dampsym methods --check` exits 0.
// Set DAMPSYM_TEST_VERBOSE=1 to print the measured numbers.
#include "cli_support.hpp"
#include "harness/registry.hpp"
#include "methods/coefficient_checks.hpp"
#include "methods/general_linear.hpp"
#include "methods/glm_coefficients.hpp"
#include "methods/tableaux.hpp"

#include "support/helpers.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <string_view>
#include <sys/wait.h>
#include <vector>

using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using dampsym::ButcherTableau;
using dampsym::Counters;
using dampsym::GlmCoefficients;
using dampsym::Mat;
using dampsym::MethodInfo;
using dampsym::RigidBody;
using dampsym::StepStatus;
using dampsym::Vec;

namespace {

using dampsym::test::method;
using dampsym::test::verbose;

// The Butcher tableau of an RK or IFRK row (the RK checks apply to it), else nullptr.
const dampsym::ButcherTableau* rk_tableau(const MethodInfo& m) {
    if (const auto* d = dampsym::method_data<dampsym::RungeKuttaTableau>(m)) return d->tableau;
    if (const auto* d = dampsym::method_data<dampsym::IntegratingFactorTableau>(m))
        return d->tableau;
    return nullptr;
}
const dampsym::PartitionedTableau* prk_pair(const MethodInfo& m) {
    return dampsym::method_data<dampsym::PartitionedTableau>(m);
}

// Least-squares slope of log y against log x.
double fit_slope(const std::vector<double>& x, const std::vector<double>& y) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    const double n = static_cast<double>(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
        const double lx = std::log(x[i]), ly = std::log(y[i]);
        sx += lx;
        sy += ly;
        sxx += lx * lx;
        sxy += lx * ly;
    }
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

// Least-squares slope of y against x (linear).
double linear_slope(const std::vector<double>& x, const std::vector<double>& y) {
    double mx = 0, my = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        mx += x[i];
        my += y[i];
    }
    mx /= static_cast<double>(x.size());
    my /= static_cast<double>(x.size());
    double sxx = 0, sxy = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        sxx += (x[i] - mx) * (x[i] - mx);
        sxy += (x[i] - mx) * (y[i] - my);
    }
    return sxy / sxx;
}

// BS's rigid body: I = (4, 3, 2), ω0 = (1, 1, 0), z0 = I ω0 = (4, 3, 0), ε = 0 (the defaults).
RigidBody bs_rigid_body() {
    return RigidBody{};
}

// Gauss–Legendre as a one-value GLM: [A e; bᵀ 1], no starting stage (y^{[0]} = z0), with the
// G-symplecticity certificate G = [1], D = diag(b) (then DA + AᵀD = BᵀGB is B(1.18)).
GlmCoefficients gauss_as_glm(int s) {
    const ButcherTableau& t = dampsym::gauss_tableau(s);
    GlmCoefficients g;
    g.name = "gauss-as-glm";
    g.s = s;
    g.r = 1;
    g.A.resize(s, s);
    g.B.resize(1, s);
    g.c.resize(s);
    for (int i = 0; i < s; ++i) {
        for (int j = 0; j < s; ++j) g.A(i, j) = t.A(i, j);
        g.B(0, i) = t.b[static_cast<std::size_t>(i)];
        g.c[i] = t.c[static_cast<std::size_t>(i)];
    }
    g.U = Mat::Ones(s, 1);
    g.V = Mat::Ones(1, 1);
    g.G = Mat::Ones(1, 1);
    g.D = g.B.row(0).transpose().asDiagonal();
    g.s0 = 0;
    g.A0.resize(0, 0);
    g.U0.resize(0);
    g.B0.resize(1, 0);
    g.V0 = Vec::Ones(1);
    g.c0.resize(0);
    g.citation = "test";
    return g;
}

MethodInfo glm_method(const GlmCoefficients& g, int order) {
    MethodInfo m{};
    m.id = g.name;
    m.order = order;
    m.implicit = true;
    m.form = dampsym::Form::plain;
    m.claims = dampsym::claim_g_symplectic;
    m.citation = "test";
    m.data = dampsym::GeneralLinearCoefficients{&g};
    return m;
}

} // namespace

TEST_CASE("rooted trees are generated with the right counts and densities", "[coefficients]") {
    const auto trees = dampsym::rooted_trees(6);
    std::vector<int> count(6, 0);
    for (const auto& t : trees) count[static_cast<std::size_t>(t.order - 1)] += 1;
    CHECK(count == std::vector<int>{1, 1, 2, 4, 9, 20});
    CHECK(trees.size() == 37);
    // Densities of the tallest (chain, γ = n!) and the bushiest (γ = n) tree of each order.
    double fact = 1;
    for (int n = 1; n <= 6; ++n) {
        fact *= n;
        double max_g = 0, min_g = std::numeric_limits<double>::infinity();
        for (const auto& t : trees)
            if (t.order == n) {
                max_g = std::max(max_g, t.gamma);
                min_g = std::min(min_g, t.gamma);
            }
        CHECK(max_g == fact);
        CHECK(min_g == n);
    }
    // Σ_{|t| = n} 1/(σ(t) γ(t)) is not needed: the exact RK4 conditions below pin γ down too.
    const auto two = dampsym::rooted_trees(5, 2);
    std::vector<int> count2(5, 0);
    for (const auto& t : two) count2[static_cast<std::size_t>(t.order - 1)] += 1;
    CHECK(count2 == std::vector<int>{2, 4, 14, 52, 214});
}

TEST_CASE("every registered method passes the coefficient checks of its family", "[coefficients]") {
    int checked = 0, unchecked = 0;
    for (const MethodInfo& m : dampsym::method_catalog()) {
        INFO("method " << m.id << " (kernel " << dampsym::kernel_name(m) << ", order " << m.order
                       << ")");
        const auto checks = dampsym::method_checks(m);
        for (const auto& c : checks) {
            INFO(c.name << ": " << c.what << ", value " << c.value);
            CHECK(c.agrees());
        }
        (checks.empty() ? unchecked : checked) += 1;
        if (rk_tableau(m) != nullptr) {
            const auto oc = dampsym::rk_order_conditions(*rk_tableau(m));
            if (verbose())
                std::printf("%-24s order %d, measured %d, residual at order+1 %.2e\n",
                            std::string(m.id).c_str(), m.order, oc.measured_order,
                            m.order < 6 ? oc.residual[static_cast<std::size_t>(m.order)] : 0.0);
            if (m.order < dampsym::rk_max_tree_order) {
                CHECK(oc.measured_order == m.order);
                CHECK(oc.residual[static_cast<std::size_t>(m.order)] > 1e-6);
            } else {
                CHECK(oc.measured_order == dampsym::rk_max_tree_order);
            }
            CHECK_FALSE(checks.empty());
        } else if (prk_pair(m) != nullptr) {
            const auto oc = dampsym::prk_order_conditions(*prk_pair(m)->q, *prk_pair(m)->p);
            CHECK(oc.measured_order == m.order);
            CHECK(oc.residual[static_cast<std::size_t>(m.order)] > 1e-6);
        } else if (dampsym::method_data<dampsym::GeneralLinearCoefficients>(m) != nullptr) {
            CHECK(checks.size() == 6);
        }
    }
    CHECK(checked >= 16);
    // Hand-written schemes have no coefficient data.
    for (const char* id : {"cimp", "csv1", "csv2"})
        CHECK(dampsym::method_checks(method(id)).empty());
    if (verbose()) std::printf("methods with checks %d, without %d\n", checked, unchecked);
}

TEST_CASE("symplecticity on the coefficients: Gauss and the symplectic PRKs hold, negative "
          "controls fail",
          "[coefficients]") {
    for (const char* id : {"gauss1", "gauss2", "gauss3", "implicit-midpoint"}) {
        INFO(id);
        const double r = dampsym::rk_symplecticity_residual(*rk_tableau(method(id)));
        if (verbose()) std::printf("%s: symplecticity residual %.2e\n", id, r);
        CHECK(r <= 1e-15);
    }
    for (const char* id : {"symplectic-euler", "symplectic-euler-adjoint", "stormer-verlet"}) {
        INFO(id);
        const auto ps =
            dampsym::prk_symplecticity(*prk_pair(method(id))->q, *prk_pair(method(id))->p);
        CHECK(ps.condition <= 1e-15);
        CHECK(ps.weights == 0.0);
    }
    for (const char* id : {"rk3", "rk4", "heun", "euler", "implicit-euler"}) {
        INFO(id);
        const double r = dampsym::rk_symplecticity_residual(*rk_tableau(method(id)));
        if (verbose()) std::printf("%s: symplecticity residual %.2e (negative control)\n", id, r);
        CHECK(r > 1e-3);
    }
    // A PRK pair that is not symplectic: explicit Euler for both parts.
    const auto& ee = dampsym::explicit_euler_tableau();
    CHECK(dampsym::prk_symplecticity(ee, ee).condition == 1.0);
}

TEST_CASE("glm4 is G-symplectic, stable, pre-consistent and consistent (BS, BD Defs 2.1-2.3)",
          "[coefficients]") {
    const GlmCoefficients& g = dampsym::butcher_glm4();
    const auto gs = dampsym::glm_g_symplecticity(g);
    if (verbose())
        std::printf("glm4 G-symplecticity residuals: DA+AtD-BtGB %.2e, G-VtGV %.2e, DU-BtGV %.2e\n",
                    gs.stages, gs.values, gs.coupling);
    CHECK(gs.certificate_valid);
    CHECK(gs.stages <= 1e-15);
    CHECK(gs.values <= 1e-15);
    CHECK(gs.coupling <= 1e-15);

    const auto st = dampsym::glm_stability(g);
    CHECK(st.power_bounded);
    CHECK_THAT(st.spectral_radius, WithinAbs(1.0, 1e-15));
    CHECK_THAT(st.max_power_norm, WithinAbs(1.0, 1e-15));

    const auto pre = dampsym::glm_preconsistency(g);
    CHECK(pre.residual <= 1e-15);
    CHECK_THAT(pre.vector[0], WithinAbs(1.0, 1e-15)); // u = (1, 0): y_1 carries the solution
    CHECK_THAT(pre.vector[1], WithinAbs(0.0, 1e-15));
    CHECK(dampsym::glm_consistency(g).residual <= 1e-15);

    // c = A e (the data's abscissae).
    CHECK(((g.A * Vec::Ones(2)) - g.c).cwiseAbs().maxCoeff() <= 1e-15);

    // Perturbed GLMs fail: one entry of A (G-symplecticity), a Jordan block in V (stability),
    // U without e in its range (pre-consistency).
    GlmCoefficients bad = g;
    bad.A(1, 0) += 1e-3;
    CHECK(dampsym::glm_g_symplecticity(bad).stages > 1e-4);
    MethodInfo bad_info = glm_method(bad, 4);
    bool g_check_seen = false;
    for (const auto& c : dampsym::method_checks(bad_info))
        if (c.name == "g-symplectic") {
            g_check_seen = true;
            CHECK_FALSE(c.holds);
            CHECK_FALSE(c.agrees());
        }
    CHECK(g_check_seen);
    GlmCoefficients jordan = g;
    jordan.V = Mat{{1.0, 1.0}, {0.0, 1.0}};
    CHECK_FALSE(dampsym::glm_stability(jordan).power_bounded);
    CHECK(dampsym::glm_stability(jordan).max_power_norm >= 1000.0);
    GlmCoefficients growing = g;
    growing.V(1, 1) = -1.01;
    CHECK_FALSE(dampsym::glm_stability(growing).power_bounded);
    GlmCoefficients no_pre = g;
    no_pre.U(1, 0) = 0.5;
    CHECK(dampsym::glm_preconsistency(no_pre).residual > 1e-3);

    // A one-value GLM built from Gauss: its G-symplecticity is B(1.18).
    for (int s = 1; s <= 3; ++s) {
        const auto gg = dampsym::glm_g_symplecticity(gauss_as_glm(s));
        CHECK(gg.certificate_valid);
        CHECK(gg.max() <= 1e-15);
    }
}

TEST_CASE("a one-value GLM without starting stages (Gauss as a GLM) has its linear-order and "
          "stage-time checks; a 1e-6 in a weight or a stage time fails them",
          "[coefficients]") {
    // s0 = 0: y^[0] = V₀ y₀, so S(z) = V₀ and the stage times are c = A e. These checks gave NaN
    // (a failure) for every such method, so an RK method written as a GLM was "refuted".
    const auto verdict = [](const GlmCoefficients& g, int order, const std::string& name) {
        for (const auto& c : dampsym::method_checks(glm_method(g, order)))
            if (c.name == name) return c.holds;
        FAIL("no check " << name);
        return false;
    };
    for (int s = 1; s <= 3; ++s) {
        const GlmCoefficients g = gauss_as_glm(s);
        INFO("gauss" << s);
        CHECK(verdict(g, 2 * s, "linear-order-" + std::to_string(2 * s)));
        CHECK(verdict(g, 2 * s, "stage-times"));
        CHECK_FALSE(verdict(g, 2 * s + 1, "linear-order-" + std::to_string(2 * s + 1))); // sharp
    }
    GlmCoefficients weight = gauss_as_glm(2);
    weight.B(0, 1) *= 1.0 + 1e-6;
    CHECK_FALSE(verdict(weight, 4, "linear-order-4"));
    GlmCoefficients time = gauss_as_glm(2);
    time.c[1] *= 1.0 + 1e-6;
    CHECK(verdict(time, 4, "linear-order-4"));
    CHECK_FALSE(verdict(time, 4, "stage-times"));
}

TEST_CASE("general-linear kernel: Gauss as a one-value GLM equals implicit-rk, failed solves "
          "change nothing",
          "[coefficients]") {
    const RigidBody prob = bs_rigid_body();
    const double h = 0.1;
    const GlmCoefficients g = gauss_as_glm(2);
    const MethodInfo info = glm_method(g, 4);
    Counters ca, cb;
    // the library's compiled kernels (the GLM kernel steps a GLM of any coefficients)
    const auto glm = dampsym::test::stepper(prob, info, h, ca);
    const auto irk = dampsym::test::stepper(prob, method("gauss2"), h, cb);
    // Step by step from the same state (the one-value GLM takes its input from z): the two
    // kernels differ only in how the update is formed (hBF with hF = A⁻¹(Y − U y) here,
    // z + h Σ b_i f(Z_i) at the converged stages in implicit_rk.hpp for s ≥ 2, s = 2 more
    // evaluations per step), i.e. by round-off per step.
    Vec za = prob.initial_state(), zb = za;
    double worst = 0;
    for (int n = 0; n < 200; ++n) {
        const double t = dampsym::time_at(0.0, h, n);
        zb = za;
        REQUIRE(glm->step(t, za) == StepStatus::ok);
        REQUIRE(irk->step(t, zb) == StepStatus::ok);
        worst = std::max(worst, (za - zb).cwiseAbs().maxCoeff() / za.cwiseAbs().maxCoeff());
    }
    if (verbose()) std::printf("gauss2 as GLM vs implicit-rk: max rel diff per step %.2e\n", worst);
    CHECK(worst <= 1e-14);
    CHECK(ca.newton_iters == cb.newton_iters);
    CHECK(ca.rhs_evals + 2 * 200 == cb.rhs_evals);

    // Failed solve: a NaN input returns solve_failed and leaves z and the stored values alone:
    // the run then continues bit for bit as one without the failure (stored values changed by
    // the failed step would change the next step).
    Counters c1, c2;
    const MethodInfo& g4 = method("glm4");
    const auto a = dampsym::test::stepper(prob, g4, h, c1),
               b = dampsym::test::stepper(prob, g4, h, c2);
    Vec z1 = prob.initial_state(), z2 = z1;
    REQUIRE(a->step(0.0, z1) == StepStatus::ok);
    REQUIRE(b->step(0.0, z2) == StepStatus::ok);
    Vec bad = Vec::Constant(3, std::numeric_limits<double>::quiet_NaN());
    CHECK(a->step(h, bad) == StepStatus::solve_failed);
    for (int n = 1; n <= 3; ++n) {
        REQUIRE(a->step(n * h, z1) == StepStatus::ok);
        REQUIRE(b->step(n * h, z2) == StepStatus::ok);
        CHECK((z1.array() == z2.array()).all());
    }
    // A failed starting method leaves the kernel unstarted.
    const auto fresh = dampsym::test::stepper(prob, g4, h, c1);
    Vec nan_start = Vec::Constant(3, std::numeric_limits<double>::quiet_NaN());
    CHECK(fresh->step(0.0, nan_start) == StepStatus::solve_failed);
    Vec z3 = prob.initial_state();
    REQUIRE(fresh->step(0.0, z3) == StepStatus::ok);
    Vec z4 = prob.initial_state();
    const auto ref = dampsym::test::stepper(prob, g4, h, c2);
    REQUIRE(ref->step(0.0, z4) == StepStatus::ok);
    CHECK((z3.array() == z4.array()).all());
}

TEST_CASE("glm4 on BS's rigid body: order 4 against the exact solution", "[coefficients]") {
    // ε = 0 is BS's free body; ε = 0.5 (γ(t) = ¼ cos 2t) also exercises the stage times c and c₀
    // of the non-autonomous plain form (wrong stage times would lower the order).
    for (const double epsilon : {0.0, 0.5}) {
        RigidBody prob = bs_rigid_body();
        prob.epsilon = epsilon;
        const MethodInfo& info = method("glm4");
        const double t_end = 4.0;
        Vec exact(3);
        prob.exact(0.0, prob.initial_state(), t_end, exact);
        std::vector<double> hs, errs;
        for (const int n : {20, 40, 80, 160}) {
            const double h = t_end / n;
            Counters c;
            const auto k = dampsym::test::stepper(prob, info, h, c); // the library's kernel
            Vec z = prob.initial_state();
            for (int i = 0; i < n; ++i)
                REQUIRE(k->step(dampsym::time_at(0.0, h, i), z) == StepStatus::ok);
            hs.push_back(h);
            errs.push_back((z - exact).norm());
            if (verbose())
                std::printf("glm4 rigid body eps %.1f h = %.4f: error %.3e, rhs evals %lld, "
                            "newton %lld\n",
                            epsilon, h, errs.back(), static_cast<long long>(c.rhs_evals),
                            static_cast<long long>(c.newton_iters));
        }
        const double p = fit_slope(hs, errs);
        if (verbose()) std::printf("glm4 measured order (eps %.1f) %.3f\n", epsilon, p);
        INFO("epsilon " << epsilon);
        CHECK_THAT(p, WithinAbs(4.0, 0.1));
        CHECK(errs.back() > 1e-12); // above the round-off floor
    }
}

TEST_CASE("glm4 keeps E_n/E_0 and F_n/F_0 near 1 without drift over 10 000 steps, rk4 drifts (BS)",
          "[coefficients]") {
    const RigidBody prob = bs_rigid_body();
    const double h = 0.1;
    const int n_steps = 10000;
    struct Ratios {
        double max_dev_E = 0, max_dev_F = 0, slope_E = 0, slope_F = 0;
    };
    auto run = [&](const MethodInfo& info) {
        Ratios r;
        Vec z = prob.initial_state();
        const double E0 = prob.energy(z), F0 = z.squaredNorm();
        std::vector<double> ts, dE, dF;
        Counters c;
        const auto k = dampsym::test::stepper(prob, info, h, c); // the library's kernel
        for (int i = 0; i < n_steps; ++i) {
            REQUIRE(k->step(dampsym::time_at(0.0, h, i), z) == StepStatus::ok);
            const double e = prob.energy(z) / E0 - 1.0, f = z.squaredNorm() / F0 - 1.0;
            r.max_dev_E = std::max(r.max_dev_E, std::abs(e));
            r.max_dev_F = std::max(r.max_dev_F, std::abs(f));
            ts.push_back(dampsym::time_at(0.0, h, i + 1));
            dE.push_back(e);
            dF.push_back(f);
        }
        r.slope_E = linear_slope(ts, dE);
        r.slope_F = linear_slope(ts, dF);
        if (verbose())
            std::printf("%s, %d steps of h = %.2f: max|E/E0-1| %.2e, max|F/F0-1| %.2e, drift "
                        "slopes %.2e, %.2e per unit time\n",
                        std::string(info.id).c_str(), n_steps, h, r.max_dev_E, r.max_dev_F,
                        r.slope_E, r.slope_F);
        return r;
    };
    const Ratios g = run(method("glm4"));
    const Ratios k = run(method("rk4"));
    const double T = n_steps * h;
    // glm4: small and bounded (the slope over the whole run explains a negligible part of it).
    CHECK(g.max_dev_E <= 1e-4);
    CHECK(g.max_dev_F <= 1e-4);
    CHECK(std::abs(g.slope_E) * T <= 0.1 * g.max_dev_E);
    CHECK(std::abs(g.slope_F) * T <= 0.1 * g.max_dev_F);
    // rk4: a measurable monotone drift that dominates its deviation and exceeds glm4's.
    CHECK(std::abs(k.slope_E) * T >= 0.5 * k.max_dev_E);
    CHECK(std::abs(k.slope_F) * T >= 0.5 * k.max_dev_F);
    CHECK(std::abs(k.slope_E) >= 100.0 * std::abs(g.slope_E));
    CHECK(std::abs(k.slope_F) >= 100.0 * std::abs(g.slope_F));
    CHECK(k.max_dev_E > g.max_dev_E);
    CHECK(k.max_dev_F > g.max_dev_F);
}

TEST_CASE("glm4 conserves the G-weighted quadratic forms of its two values to round-off (BS)",
          "[coefficients]") {
    // BS: Σ g_ij y_iᵀ M y_j is conserved for a quadratic invariant yᵀMy when DA + AᵀD = BᵀGB,
    // G = VᵀGV, DU = BᵀGV. Rigid body: M = I (Casimir F) and M = I⁻¹ (E = 2H).
    const RigidBody prob = bs_rigid_body();
    const MethodInfo& info = method("glm4");
    const Mat& G = dampsym::method_data<dampsym::GeneralLinearCoefficients>(info)->glm->G;
    const Mat casimir_matrix = Mat::Identity(3, 3);
    const Mat energy_matrix = Vec{{1.0 / prob.I1, 1.0 / prob.I2, 1.0 / prob.I3}}.asDiagonal();
    auto weighted = [&](const Mat& y, const Mat& M) {
        return (G * (y.transpose() * M * y)).trace();
    };
    Counters c;
    // the library's glm4 kernel on the rigid body; its two values are read through its type
    // (a cast names the stepper's type and compiles no step)
    const auto stepper = dampsym::test::stepper(prob, info, 0.1, c);
    auto* typed =
        dynamic_cast<dampsym::StepperOf<dampsym::GeneralLinear<RigidBody>>*>(stepper.get());
    REQUIRE(typed != nullptr);
    dampsym::AnyStepper& step = *stepper;
    const dampsym::GeneralLinear<RigidBody>& k = typed->kernel();
    Vec z = prob.initial_state();
    REQUIRE(step.step(0.0, z) == StepStatus::ok);
    const double F1 = weighted(k.values(), casimir_matrix),
                 E1 = weighted(k.values(), energy_matrix);
    double dF = 0, dE = 0;
    for (int i = 1; i < 10000; ++i) {
        REQUIRE(step.step(dampsym::time_at(0.0, 0.1, i), z) == StepStatus::ok);
        dF = std::max(dF, std::abs(weighted(k.values(), casimir_matrix) / F1 - 1.0));
        dE = std::max(dE, std::abs(weighted(k.values(), energy_matrix) / E1 - 1.0));
    }
    if (verbose())
        std::printf("glm4 G-weighted forms over 10000 steps: max rel change F %.2e, E %.2e\n", dF,
                    dE);
    CHECK(dF <= 1e-12);
    CHECK(dE <= 1e-12);
}

TEST_CASE("dampsym methods --check agrees with every declaration", "[coefficients][cli]") {
    const std::string bin = dampsym_test::binary_path();
    auto status_of = [&](const std::string& rest) {
        const std::string cmd = "'" + bin + "' " + rest + " > /dev/null 2>&1";
        const int raw = std::system(cmd.c_str());
        return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    };
    CHECK(status_of("methods --check") == 0);
    CHECK(status_of("methods") == 0);

    const auto r = dampsym_test::run({"methods", "--check", "--json"});
    INFO(r.err);
    REQUIRE(r.status == 0);
    const auto j = nlohmann::json::parse(r.out);
    CHECK(j["summary"]["checks_failed"] == 0);
    CHECK(j["methods"].size() == dampsym::method_catalog().size());
    bool saw_glm = false, saw_cimp = false;
    for (const auto& m : j["methods"]) {
        if (m["id"] == "glm4") {
            saw_glm = true;
            CHECK(m["claims"] == nlohmann::json::array({"g-symplectic"}));
            std::vector<std::string> names;
            for (const auto& c : m["checks"]) {
                names.push_back(c["name"].get<std::string>());
                CHECK(c["passed"] == true);
            }
            CHECK(names == std::vector<std::string>{"g-symplectic", "stable", "pre-consistent",
                                                    "consistent", "linear-order-4", "stage-times"});
        }
        if (m["id"] == "cimp") {
            saw_cimp = true;
            CHECK(m["checks"].is_null());
            CHECK(m["note"] == "no coefficient-level check");
        }
        if (m["id"] == "rk4") {
            bool saw_fail_at_5 = false;
            for (const auto& c : m["checks"])
                if (c["name"] == "order-conditions-5") {
                    saw_fail_at_5 = true;
                    CHECK(c["holds"] == false);
                    CHECK(c["passed"] == true);
                }
            CHECK(saw_fail_at_5);
        }
    }
    CHECK(saw_glm);
    CHECK(saw_cimp);
    const auto text = dampsym_test::run({"methods", "--check"});
    CHECK(text.status == 0);
    CHECK(text.out.find("no coefficient-level check") != std::string::npos);
    CHECK(text.out.find("FAIL") == std::string::npos);
}
