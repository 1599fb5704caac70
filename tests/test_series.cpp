// MinMaxDecimator and StrideSampler (src/diagnostics/series.hpp): the series a figure
// draws keep every bucket's extremes, so the maxima the report states are in the series file.
#include "diagnostics/series.hpp"
#include "harness/case/case.hpp"
#include "harness/run/runner.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

using dampsym::MinMaxDecimator;
using json = nlohmann::json;
using dampsym::StrideSampler;

TEST_CASE("MinMaxDecimator keeps every bucket's extremes in time order", "[series]") {
    const std::int64_t n = 100003;
    std::vector<double> y(static_cast<std::size_t>(n));
    for (std::int64_t i = 0; i < n; ++i)
        y[static_cast<std::size_t>(i)] =
            std::sin(0.01 * static_cast<double>(i)) + 1e-3 * std::sin(7.3 * static_cast<double>(i));
    y[777] = 5.0;
    y[50001] = -7.0;
    MinMaxDecimator d(n, 1000);
    for (std::int64_t i = 0; i < n; ++i)
        d.push(0.01 * static_cast<double>(i), y[static_cast<std::size_t>(i)]);
    const auto j = d.to_json();
    const auto oy = j["y"].get<std::vector<double>>();
    const auto ot = j["t"].get<std::vector<double>>();
    CHECK(oy.size() <= 2000);
    CHECK(*std::max_element(oy.begin(), oy.end()) == 5.0);
    CHECK(*std::min_element(oy.begin(), oy.end()) == -7.0);
    CHECK(std::is_sorted(ot.begin(), ot.end()));
    const std::int64_t per = d.samples_per_bucket();
    for (std::int64_t s = 0; s < n; s += per) {
        const auto b = y.begin() + s, e = y.begin() + std::min(n, s + per);
        CHECK(std::find(oy.begin(), oy.end(), *std::max_element(b, e)) != oy.end());
        CHECK(std::find(oy.begin(), oy.end(), *std::min_element(b, e)) != oy.end());
    }
    CHECK(j["last"][1].get<double>() == y.back());
}

TEST_CASE("MinMaxDecimator skips non-finite samples and counts them", "[series]") {
    MinMaxDecimator d(4, 10);
    d.push(0.0, 1.0);
    d.push(1.0, std::numeric_limits<double>::quiet_NaN());
    d.push(2.0, 3.0);
    d.push(3.0, std::numeric_limits<double>::infinity());
    const auto j = d.to_json();
    CHECK(j["y"] == nlohmann::json({1.0, 3.0}));
    CHECK(j["nonfinite"] == 2);
    CHECK(j["last"].is_null());
}

TEST_CASE("StrideSampler keeps about the asked number of samples and the last", "[series]") {
    const StrideSampler s(100001, 2000);
    int kept = 0;
    for (std::int64_t i = 0; i < 100001; ++i) kept += s.wants(i) ? 1 : 0;
    CHECK(kept <= 2002);
    CHECK(kept >= 1900);
    CHECK(s.wants(100000));
    CHECK(s.wants(0));
}

