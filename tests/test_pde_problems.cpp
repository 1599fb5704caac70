// The damped Burgers and NLS problems registered for dampsym's methods
// (src/pde/{burgers,nls}/problem.hpp, docs/pde.md): dampsym's kernels on them are B's schemes —
// cimp = IF (4.15), etdrk2 = ETD (5.27), implicit-midpoint = IMP (5.28) on the NLS (the library's
// NLSStepper, src/pde/nls/schemes.hpp, solves B's printed equations); the forms' Jacobians are the
// derivatives of N; the Burgers Casimir law uses the rate factor ½ and the NLS invariants agree
// with pde::nls_invariants (B (5.29)).
#include "core/method.hpp"
#include "pde/burgers/methods.hpp"
#include "pde/burgers/problem.hpp"
#include "pde/nls/methods.hpp"
#include "pde/nls/problem.hpp"
#include "pde/nls/schemes.hpp"

#include "support/helpers.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <string_view>
#include <type_traits>

using dampsym::Counters;
using dampsym::Mat;
using dampsym::StepStatus;
using dampsym::Vec;
using dampsym::test::method;
using dampsym::test::verbose;
using cd = std::complex<double>;

namespace {

dampsym::ParamMap nls_params(int M, double gamma) {
    dampsym::ParamMap m;
    m["M"] = M;
    m["L"] = std::numbers::pi;
    m["gamma"] = gamma;
    m["lambda"] = 2.0;
    m["initial"] = 0;
    m["A"] = 1.0;
    m["k"] = 1;
    return m;
}

// A multi-mode state: ψ = 0.6 e^{ix} + 0.3 e^{−3ix} + 0.2 cos 2x.
template <class P>
Vec multimode(const P& p) {
    const int M = p.grid.M;
    Vec z(2 * M);
    for (int n = 0; n < M; ++n) {
        const double x = p.grid.x(n);
        const cd psi =
            0.6 * std::exp(cd(0, x)) + 0.3 * std::exp(cd(0, -3 * x)) + 0.2 * std::cos(2 * x);
        z[n] = psi.real();
        z[M + n] = psi.imag();
    }
    return z;
}

// Central-difference Jacobian of N, to compare with N_jacobian.
template <class P>
double jacobian_defect(const P& p, const Vec& z) {
    const int d = p.dim();
    Mat J(d, d), Jn(d, d);
    p.N_jacobian(0.0, z, J);
    Vec a(d), b(d);
    for (int j = 0; j < d; ++j) {
        Vec zp = z, zm = z;
        const double e = 1e-6;
        zp[j] += e;
        zm[j] -= e;
        p.N(0.0, zp, a);
        p.N(0.0, zm, b);
        Jn.col(j) = (a - b) / (2 * e);
    }
    return (J - Jn).cwiseAbs().maxCoeff() / J.cwiseAbs().maxCoeff();
}

// n steps of method `id` on p from (0, z) by the library's (kernel, problem) pair, whose kernel
// must be `kernel`; the final state.
template <class P>
Vec run(const P& p, const char* id, std::string_view kernel, double h, int n, Vec z) {
    Counters c;
    const auto k = dampsym::test::stepper_among(p, method(id), h, c, {kernel});
    REQUIRE(dampsym::test::steps_from_zero(k.get(), h, n, z));
    return z;
}

} // namespace

