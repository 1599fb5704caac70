// B Fig 5.10 (damped driven NLS): the nls-driven problem's forcing, B's own schemes
// nls-if/-etd/-imp (src/pde/nls/methods.hpp) against dampsym's cimp/etdrk2/implicit-midpoint on the
// same problem, and the `attractor` diagnostic's statistics on signals with known answers.
#include "core/method.hpp"
#include "diagnostics/attractor_diagnostic.hpp"
#include "pde/nls/problem.hpp"
#include "pde/nls/schemes.hpp"

#include "support/helpers.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <complex>
#include <numbers>
#include <string_view>

using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using dampsym::Counters;
using dampsym::StepStatus;
using dampsym::Vec;
using dampsym::test::method;

namespace {

dampsym::NLSDriven driven(double Gamma) {
    dampsym::ParamMap m;
    for (const auto& s : dampsym::NLSDriven::param_specs()) m[s.name] = s.default_value;
    m["M"] = 32;
    m["L"] = std::numbers::sqrt2 * std::numbers::pi;
    m["gamma"] = 0.2;
    m["Gamma"] = Gamma;
    m["alpha"] = 0.3;
    return dampsym::NLSDriven::from_params(m);
}

// n steps of method `id` by the library's (kernel, problem) pair, whose kernel must be `kernel`.
template <class P>
Vec steps(std::string_view kernel, const P& p, const char* id, double h, int n, double t0, Vec z) {
    CHECK(dampsym::test::kernel<P>(method(id)).kernel_id == kernel);
    Counters c;
    const auto k = dampsym::test::stepper(p, method(id), h, c);
    for (int i = 0; i < n; ++i) REQUIRE(k->step(t0 + i * h, z) == StepStatus::ok);
    return z;
}

double rel_diff(const Vec& a, const Vec& b) {
    return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

} // namespace

TEST_CASE("nls-driven: B's IF, ETD, IMP by FFT are cimp, etdrk2, implicit-midpoint with the "
          "forcing at the midpoint time, the forcing matters",
          "[attractor]") {
    const auto p = driven(0.45);
    const Vec z0 = p.initial_state();
    CHECK(z0[16] == 3.0); // 3 sech(3x) at x = 0 (grid point M/2)
    CHECK(p.probe(z0) == 3.0);
    const double h = 0.02, t0 = 1.7;
    const int n = 50;
    // Two solvers of the same equations, each to round-off: the difference is round-off amplified
    // by the 3 sech 3x soliton's fast phase (4.8e-12 after 50 steps, measured).
    constexpr double tol = 1e-10;
    const Vec a = steps("nls-if", p, "nls-if", h, n, t0, z0);
    const Vec b = steps("cimp", p, "cimp", h, n, t0, z0);
    CHECK(rel_diff(a, b) <= tol);
    const Vec c = steps("nls-etd", p, "nls-etd", h, n, t0, z0);
    const Vec d = steps("exponential-rk", p, "etdrk2", h, n, t0, z0);
    CHECK(rel_diff(c, d) <= tol);
    const Vec e = steps("nls-imp", p, "nls-imp", h, n, t0, z0);
    const Vec f = steps("implicit-rk", p, "implicit-midpoint", h, n, t0, z0);
    CHECK(rel_diff(e, f) <= tol);
    // negative controls: IF and IMP are different maps; without the forcing the states differ
    CHECK(rel_diff(a, e) >= 1e-6);
    const auto q = driven(0.0);
    CHECK(rel_diff(steps("nls-if", q, "nls-if", h, n, t0, z0), a) >= 1e-3);
    // the forcing's phase: N at t and at t + 2π/ω₀ agree, at t + π/ω₀ they do not
    Vec n1(p.dim()), n2(p.dim()), n3(p.dim());
    p.N(0.4, z0, n1);
    p.N(0.4 + 2.0 * std::numbers::pi, z0, n2);
    p.N(0.4 + std::numbers::pi, z0, n3);
    CHECK(rel_diff(n2, n1) <= 1e-12);
    CHECK((n3 - n1).cwiseAbs().maxCoeff() >= 0.6); // 2Γ(|sin θ|, |cos θ|): at least 2Γ/√2
}

TEST_CASE("attractor: statistics of a periodic and of a constant probe", "[attractor]") {
    dampsym::CaseFacts c;
    c.t0 = 0.0;
    c.t_end = 100.0;
    c.points = 10000; // output every 0.01
    const double T = 2.5;
    dampsym::Mat g(1, c.points + 1);
    for (int i = 0; i <= c.points; ++i)
        g(0, i) = 2.0 + std::sin(2.0 * std::numbers::pi * c.grid_time(i) / T);
    auto probe = [](const Vec& z) { return z[0]; };
    const auto m = dampsym::attractor_metrics(c, g, "s", probe);
    CHECK(m["from"].get<double>() == 50.0);
    CHECK(m["points"].get<int>() == 5001);
    CHECK_THAT(m["mean"].get<double>(), WithinAbs(2.0, 1e-3));
    CHECK_THAT(m["std"].get<double>(), WithinRel(1.0 / std::numbers::sqrt2, 1e-3));
    CHECK_THAT(m["max"].get<double>(),
               WithinAbs(3.0, 1e-4)); // sampled every 0.01: the crest is missed by ≤ 8e-5
    CHECK_THAT(m["q50"].get<double>(), WithinAbs(2.0, 1e-2));
    CHECK_THAT(m["period"].get<double>(), WithinRel(T, 1e-6));
    CHECK(m["period_spread"].get<double>() <= 1e-6);
    CHECK(m["crossings"].get<int>() == 20);
    // an irregular probe (two incommensurate periods) has a period spread of order 1
    for (int i = 0; i <= c.points; ++i) {
        const double t = c.grid_time(i);
        g(0, i) =
            2.0 + std::sin(2.0 * std::numbers::pi * t / T) + 0.8 * std::sin(std::numbers::e * t);
    }
    const auto q = dampsym::attractor_metrics(c, g, "s", probe);
    CHECK(q["period_spread"].get<double>() >= 0.2); // 0.29
    // a constant probe: no period, and the reason is given
    g.setConstant(0.5);
    const auto k = dampsym::attractor_metrics(c, g, "s", probe);
    CHECK(k["std"].get<double>() == 0.0);
    CHECK(k["mean_se"].get<double>() <= 1e-15); // round-off of the batch means
    CHECK(k["period"].is_null());
    CHECK(k["undefined"]["period"].get<std::string>().find("constant") != std::string::npos);
    // too short a window
    c.points = 10;
    const auto s = dampsym::attractor_metrics(c, dampsym::Mat::Ones(1, 11), "s", probe);
    CHECK(s["mean"].is_null());
}

TEST_CASE("nls-driven: a fixed-point iteration that overflows is a failed solve, not a NaN state",
          "[attractor]") {
    dampsym::ParamMap m;
    for (const auto& s : dampsym::NLSDriven::param_specs()) m[s.name] = s.default_value;
    m["M"] = 16;
    m["A"] = 10.0;
    m["Gamma"] = 100.0;
    m["omega0"] = 100.0;
    const auto p = dampsym::NLSDriven::from_params(m);
    Vec z = p.initial_state();
    const Vec z0 = z;
    Counters c;
    const auto k = dampsym::test::stepper(p, method("nls-if"), 0.5, c); // the library's pair
    CHECK(k->step(0.0, z) == StepStatus::solve_failed);
    CHECK(z == z0); // the state of the last good step
    dampsym::pde::NLSStepper st(p.grid, p.nls_params(), 0.5,
                                dampsym::pde::NLSScheme::integrating_factor);
    dampsym::pde::CVec psi(16);
    for (int n = 0; n < 16; ++n) psi[n] = {z0[n], z0[16 + n]};
    CHECK_FALSE(st.step(0.0, psi));
    CHECK(st.why().find("non-finite") != std::string::npos);
    // the same problem at a small step converges
    Vec z1 = z0;
    const auto k1 = dampsym::test::stepper(p, method("nls-if"), 1e-4, c);
    CHECK(k1->step(0.0, z1) == StepStatus::ok);
    CHECK(z1.allFinite());
}
