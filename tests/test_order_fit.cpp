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

TEST_CASE("fit_order drops points at the floor and on a plateau; the slope stays exact",
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
    SECTION("a plateau above the floor (local order ~ 0 at the fine end) is dropped") {
        for (double p : {1.0, 2.0, 3.0, 4.0}) {
            INFO("p=" << p);
            // Asymptotic on the 6 coarsest points, then three points stuck near the last error.
            std::vector<OrderPoint> pts;
            const double stuck = 0.5 * std::pow(hs[5], p);
            for (std::size_t i = 0; i < hs.size(); ++i)
                pts.push_back({hs[i], i <= 5 ? 0.5 * std::pow(hs[i], p)
                                             : stuck * (1.0 + 1e-3 * static_cast<double>(i))});
            const auto fit = dampsym::fit_order(pts, 1e-300);
            REQUIRE(fit.ok);
            CHECK_THAT(fit.slope, WithinRel(p, 1e-12));
            CHECK(fit.window_h.size() == 6);
            for (std::size_t i = 6; i < hs.size(); ++i) {
                CHECK(dropped_contains(fit, hs[i]));
                CHECK_FALSE(window_contains(fit, hs[i]));
            }
            // the local orders show the plateau
            CHECK(std::abs(fit.local_orders.back()) < 0.05);
        }
    }
}

TEST_CASE("fit_order: a fine-end round-off run longer than the asymptotic run is not reported "
          "as the order",
          "[order]") {
    // 4 points in the asymptotic regime (order 2), then 4 finer points whose error no longer
    // converges (above the floor the caller gave, as with round-off accumulated over many steps).
    // Those local orders are consistent with each other (≈ 0, or ≈ −½ for a √N round-off rise),
    // but they are not convergence: the fit must report the slope of the asymptotic points, or
    // fail, never an order of ≈ 0 or < 0 with ok == true.
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
    std::string window;
    for (double h : fit.window_h) window += std::to_string(h) + " ";
    INFO("ok=" << fit.ok << " slope=" << fit.slope << " window h: " << window
               << " reason=" << fit.reason);
    if (fit.ok) CHECK_THAT(fit.slope, WithinRel(2.0, 1e-12));
    CHECK_FALSE((fit.ok && fit.slope < 0.5));
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