TEST_CASE("pde problems: cimp, etdrk2, implicit-midpoint on the NLS problems are B's IF (4.15), "
          "ETD (5.27), IMP (5.28)",
          "[pde]") {
    for (bool cubic : {false, true}) {
        const auto m = nls_params(32, 0.1);
        const double h = 0.01;
        const int n = 100;
        dampsym::pde::NLSParams bp;
        bp.gamma = 0.1;
        bp.lambda = 2.0;
        bp.cubic = cubic;
        auto check = [&](const auto& prob) {
            const Vec z0 = multimode(prob);
            const int M = prob.grid.M;
            CHECK(jacobian_defect(prob, z0) <= 1e-8);
            struct Row {
                const char* id;
                dampsym::pde::NLSScheme s;
            };
            for (const Row r :
                 {Row{"cimp", dampsym::pde::NLSScheme::integrating_factor},
                  Row{"etdrk2", dampsym::pde::NLSScheme::etd},
                  Row{"implicit-midpoint", dampsym::pde::NLSScheme::implicit_midpoint}}) {
                Vec z;
                if (r.s == dampsym::pde::NLSScheme::integrating_factor)
                    z = run(prob, r.id, "cimp", h, n, z0);
                else if (r.s == dampsym::pde::NLSScheme::etd)
                    z = run(prob, r.id, "exponential-rk", h, n, z0);
                else
                    z = run(prob, r.id, "implicit-rk", h, n, z0);
                dampsym::pde::CVec psi(M);
                for (int j = 0; j < M; ++j) psi[j] = cd(z0[j], z0[M + j]);
                dampsym::pde::NLSStepper st(prob.grid, bp, h, r.s);
                for (int i = 0; i < n; ++i) REQUIRE(st.step(i * h, psi));
                double d = 0, s = 0;
                for (int j = 0; j < M; ++j) {
                    d = std::max(d, std::abs(cd(z[j], z[M + j]) - psi[j]));
                    s = std::max(s, std::abs(psi[j]));
                }
                if (verbose())
                    std::printf("[pde problems] %s %s vs B's scheme: %.2e relative\n",
                                cubic ? "nls" : "schrodinger", r.id, d / s);
                INFO(r.id << (cubic ? " nls" : " schrodinger") << ": " << d / s);
                CHECK(d / s <= 1e-12);
            }
            // invariants: the problem's (Parseval) against the library's (𝒟_x by FFT)
            dampsym::pde::SpectralDerivative D(prob.grid);
            dampsym::pde::CVec psi(M);
            for (int j = 0; j < M; ++j) psi[j] = cd(z0[j], z0[M + j]);
            const auto I = dampsym::pde::nls_invariants(prob.grid, bp, D, psi);
            double out[3];
            prob.invariants(0.0, z0, out);
            if constexpr (std::decay_t<decltype(prob)>::invariant_names.size() == 3) {
                CHECK(std::abs(out[0] - I.I1) <= 1e-13 * std::abs(I.I1));
                CHECK(std::abs(out[1] - I.I2) <= 1e-13 * I.I2);
                CHECK(std::abs(out[2] - I.I3) <= 1e-13 * std::abs(I.I3));
            } else { // the cubic NLS: momentum and mass
                CHECK(std::abs(out[0] - I.I1) <= 1e-13 * std::abs(I.I1));
                CHECK(std::abs(out[1] - I.I2) <= 1e-13 * I.I2);
            }
        };
        if (cubic)
            check(dampsym::NLS::from_params(m));
        else
            check(dampsym::Schrodinger::from_params(m));
    }
}

TEST_CASE("pde problems: Burgers N_jacobian and the Casimir law with rate factor 1/2", "[pde]") {
    dampsym::ParamMap m;
    m["M"] = 33;
    m["gamma"] = 0.1;
    const auto p = dampsym::Burgers::from_params(m);
    const Vec z0 = p.initial_state();
    CHECK(jacobian_defect(p, z0) <= 1e-8);
    STATIC_REQUIRE(dampsym::invariant_rate_factor<dampsym::Burgers>(0) == 0.5);
    STATIC_REQUIRE(dampsym::invariant_rate_factor<dampsym::NLS>(0) == 1.0);
    // cimp keeps C_{n+1} = e^{-2γh} C_n = e^{-Γ(h)} C_n; the plain implicit midpoint does not
    const double h = 0.05;
    double c0, c1;
    p.invariants(0.0, z0, &c0);
    const Vec z1 = run(p, "cimp", "cimp", h, 1, z0);
    p.invariants(h, z1, &c1);
    CHECK(std::abs(c1 - std::exp(-2 * 0.1 * h) * c0) <= 1e-15 * c0);
    const Vec w1 = run(p, "implicit-midpoint", "implicit-rk", h, 1, z0);
    p.invariants(h, w1, &c1);
    CHECK(std::abs(c1 - std::exp(-2 * 0.1 * h) * c0) >= 1e-8 * c0);
}

