// Diagnostic "pde-error" (B Fig 5.4; docs/conventions.md §5) and the solution of B's modified
// Burgers (4.5) by characteristics it compares with (src/pde/burgers/schemes.hpp).
#include "diagnostics/pde_error_diagnostic.hpp"
#include "pde/burgers/schemes.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <numbers>

using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using dampsym::Vec;
using dampsym::pde::PeriodicGrid;

TEST_CASE("pde-error: Burgers' characteristic solution is the Gaussian at 0 and solves (4.5)",
          "[pde-error]") {
    const PeriodicGrid g(64, std::numbers::pi);
    Vec u;
    REQUIRE(dampsym::pde::burgers_characteristic_solution(g, 0.1, 0.0, u));
    CHECK((u.array() == dampsym::pde::burgers_gaussian(g).array()).all());
    // u_t + u u_x + 2γu = 0 by central differences in t and x (truncation O(δ² + Δx²)): the
    // residual is small and falls 4× when δ and Δx halve (a wrong solution leaves an O(1) one;
    // with u_t + u u_x = 0, the undamped equation, the γ = 0.1 solution leaves 2γu ~ 0.07)
    for (const double gamma : {0.0, 0.1}) {
        const double tau = 3.0;
        double worst[2] = {0.0, 0.0};
        Vec a;
        for (int level = 0; level < 2; ++level) {
            const PeriodicGrid f(2048 << level, std::numbers::pi);
            const double d = 2e-4 / (1 << level);
            Vec b, c;
            REQUIRE(dampsym::pde::burgers_characteristic_solution(f, gamma, tau, a));
            REQUIRE(dampsym::pde::burgers_characteristic_solution(f, gamma, tau - d, b));
            REQUIRE(dampsym::pde::burgers_characteristic_solution(f, gamma, tau + d, c));
            for (int n = 0; n < f.M; ++n) {
                // away from x = ±π, where the periodic extension of the Gaussian has a kink
                // (u0' jumps by 2π φ(π)) that a central difference does not resolve
                if (std::abs(f.x(n)) > 2.5) continue;
                const double ut = (c[n] - b[n]) / (2 * d);
                const double ux = (a[f.wrap(n + 1)] - a[f.wrap(n - 1)]) / (2 * f.dx);
                worst[level] = std::max(worst[level], std::abs(ut + a[n] * ux + 2 * gamma * a[n]));
            }
        }
        if (gamma > 0) { // the negative control: the undamped solution in the damped equation
            const PeriodicGrid f(4096, std::numbers::pi);
            const double d = 1e-4;
            Vec a0, b0, c0;
            REQUIRE(dampsym::pde::burgers_characteristic_solution(f, 0.0, tau, a0));
            REQUIRE(dampsym::pde::burgers_characteristic_solution(f, 0.0, tau - d, b0));
            REQUIRE(dampsym::pde::burgers_characteristic_solution(f, 0.0, tau + d, c0));
            double wrong = 0.0;
            for (int n = 0; n < f.M; ++n) {
                const double ut = (c0[n] - b0[n]) / (2 * d);
                const double ux = (a0[f.wrap(n + 1)] - a0[f.wrap(n - 1)]) / (2 * f.dx);
                wrong = std::max(wrong, std::abs(ut + a0[n] * ux + 2 * gamma * a0[n]));
            }
            CHECK(wrong >= 1e-2);
        }
        INFO("gamma " << gamma << ": residuals " << worst[0] << ", " << worst[1]);
        CHECK(worst[1] <= 1e-4);
        CHECK(worst[0] / worst[1] >= 3.5);
        const PeriodicGrid f(4096, std::numbers::pi);
        // the mass decays as e^{-2γt} (B (5.14)): Δx Σ u to the grid's quadrature accuracy
        CHECK_THAT(f.dx * a.sum(), WithinRel(std::exp(-2 * gamma * tau) * f.dx *
                                                 dampsym::pde::burgers_gaussian(f).sum(),
                                             1e-6));
    }
}

TEST_CASE("pde-error: the shock time of the Gaussian, and no solution from it on", "[pde-error]") {
    const double sb = std::sqrt(2 * std::numbers::pi * std::exp(1.0)); // 1/φ(1) = 4.13
    CHECK_THAT(dampsym::pde::burgers_gaussian_shock_time(0.0), WithinRel(sb, 1e-15));
    // γ = 0.1: (1 − e^{−0.2τ})/0.2 = sb at τ = 8.76
    const double tb = dampsym::pde::burgers_gaussian_shock_time(0.1);
    CHECK_THAT((1 - std::exp(-0.2 * tb)) / 0.2, WithinRel(sb, 1e-12));
    CHECK_THAT(tb, WithinAbs(8.76, 0.01));
    CHECK(std::isinf(dampsym::pde::burgers_gaussian_shock_time(0.125))); // 2γ sb > 1: never
    const PeriodicGrid g(32, std::numbers::pi);
    Vec u = Vec::Constant(32, 7.0);
    CHECK_FALSE(dampsym::pde::burgers_characteristic_solution(g, 0.1, tb, u));
    CHECK(u[0] == 7.0); // untouched
    CHECK(dampsym::pde::burgers_characteristic_solution(g, 0.1, 0.99 * tb, u));
}

TEST_CASE("pde-error: metrics on an output grid, exact, perturbed, after a shock", "[pde-error]") {
    const PeriodicGrid g(16, std::numbers::pi);
    const double gamma = 0.1;
    dampsym::CaseFacts c;
    c.t0 = 1.0;    // the solution starts at the case's t0
    c.t_end = 6.0; // output times 1, 2, ..., 6: τ up to 5
    c.points = 5;
    auto solution = [&](double t, Vec& out) {
        return dampsym::pde::burgers_characteristic_solution(g, gamma, t - c.t0, out);
    };
    dampsym::Mat grid(g.M + 1, 6); // one component beyond the field: not compared
    Vec u;
    for (int i = 0; i <= 5; ++i) {
        REQUIRE(solution(c.grid_time(i), u));
        grid.col(i).head(g.M) = u;
        grid(g.M, i) = 1e9;
    }
    const auto exact = dampsym::pde_error_metrics(c, grid, solution);
    CHECK(exact["max_abs"].get<double>() == 0.0);
    CHECK(exact["points"].get<int>() == 5); // t0 left out
    // the negative control: one value off by 1e-3 at the third output time
    grid(5, 3) += 1e-3;
    const auto off = dampsym::pde_error_metrics(c, grid, solution);
    CHECK_THAT(off["max_abs"].get<double>(), WithinRel(1e-3, 1e-9));
    CHECK(off["final_abs"].get<double>() == 0.0);
    // past the shock (γ = 0: at τ = 4.13): undefined, with the reason
    auto undamped = [&](double t, Vec& out) {
        return dampsym::pde::burgers_characteristic_solution(g, 0.0, t - c.t0, out);
    };
    const auto shock = dampsym::pde_error_metrics(c, grid, undamped);
    CHECK(shock["max_abs"].is_null());
    CHECK(shock.contains("undefined"));
}
