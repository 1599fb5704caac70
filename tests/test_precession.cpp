// Diagnostic "precession" (HLW Fig 2.1; docs/conventions.md §5): the turn of the perihelion
// direction (the Laplace–Runge–Lenz vector's angle, unwrapped on the output grid).
#include "diagnostics/precession_diagnostic.hpp"
#include "problems/kepler.hpp"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <numbers>

using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using dampsym::Mat;
using dampsym::Vec;

namespace {

// A grid of n + 1 "states" whose first two components are the Runge–Lenz vector itself.
Mat grid_of_angles(double radius, double phi0, double turn, int n) {
    Mat g(2, n + 1);
    for (int i = 0; i <= n; ++i) {
        const double phi = phi0 + turn * i / n;
        g(0, i) = radius * std::cos(phi);
        g(1, i) = radius * std::sin(phi);
    }
    return g;
}

std::array<double, 2> identity_a(const Vec& z) {
    return {z[0], z[1]};
}

dampsym::CaseFacts facts(double t_end, int points) {
    dampsym::CaseFacts c;
    c.t0 = 0.0;
    c.t_end = t_end;
    c.points = points;
    c.needs_grid = true;
    c.reference_ok = false;
    return c;
}

} // namespace

TEST_CASE("precession: the unwrapped turn of the perihelion, across the +-pi cut", "[precession]") {
    // three full turns clockwise starting just below the cut at pi: atan2 jumps by 2 pi six times
    const double turn = -6.0 * std::numbers::pi - 0.3;
    const Mat g = grid_of_angles(0.6, 3.0, turn, 600);
    const auto m = dampsym::precession_metrics(facts(100.0, 600), g, identity_a);
    CHECK_THAT(m["total"].get<double>(), WithinRel(turn, 1e-12));
    CHECK_THAT(m["rate"].get<double>(), WithinRel(turn / 100.0, 1e-12));
    CHECK_THAT(m["initial_angle"].get<double>(), WithinAbs(3.0, 1e-15));
    CHECK_THAT(m["min_eccentricity"].get<double>(), WithinRel(0.6, 1e-15));
    CHECK(!m.contains("reference_total")); // no reference given
}

TEST_CASE("precession: undefined for a circular orbit and for a grid that is too coarse",
          "[precession]") {
    // negative controls of the definition: no direction, and an ambiguous unwrapping
    const Mat circular = grid_of_angles(1e-9, 0.0, 0.1, 10);
    auto m = dampsym::precession_metrics(facts(1.0, 10), circular, identity_a);
    CHECK(m["total"].is_null());
    CHECK(m["undefined"]["total"].get<std::string>().find("circular") != std::string::npos);
    const Mat coarse = grid_of_angles(0.6, 0.0, 3.0 * std::numbers::pi, 4); // 2.4 rad per point
    m = dampsym::precession_metrics(facts(1.0, 4), coarse, identity_a);
    CHECK(m["rate"].is_null());
    CHECK(m["undefined"]["rate"].get<std::string>().find("output_dt") != std::string::npos);
}

TEST_CASE("precession: Kepler's Runge-Lenz vector is (e, 0) at HLW(2.9) and the exact flow does "
          "not turn it",
          "[precession]") {
    dampsym::Kepler k;
    k.e = 0.6;
    const Vec z0 = k.initial_state();
    const auto a0 = k.runge_lenz(z0);
    CHECK_THAT(a0[0], WithinRel(0.6, 1e-14));
    CHECK_THAT(a0[1], WithinAbs(0.0, 1e-15));
    // the exact solution over 3 periods, 200 points per period
    const int n = 600;
    Mat g(4, n + 1);
    Vec z(4);
    for (int i = 0; i <= n; ++i) {
        k.exact(0.0, z0, 3.0 * k.period() * i / n, z);
        g.col(i) = z;
    }
    dampsym::CaseFacts c = facts(3.0 * k.period(), n);
    c.ref = g;
    c.reference_ok = true;
    const auto m = dampsym::precession_metrics(c, g, [&](const Vec& v) { return k.runge_lenz(v); });
    CHECK_THAT(m["total"].get<double>(), WithinAbs(0.0, 1e-12));
    CHECK_THAT(m["reference_total"].get<double>(), WithinAbs(0.0, 1e-12));
    CHECK_THAT(m["min_eccentricity"].get<double>(), WithinRel(0.6, 1e-12));
    // a turned copy of the orbit (every state rotated by 0.2 rad more per period) is measured
    Mat turned = g;
    for (int i = 0; i <= n; ++i) {
        const double a = 0.6 * i / n;
        const double c2 = std::cos(a), s2 = std::sin(a);
        for (int b : {0, 2}) {
            const double x = g(b, i), y = g(b + 1, i);
            turned(b, i) = c2 * x - s2 * y;
            turned(b + 1, i) = s2 * x + c2 * y;
        }
    }
    const auto mt =
        dampsym::precession_metrics(c, turned, [&](const Vec& v) { return k.runge_lenz(v); });
    CHECK_THAT(mt["total"].get<double>(), WithinRel(0.6, 1e-10));
    CHECK_THAT(mt["total_minus_reference"].get<double>(), WithinRel(0.6, 1e-10));
}