TEST_CASE("pde problems: burgers-box and burgers-upwind (the dt -> 0 limits of B (5.12), (4.18)), "
          "B's Burgers schemes as kernels are pde::BurgersStepper",
          "[pde]") {
    dampsym::ParamMap m;
    m["M"] = 33;
    m["gamma"] = 0.1;
    const auto box = dampsym::BurgersBox::from_params(m);
    const auto up = dampsym::BurgersUpwind::from_params(m);
    const Vec z0 = box.initial_state() + 0.2 * Vec::LinSpaced(33, 0.0, 1.0).array().sin().matrix();
    CHECK(jacobian_defect(box, z0) <= 1e-8);
    CHECK(jacobian_defect(up, z0) <= 1e-8);
    // box: A_x N = -D_x(u^2/2) row by row, and sum N = 0 (the Casimir); upwind: sum N = -(1/2dx)
    // sum (u_j - u_{j-1})^2 (not conservative)
    Vec n(33);
    box.N(0.0, z0, n);
    double worst = 0.0, sq = 0.0;
    const double dx = box.grid.dx;
    for (int j = 0; j < 33; ++j) {
        const int r = (j + 1) % 33, l = (j + 32) % 33;
        worst = std::max(
            worst, std::abs(0.5 * (n[j] + n[r]) + (z0[r] * z0[r] - z0[j] * z0[j]) / (2.0 * dx)));
        sq += (z0[j] - z0[l]) * (z0[j] - z0[l]);
    }
    CHECK(worst <= 1e-13);
    CHECK(std::abs(n.sum()) <= 1e-13 * n.cwiseAbs().sum());
    up.N(0.0, z0, n);
    CHECK_THAT(n.sum(), Catch::Matchers::WithinRel(-0.5 * sq / dx, 1e-12));
    m["M"] = 32;
    CHECK_THROWS_AS(dampsym::BurgersBox::from_params(m), std::invalid_argument); // even M
    // the kernels step exactly as the library stepper (bitwise), each only on its own problem
    const auto central = dampsym::Burgers::from_params(m);
    const auto up32 = dampsym::BurgersUpwind::from_params(m);
    auto lib = [](const auto& p, dampsym::pde::BurgersScheme s, double h, int steps) {
        Vec u = p.initial_state();
        dampsym::pde::BurgersStepper st(p.grid, p.gamma, h, s);
        for (int i = 0; i < steps; ++i) REQUIRE(st.step(u));
        return u;
    };
    using dampsym::pde::BurgersScheme;
    CHECK(run(central, "burgers-csv", "burgers-csv", 0.05, 20, central.initial_state()) ==
          lib(central, BurgersScheme::csv_split, 0.05, 20));
    CHECK(run(box, "burgers-box", "burgers-box", 0.05, 20, box.initial_state()) ==
          lib(box, BurgersScheme::box, 0.05, 20));
    CHECK(run(up32, "burgers-nsfd", "burgers-nsfd", 0.05, 20, up32.initial_state()) ==
          lib(up32, BurgersScheme::nsfd, 0.05, 20));
    STATIC_REQUIRE(dampsym::BurgersCsv<dampsym::Burgers>::applies<dampsym::Burgers>);
    STATIC_REQUIRE(!dampsym::BurgersCsv<dampsym::Burgers>::applies<dampsym::BurgersBox>);
    STATIC_REQUIRE(!dampsym::BurgersBoxScheme<dampsym::Burgers>::applies<dampsym::Burgers>);
    STATIC_REQUIRE(dampsym::BurgersNsfd<dampsym::Burgers>::applies<dampsym::BurgersUpwind>);
    STATIC_REQUIRE(!dampsym::BurgersNsfd<dampsym::Burgers>::applies<dampsym::NLS>);
    // a space of another PDE is another type, even where its value is the same (central = 0)
    STATIC_REQUIRE(!dampsym::BurgersCsv<dampsym::Burgers>::applies<dampsym::NLS>);
    STATIC_REQUIRE(dampsym::NlsIf<dampsym::NLS>::applies<dampsym::NLS>);
    STATIC_REQUIRE(!dampsym::NlsIf<dampsym::NLS>::applies<dampsym::Burgers>);
    STATIC_REQUIRE(dampsym::BurgersNsfd<dampsym::Burgers>::kernel_id == "burgers-nsfd");
    STATIC_REQUIRE(dampsym::NlsEtd<dampsym::NLS>::kernel_id == "nls-etd");
    STATIC_REQUIRE(std::is_base_of_v<dampsym::SchemeKernel<dampsym::Scheme::nls_imp>,
                                     dampsym::NlsImp<dampsym::NLS>>);
}
