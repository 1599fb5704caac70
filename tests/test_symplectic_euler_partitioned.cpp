// HLW's symplectic Euler (1.8) on a partitioned system (1.7),
// methods/symplectic_euler_partitioned.hpp: its closed form on Lotka–Volterra, its step Jacobian,
// its equality with the adjoint symplectic Euler HLW (1.9) on a separable system and its
// symplecticity there (explicit Euler as the negative control).
#include "core/method.hpp"
#include "harness/registry.hpp"
#include "methods/symplectic_euler_partitioned.hpp"
#include "support/helpers.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace dampsym;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using dampsym::test::method;
using dampsym::test::pendulum;

namespace {

LotkaVolterra lotka_volterra(double u0, double v0) {
    LotkaVolterra p;
    p.u0 = u0;
    p.v0 = v0;
    return p;
}

// ‖ΨᵀJ⁻¹Ψ − J⁻¹‖_F for a 2×2 step Jacobian (canonical z = (q, p), γ = 0).
double symplectic_defect(const Mat& Psi) {
    Mat Jinv(2, 2);
    Jinv << 0.0, 1.0, -1.0, 0.0;
    return (Psi.transpose() * Jinv * Psi - Jinv).norm();
}

} // namespace

TEST_CASE("HLW (1.8) on Lotka-Volterra is the closed form u1 = u/(1 - h(v - 2)), "
          "v1 = v(1 + h(1 - u1))",
          "[symplectic-euler-partitioned]") {
    STATIC_REQUIRE(SymplecticEulerPartitioned<LotkaVolterra>::applies<LotkaVolterra>);
    STATIC_REQUIRE_FALSE(SymplecticEulerPartitioned<Pendulum>::applies<Pendulum>);
    const LotkaVolterra lv = lotka_volterra(6.0, 2.0);
    const double h = 0.12;
    Counters c;
    // the library's compiled (kernel, problem) pair
    const auto k = dampsym::test::stepper(lv, method("symplectic-euler-partitioned"), h, c);
    Vec z = lv.initial_state();
    for (int n = 0; n < 200; ++n) {
        const double u = z[0], v = z[1];
        const double u1 = u / (1.0 - h * (v - 2.0));
        const double v1 = v * (1.0 + h * (1.0 - u1));
        REQUIRE(k->step(n * h, z) == StepStatus::ok);
        CHECK_THAT(z[0], WithinRel(u1, 4e-15));
        CHECK_THAT(z[1], WithinRel(v1, 4e-15));
    }
    CHECK(c.rhs_evals >= 2 * 200); // a Newton evaluation or more, and b at the solution
}

TEST_CASE("HLW (1.8): step_jacobian advances z like step() and matches central differences",
          "[symplectic-euler-partitioned]") {
    const LotkaVolterra lv = lotka_volterra(4.0, 2.0);
    const double h = 0.12, t = 0.3;
    Counters c;
    const auto k = dampsym::test::stepper(lv, method("symplectic-euler-partitioned"), h, c);
    const Vec z0{{3.1, 1.7}};
    Vec za = z0, zb = z0;
    Mat Psi;
    REQUIRE(k->step(t, za) == StepStatus::ok);
    REQUIRE(k->step_jacobian(t, zb, Psi) == StepStatus::ok);
    CHECK((za.array() == zb.array()).all());
    const double delta = 1e-6;
    for (int j = 0; j < 2; ++j) {
        Vec zp = z0, zm = z0;
        zp[j] += delta;
        zm[j] -= delta;
        REQUIRE(k->step(t, zp) == StepStatus::ok);
        REQUIRE(k->step(t, zm) == StepStatus::ok);
        const Vec col = (zp - zm) / (2.0 * delta);
        for (int i = 0; i < 2; ++i) CHECK_THAT(Psi(i, j), WithinAbs(col[i], 1e-8));
    }
}

TEST_CASE("on a separable system HLW (1.8) with (u, v) = (q, p) is the adjoint symplectic Euler "
          "HLW (1.9) and symplectic, explicit Euler is not",
          "[symplectic-euler-partitioned]") {
    const Pendulum prob = pendulum(0.0);
    const double h = 0.1;
    Counters c1, c2, c3;
    // the registry does not give HLW (1.8) to a separable problem: its kernel is built here; the
    // adjoint symplectic Euler and explicit Euler come compiled from the library
    SymplecticEulerPartitioned<Pendulum> se(prob, method("symplectic-euler-partitioned"), h, c1);
    const auto adj = dampsym::test::stepper(prob, method("symplectic-euler-adjoint"), h, c2);
    const auto euler = dampsym::test::stepper(prob, method("euler"), h, c3);
    Vec za{{1.1, -0.4}}, zb = za, ze = za;
    double worst_diff = 0, worst_defect = 0, euler_defect = 0;
    Mat Psi, PsiE;
    for (int n = 0; n < 100; ++n) {
        REQUIRE(se.step_jacobian(n * h, za, Psi) == StepStatus::ok);
        REQUIRE(adj->step(n * h, zb) == StepStatus::ok);
        REQUIRE(euler->step_jacobian(n * h, ze, PsiE) == StepStatus::ok);
        worst_diff = std::max(worst_diff, (za - zb).cwiseAbs().maxCoeff());
        worst_defect = std::max(worst_defect, symplectic_defect(Psi));
        euler_defect = std::max(euler_defect, symplectic_defect(PsiE));
    }
    CHECK(worst_diff <= 1e-14);
    CHECK(worst_defect <= 1e-14);
    CHECK(euler_defect >= 1e-3); // the negative control of the defect
}
