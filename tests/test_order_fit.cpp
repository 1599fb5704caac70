// dampsym::fit_order (src/diagnostics/order_fit.hpp): least-squares order over the asymptotic
// window of a step ladder, with floor/plateau and pre-asymptotic points dropped.
#include "diagnostics/order_fit.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace {

using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using dampsym::OrderPoint;

std::vector<double> halving_ladder(double h0, int n) {
    std::vector<double> h;
    for (int i = 0; i < n; ++i) h.push_back(h0 / std::pow(2.0, i));
    return h;
}

std::vector<OrderPoint> power_law(const std::vector<double>& hs, double C, double p) {
    std::vector<OrderPoint> pts;
    for (double h : hs) pts.push_back({h, C * std::pow(h, p)});
    return pts;
}

bool dropped_contains(const dampsym::OrderFit& f, double h) {
    return std::any_of(f.dropped.begin(), f.dropped.end(),
                       [&](const dampsym::DroppedPoint& d) { return d.h == h; });
}
bool window_contains(const dampsym::OrderFit& f, double h) {
    return std::find(f.window_h.begin(), f.window_h.end(), h) != f.window_h.end();
}

// Independent least-squares slope of log e against log h over the given h values.
double ls_slope(const std::vector<OrderPoint>& pts, const std::vector<double>& window) {
    double mx = 0, my = 0, n = 0;
    for (const auto& p : pts)
        if (std::find(window.begin(), window.end(), p.h) != window.end()) {
            mx += std::log(p.h);
            my += std::log(p.error);
            n += 1;
        }
    mx /= n;
    my /= n;
    double sxy = 0, sxx = 0;
    for (const auto& p : pts)
        if (std::find(window.begin(), window.end(), p.h) != window.end()) {
            sxy += (std::log(p.h) - mx) * (std::log(p.error) - my);
            sxx += (std::log(p.h) - mx) * (std::log(p.h) - mx);
        }
    return sxy / sxx;
}

} // namespace

TEST_CASE("fit_order recovers the exact slope of e = C h^p", "[order]") {
    for (double p : {1.0, 2.0, 3.0, 4.0}) {
        for (double C : {1e-3, 0.37, 25.0}) {
            INFO("p=" << p << " C=" << C);
            const auto pts = power_law(halving_ladder(0.2, 6), C, p);
            const auto fit = dampsym::fit_order(pts, 1e-14);
            REQUIRE(fit.ok);
            CHECK(fit.reason.empty());
            CHECK_THAT(fit.slope, WithinRel(p, 1e-12));
            CHECK_THAT(fit.intercept, WithinRel(std::log(C), 1e-10));
            CHECK_THAT(fit.r2, WithinAbs(1.0, 1e-12));
            CHECK(fit.window_h.size() == 6);
            CHECK(fit.dropped.empty());
            REQUIRE(fit.local_orders.size() == 5);
            for (double lo : fit.local_orders) CHECK_THAT(lo, WithinRel(p, 1e-12));
        }
    }
}

TEST_CASE("fit_order: a ladder that does not halve, given in any order", "[order]") {
    // Local orders are log(e_i/e_j)/log(h_i/h_j), not log2 of ratios.
    const std::vector<double> hs{0.013, 0.3, 0.07, 0.031, 0.11, 0.0049};
    const auto pts = power_law(hs, 2.5, 3.0);
    const auto fit = dampsym::fit_order(pts, 1e-14);
    REQUIRE(fit.ok);
    CHECK_THAT(fit.slope, WithinRel(3.0, 1e-12));
    CHECK(fit.window_h.size() == 6);
    CHECK(std::is_sorted(fit.window_h.rbegin(), fit.window_h.rend())); // descending h
    for (double lo : fit.local_orders) CHECK_THAT(lo, WithinRel(3.0, 1e-12));
}