TEST_CASE("figures: the series hook keeps series and changes no number of the report", "[series]") {
    const json spec = {{"id", "series-test"},
                       {"title", "series hook"},
                       {"no_checks_because", "a unit test of the figures hook"},
                       {"problem", {{"id", "oscillator"}, {"omega", 1.0}, {"gamma", 0.1}}},
                       {"methods", {"csv1", "rk3"}},
                       {"t_end", 20.0},
                       {"dt", 0.01},
                       {"diagnostics", {"error", "energy", "invariants", "dissipation-drift"}}};
    const dampsym::CaseSpec c = dampsym::parse_case(spec, "test_series.cpp", {});
    dampsym::RunOptions plain;
    plain.time_budget = 0.0;
    const json a = dampsym::run_cases({c}, plain);
    dampsym::RunOptions with = plain;
    std::vector<json> got;
    with.series_sink = [&](const json& s) { got.push_back(s); };
    const json b = dampsym::run_cases({c}, with);
    CHECK(a["cases"] == b["cases"]); // the numbers do not move with --figures
    REQUIRE(got.size() == 1);
    const json& runs = got[0]["runs"];
    REQUIRE(runs.size() == 2);
    for (std::size_t i = 0; i < 2; ++i) {
        const json& s = runs[i]["series"];
        const json& m = b["cases"][0]["runs"][i]["metrics"];
        const auto y = s["invariants.H_gamma.step_res"]["y"].get<std::vector<double>>();
        CHECK(*std::max_element(y.begin(), y.end()) ==
              m["invariants"]["H_gamma"]["max_step_res"].get<double>());
        CHECK(s["error.abs"]["last"][1].get<double>() == m["error"]["final_abs"].get<double>());
        CHECK(s.contains("dissipation-drift.d"));
        CHECK(s.contains("energy.error"));
    }
}

// With the error diagnostic alone the exact reference is evaluated on the fly (nothing stored);
// --figures stores it on the grid. The problem check looked at the reference's middle state only
// when it was stored: report.json's problem_check moved with --figures (3 states against 2).
TEST_CASE("figures: a streamed case's report does not move with --figures", "[series]") {
    const json spec = {{"id", "series-streamed"},
                       {"title", "series hook, streamed grid"},
                       {"no_checks_because", "a unit test of the figures hook"},
                       {"problem", {{"id", "oscillator"}, {"omega", 1.0}, {"gamma", 0.1}}},
                       {"methods", {"csv1"}},
                       {"t_end", 10.0},
                       {"dt", 0.01},
                       {"output_dt", 0.1},
                       {"diagnostics", {"error"}}};
    const dampsym::CaseSpec c = dampsym::parse_case(spec, "test_series.cpp", {});
    dampsym::RunOptions plain;
    plain.time_budget = 0.0;
    const json a = dampsym::run_cases({c}, plain);
    dampsym::RunOptions with = plain;
    with.series_sink = [](const json&) {};
    const json b = dampsym::run_cases({c}, with);
    CHECK(a["cases"][0]["problem_check"]["states"] == 3);
    CHECK(a["cases"] == b["cases"]);
}

namespace {
// cimp on an oscillator with the invariants diagnostic: (the run's H_γ ratio-deviation series,
// the run's H_γ invariant metrics).
std::pair<json, json> ratio_series(const json& problem, double t_end, double dt) {
    const json spec = {{"id", "ratio-series"},
                       {"title", "the ratio-deviation series"},
                       {"no_checks_because", "a unit test of the figures hook"},
                       {"problem", problem},
                       {"methods", {"cimp"}},
                       {"t_end", t_end},
                       {"dt", dt},
                       {"diagnostics", {"invariants"}}};
    const dampsym::CaseSpec c = dampsym::parse_case(spec, "test_series.cpp", {});
    dampsym::RunOptions with;
    with.time_budget = 0.0;
    std::vector<json> got;
    with.series_sink = [&](const json& s) { got.push_back(s); };
    const json b = dampsym::run_cases({c}, with);
    REQUIRE(got.size() == 1);
    return {got[0]["runs"][0]["series"]["invariants.H_gamma.ratio_dev"],
            b["cases"][0]["runs"][0]["metrics"]["invariants"]["H_gamma"]};
}
} // namespace

// e^{2Γ} I_n / I_0 − 1 has no value when I_0 = 0: the series keeps no point of it (the figure drew
// −1 at every step for an oscillator at rest, which the report calls undefined). Negative
// control: the same case from q0 = 1 keeps the series.
TEST_CASE("figures: the ratio-deviation series is empty when I_0 = 0", "[series]") {
    for (const double q0 : {0.0, 1.0}) {
        const auto [s, inv] =
            ratio_series({{"id", "oscillator"}, {"gamma", 0.1}, {"q0", q0}}, 1.0, 0.1);
        INFO("q0 = " << q0 << ": " << s.dump());
        const auto y = s["y"].get<std::vector<double>>();
        if (q0 == 0.0) {
            CHECK(y.empty());
            CHECK(s["nonfinite"].get<int>() == 10);
            CHECK(inv["max_global_ratio_dev"].is_null());
        } else {
            CHECK(y.size() == 10);
        }
    }
}