TEST_CASE("fit_order drops points at the floor and on a plateau, the slope stays exact",
          "[order]") {
    const auto hs = halving_ladder(0.1, 9);
    SECTION("errors clamped at 1e-13 with floor 1e-12 are dropped as at the floor") {
        const auto fine = halving_ladder(0.1, 12); // down to 4.9e-5: p >= 3 reaches the floor
        for (double p : {1.0, 2.0, 3.0, 4.0}) {
            INFO("p=" << p);
            std::vector<OrderPoint> pts;
            int clamped = 0;
            for (double h : fine) {
                const double e = std::max(0.5 * std::pow(h, p), 1e-13);
                pts.push_back({h, e});
                if (!(e > 1e-12)) ++clamped;
            }
            const auto fit = dampsym::fit_order(pts, 1e-12);
            REQUIRE(fit.ok);
            CHECK_THAT(fit.slope, WithinRel(p, 1e-12));
            CHECK(fit.dropped.size() == static_cast<std::size_t>(clamped));
            CHECK(fit.window_h.size() == fine.size() - static_cast<std::size_t>(clamped));
            for (const auto& d : fit.dropped) {
                CHECK(d.error <= 1e-12);
                CHECK(d.reason.find("floor") != std::string::npos);
            }
            if (p >= 3.0) CHECK(clamped >= 2); // the floor case really happens on this ladder
        }
    }
    SECTION("a plateau above the floor (local order ~ 0 at the fine end) fails the fit") {
        // The floor is where the fit may stop looking; above it the finest steps are where the
        // asymptotic behaviour lives, so a plateau there is a failure with its status, never a
        // window that looks away from it.
        for (double p : {1.0, 2.0, 3.0, 4.0}) {
            INFO("p=" << p);
            std::vector<OrderPoint> pts;
            const double stuck = 0.5 * std::pow(hs[5], p);
            for (std::size_t i = 0; i < hs.size(); ++i)
                pts.push_back({hs[i], i <= 5 ? 0.5 * std::pow(hs[i], p)
                                             : stuck * (1.0 + 1e-3 * static_cast<double>(i))});
            const auto fit = dampsym::fit_order(pts, 1e-300);
            CHECK_FALSE(fit.ok);
            CHECK(fit.status == "no convergence at the finest steps");
            CHECK(fit.window_h.empty());
            CHECK(std::abs(fit.local_orders.back()) < 0.05); // the local orders show the plateau
            CHECK(fit.reason.find("local orders") != std::string::npos);
        }
    }
}

TEST_CASE("fit_order: a fine-end run that stops converging above the floor fails the fit",
          "[order]") {
    // 4 points in the asymptotic regime (order 2), then 4 finer points whose error no longer
    // converges (above the floor the caller gave, as with round-off accumulated over many steps).
    // Those local orders are consistent with each other (≈ 0, or ≈ −½ for a √N round-off rise),
    // but they are not convergence, and they are the finest steps: the fit fails with its status.
    const auto hs = halving_ladder(0.1, 8);
    const double e3 = std::pow(hs[3], 2.0);
    std::vector<OrderPoint> pts;
    SECTION("flat plateau") {
        for (std::size_t i = 0; i < hs.size(); ++i)
            pts.push_back({hs[i], i < 4 ? std::pow(hs[i], 2.0) : e3 * 0.999});
    }
    SECTION("round-off rising like sqrt(number of steps)") {
        for (std::size_t i = 0; i < hs.size(); ++i)
            pts.push_back({hs[i], i < 4 ? std::pow(hs[i], 2.0) : e3 * std::sqrt(hs[3] / hs[i])});
    }
    const auto fit = dampsym::fit_order(pts, 1e-14);
    INFO("status=" << fit.status << " reason=" << fit.reason);
    CHECK_FALSE(fit.ok);
    CHECK(fit.status == "no convergence at the finest steps");
}

TEST_CASE("fit_order: an order that drops at the finest steps fails the fit, whatever the coarse "
          "steps show",
          "[order]") {
    // Kutta's 3/8 rule with a21 = 1/3 + 1e-6 on the damped pendulum, h = 0.2 ... 0.0125: fourth
    // order while the truncation error dominates, then the O(1e-6 h) consistency defect: local
    // orders 4.02, 4.10, 2.32, 0.90 with every error 1000x above the floor. The old rule (the
    // longest agreeing run anywhere) reported 4.06.
    const std::vector<double> hs{0.2, 0.1, 0.05, 0.025, 0.0125};
    const std::vector<double> lo{4.02, 4.10, 2.32, 0.90};
    std::vector<OrderPoint> pts{{hs[0], 1e-3}};
    for (std::size_t i = 0; i < lo.size(); ++i)
        pts.push_back({hs[i + 1], pts.back().error / std::pow(2.0, lo[i])});
    REQUIRE(pts.back().error > 1000 * 1e-11); // far above the floor
    const auto fit = dampsym::fit_order(pts, 1e-11);
    CHECK_FALSE(fit.ok);
    CHECK(fit.status == "order drops at small h");
    CHECK(fit.reason.find("0.9") != std::string::npos); // the local orders are in the reason
    // positive control: the same ladder without the defect fits order 4 to the finest step
    std::vector<OrderPoint> clean;
    for (double h : hs) clean.push_back({h, 0.02 * std::pow(h, 4.0)});
    const auto good = dampsym::fit_order(clean, 1e-11);
    REQUIRE(good.ok);
    CHECK(good.status == "ok");
    CHECK(good.window_h.back() == hs.back());
    // and an order that RISES at the finest steps is named as such
    std::vector<OrderPoint> rising{{0.2, 1e-2}, {0.1, 5e-3}, {0.05, 2.5e-3}, {0.025, 1.5e-4}};
    const auto up = dampsym::fit_order(rising, 1e-14);
    CHECK_FALSE(up.ok);
    CHECK(up.status == "order rises at small h");
}

TEST_CASE("fit_order: an error not small against the solution is never in the window", "[order]") {
    // The undamped oscillator (amplitude 1) with a second-order method on h = 2.5 ... 0.0625: at
    // h = 1 the error 1.78 exceeds the solution; its local order with h = 0.5 is meaningless.
    // With the solution's scale the points with error >= 0.1 are dropped with that reason and the
    // fit sees only the asymptotic points; without it they would bend the slope.
    const std::vector<double> hs{2.5, 2.0, 1.0, 0.5, 0.25, 0.125, 0.0625, 0.03125, 0.015625};
    std::vector<OrderPoint> pts;
    for (double h : hs) pts.push_back({h, h > 1.0 ? 1.9 : 1.78 * h * h * (1.0 - 0.05 * h)});
    const auto fit = dampsym::fit_order(pts, 1e-14, 1.0);
    REQUIRE(fit.ok);
    CHECK_THAT(fit.slope, WithinAbs(2.0, 0.01));
    CHECK(fit.window_h.front() == 0.125); // the first error below 0.1 x the solution
    for (double h : {2.5, 2.0, 1.0, 0.5, 0.25}) {
        CHECK(dropped_contains(fit, h));
        CHECK_FALSE(window_contains(fit, h));
    }
    bool named = false;
    for (const auto& d : fit.dropped)
        named = named || d.reason == "error not small against the solution";
    CHECK(named);
    // negative control: without the solution's scale the local order 1.96 between h = 1 and 0.5
    // agrees with the finer ones, and h = 1 (error 1.69 > the amplitude) enters the window
    const auto blind = dampsym::fit_order(pts, 1e-14);
    REQUIRE(blind.ok);
    CHECK(blind.window_h.front() == 1.0);
}

TEST_CASE("fit_order drops pre-asymptotic coarse points: e = C h^p (1 + 50 h)", "[order]") {
    const auto hs = halving_ladder(0.4, 14);
    for (double p : {1.0, 2.0, 3.0, 4.0}) {
        INFO("p=" << p);
        std::vector<OrderPoint> pts;
        for (double h : hs) pts.push_back({h, 0.3 * std::pow(h, p) * (1.0 + 50.0 * h)});
        const auto fit = dampsym::fit_order(pts, 1e-300);
        REQUIRE(fit.ok);
        // The coarsest points (50h >= 2.5, local orders p + 0.64 and more) are outside the window
        // and the finest point is inside it.
        for (double h : {0.4, 0.2, 0.1, 0.05}) {
            CHECK(dropped_contains(fit, h));
            CHECK_FALSE(window_contains(fit, h));
        }
        CHECK(window_contains(fit, hs.back()));
        // The slope is the least-squares slope over the window (computed here independently)...
        CHECK_THAT(fit.slope, WithinRel(ls_slope(pts, fit.window_h), 1e-12));
        // ...and the remaining bias log2((1+50h)/(1+25h)) of the window is small.
        CHECK(fit.slope > p);
        CHECK(fit.slope < p + 0.2);
        // the local orders are those of the model, coarse to fine
        REQUIRE(fit.local_orders.size() == hs.size() - 1);
        CHECK_THAT(fit.local_orders[0],
                   WithinRel(p + std::log2((1.0 + 50.0 * 0.4) / (1.0 + 25.0 * 0.4)), 1e-12));
    }
}