// A strongly damped oscillator (γ = 50 > ω: H_γ indefinite, the state on the slow mode where its
// terms cancel): from some step on e^{2Γ} I_n / I_0 − 1 is the run's round-off times e^{2Γ}, which
// the report calls undefined from that step and the figure drew as ±1e300. The series ends at the
// same step: its finite points are the resolved ones (cimp keeps the law there, |r| tiny), the
// rest are skipped as non-finite. Control: at γ = 0.1 every point is kept.
TEST_CASE("figures: the ratio-deviation series ends where the ratio is no longer resolved",
          "[series]") {
    for (const double gamma : {50.0, 0.1}) {
        const auto [s, inv] = ratio_series({{"id", "oscillator"}, {"gamma", gamma}}, 10.0, 0.05);
        const auto y = s["y"].get<std::vector<double>>();
        const int nonfinite = s["nonfinite"].get<int>();
        INFO("gamma = " << gamma << ": " << inv.dump());
        REQUIRE(!y.empty());
        CHECK(static_cast<int>(y.size()) + nonfinite == 200); // every step, kept or skipped
        double worst = 0.0;
        for (const double v : y) worst = std::max(worst, std::abs(v));
        CHECK(worst <= 1e-6);
        if (gamma == 50.0) {
            CHECK(nonfinite > 100);
            CHECK(inv["max_global_ratio_dev"].is_null());
            // the report names the first unresolved step: the series kept the ones before it
            const std::string why = inv["undefined"]["max_global_ratio_dev"].get<std::string>();
            CHECK(why.find("at step " + std::to_string(y.size() + 1) + " ") != std::string::npos);
        } else {
            CHECK(nonfinite == 0);
        }
    }
}

// A run keeps orbit samples only for a case that draws its orbit (case_draws_orbit): the problem's
// default (Kepler draws its orbit, the oscillator a phase portrait only on request) or the case's
// "figures" key. Negative control: the oscillator without the key keeps none.
TEST_CASE("figures: orbit samples only for a case that draws its orbit", "[series]") {
    auto orbit_kept = [](json spec) {
        const dampsym::CaseSpec c = dampsym::parse_case(spec, "test_series.cpp", {});
        dampsym::RunOptions with;
        with.time_budget = 0.0;
        std::vector<json> got;
        with.series_sink = [&](const json& s) { got.push_back(s); };
        dampsym::run_cases({c}, with);
        REQUIRE(got.size() == 1);
        bool any = false;
        for (const auto& r : got[0]["runs"]) any = any || r["series"].contains("orbit");
        return any;
    };
    json osc = {{"id", "orbit-test"},
                {"title", "orbit samples"},
                {"no_checks_because", "a unit test of the figures hook"},
                {"problem", {{"id", "oscillator"}, {"omega", 1.0}, {"gamma", 0.1}}},
                {"methods", {"csv1"}},
                {"t_end", 20.0},
                {"dt", 0.01},
                {"diagnostics", {"error", "energy"}}};
    CHECK_FALSE(orbit_kept(osc)); // on request only
    osc["figures"] = {"series", "orbit"};
    CHECK(orbit_kept(osc));
    osc["figures"] = {"series"};
    CHECK_FALSE(orbit_kept(osc));
    json kepler = osc;
    kepler.erase("figures");
    kepler["problem"] = {{"id", "kepler"}};
    CHECK(orbit_kept(kepler)); // by default
    kepler["figures"] = {"series"};
    CHECK_FALSE(orbit_kept(kepler));
}