TEST_CASE("fit_order drops NaN, inf, zero and negative errors", "[order]") {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    auto pts = power_law(halving_ladder(0.2, 5), 3.0, 2.0);
    pts.push_back({0.4, nan});
    pts.push_back({0.8, inf});
    pts.push_back({0.2 / 32, 0.0});
    pts.push_back({0.2 / 64, -1e-6});
    pts.push_back({0.2 / 128, -inf});
    const auto fit = dampsym::fit_order(pts, 1e-14);
    REQUIRE(fit.ok);
    CHECK_THAT(fit.slope, WithinRel(2.0, 1e-12));
    CHECK(fit.window_h.size() == 5);
    CHECK(fit.dropped.size() == 5);
    for (double h : {0.4, 0.8, 0.2 / 32, 0.2 / 64, 0.2 / 128}) {
        CHECK(dropped_contains(fit, h));
        CHECK_FALSE(window_contains(fit, h));
    }
    for (double lo : fit.local_orders) CHECK(std::isfinite(lo));
}

TEST_CASE("fit_order: fewer than 3 usable points is a failed fit with a reason", "[order]") {
    SECTION("two points") {
        const auto fit = dampsym::fit_order(power_law({0.1, 0.05}, 1.0, 2.0), 1e-14);
        CHECK_FALSE(fit.ok);
        CHECK_FALSE(fit.reason.empty());
        CHECK(fit.reason.find('3') != std::string::npos);
    }
    SECTION("five points, three of them at the floor or not finite") {
        std::vector<OrderPoint> pts{{0.1, 1e-2},
                                    {0.05, 2.5e-3},
                                    {0.025, 1e-13},
                                    {0.0125, std::numeric_limits<double>::quiet_NaN()},
                                    {0.00625, 0.0}};
        const auto fit = dampsym::fit_order(pts, 1e-12);
        CHECK_FALSE(fit.ok);
        CHECK_FALSE(fit.reason.empty());
        CHECK(fit.dropped.size() == 3);
    }
    SECTION("no points at all") {
        const auto fit = dampsym::fit_order({}, 1e-14);
        CHECK_FALSE(fit.ok);
        CHECK_FALSE(fit.reason.empty());
    }
    SECTION("no three consecutive points with consistent local orders") {
        std::vector<OrderPoint> pts{
            {0.1, 1e-2}, {0.05, 1e-3}, {0.025, 8e-4}, {0.0125, 1e-6}, {0.00625, 9e-7}};
        const auto fit = dampsym::fit_order(pts, 1e-14);
        CHECK_FALSE(fit.ok);
        CHECK_FALSE(fit.reason.empty());
    }
}

TEST_CASE("fit_order: R^2 is 1 on clean data and visibly below 1 on noisy data", "[order]") {
    const auto hs = halving_ladder(0.1, 7);
    const auto clean = dampsym::fit_order(power_law(hs, 0.8, 2.0), 1e-14);
    REQUIRE(clean.ok);
    CHECK(clean.r2 >= 1.0 - 1e-13);
    CHECK(clean.r2 <= 1.0 + 1e-13);
    // ±5% alternating noise keeps the local orders consistent (2 ± 0.14) but bends the line.
    std::vector<OrderPoint> noisy;
    for (std::size_t i = 0; i < hs.size(); ++i)
        noisy.push_back({hs[i], 0.8 * hs[i] * hs[i] * (i % 2 ? 0.95 : 1.05)});
    const auto fit = dampsym::fit_order(noisy, 1e-14);
    REQUIRE(fit.ok);
    CHECK(fit.window_h.size() == hs.size());
    CHECK(fit.r2 < 1.0 - 1e-6);
    CHECK(fit.r2 > 0.99);
    CHECK_THAT(fit.slope, WithinRel(ls_slope(noisy, fit.window_h), 1e-12));
}
