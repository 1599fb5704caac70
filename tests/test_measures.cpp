// Measures as the paper states them and comparison checks (docs/case-keys.md):
// the "measures" of a case (component, norm, statistic over the output grid, growth rate) against
// values recomputed here from the exact oscillator solution; ratio, spread and across_dt checks
// against their inputs; a check that must fail does; no case without a check or a stated reason.
#include "harness/case/case.hpp"
#include "harness/run/runner.hpp"
#include "problems/oscillator.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <string>

using json = nlohmann::json;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;

namespace {

json run_measures_case(json spec) {
    if (!spec.contains("id")) spec["id"] = "measures";
    const dampsym::CaseSpec c = dampsym::parse_case(spec, "test_measures.cpp", {});
    dampsym::RunOptions options;
    options.jobs = 1;
    options.time_budget = 0.0;
    const json report = dampsym::run_cases({c}, options);
    REQUIRE(report["cases"].size() == 1);
    return report["cases"][0];
}

// Exact oscillator state at t (the problem's own closed form).
dampsym::Vec exact_at(double omega, double gamma, double q0, double p0, double t) {
    dampsym::ParamMap params;
    params.scalars = {{"omega", omega}, {"gamma", gamma}, {"q0", q0}, {"p0", p0}};
    const auto osc = dampsym::Oscillator::from_params(params);
    dampsym::Vec z(2);
    osc.exact(0.0, osc.initial_state(), t, z); // from (t0, z0) = (0, (q0, p0))
    return z;
}

const json* find_check(const json& c, const std::string& name) {
    for (const auto& ck : c["checks"])
        if (ck["name"] == name) return &ck;
    return nullptr;
}

// csv1 on the oscillator, two grid points (t = 1, 2): every statistic can be recomputed by hand.
json two_point_case() {
    return {{"problem", {{"id", "oscillator"}, {"omega", 1.0}, {"gamma", 0.1}, {"q0", 1.0}}},
            {"methods", {"csv1", "rk3"}},
            {"t_end", 2.0},
            {"dt", 0.1},
            {"output_dt", 1.0},
            {"diagnostics", {"error"}},
            {"measures",
             {{"q_final", {{"component", "q"}, {"over", "final"}}},
              {"q_mean", {{"component", "q"}, {"over", "mean"}}},
              {"p_max_rel", {{"component", "p"}, {"norm", "rel"}, {"over", "max"}}},
              {"z0_rms", {{"component", "z[0]"}, {"over", "rms"}}},
              {"state_max", {{"over", "max"}}},
              {"state_mean", {{"component", "state"}, {"over", "mean"}}},
              {"H_final", {{"quantity", "energy-error"}, {"over", "final"}}}}},
            {"expect",
             {{"rk3 beats csv1 in q",
               {{"metric", "measure.q_mean"}, {"ratio", {"rk3", "csv1"}}, {"lt", 1.0}}},
              {"spread of the final q error",
               {{"metric", "measure.q_final"}, {"spread", "all"}, {"ge", 1.0}}},
              {"deliberately wrong: csv1 beats rk3",
               {{"metric", "measure.q_mean"}, {"ratio", {"rk3", "csv1"}}, {"gt", 1.0}}}}}};
}

} // namespace

TEST_CASE("measures: component, norm and statistic as stated, recomputed from the exact solution",
          "[measures]") {
    const json c = run_measures_case(two_point_case());
    const json& run = c["runs"][0]; // csv1
    REQUIRE(run["method"] == "csv1");
    const json& m = run["metrics"]["measure"];
    const json& e = run["metrics"]["error"];
    // final state of the run against the exact solution at t = 2
    const dampsym::Vec u2 = exact_at(1.0, 0.1, 1.0, 0.0, 2.0);
    const double q2 = run["final_state"][0].get<double>(), p2 = run["final_state"][1].get<double>();
    CHECK_THAT(m["q_final"].get<double>(), WithinRel(std::abs(q2 - u2[0]), 1e-12));
    // the whole state reproduces the error diagnostic's own numbers
    CHECK_THAT(m["state_max"].get<double>(), WithinRel(e["max_abs"].get<double>(), 1e-14));
    CHECK_THAT(m["state_mean"].get<double>(), WithinRel(e["mean_abs"].get<double>(), 1e-14));
    // mean over t = 1, 2 of |Δq|; rms of z[0] = q; max of |Δp|/|p|: both points from a rerun at
    // t_end = 1 (same steps up to t = 1)
    json first = two_point_case();
    first["t_end"] = 1.0;
    first["methods"] = {"csv1"};
    first.erase("expect");
    first.erase("measures"); // one output point: only the final state is read
    first["no_checks_because"] = "reads the run's final state only";
    const json c1 = run_measures_case(first);
    const json& r1 = c1["runs"][0];
    const dampsym::Vec u1 = exact_at(1.0, 0.1, 1.0, 0.0, 1.0);
    const double dq1 = std::abs(r1["final_state"][0].get<double>() - u1[0]);
    const double dq2 = std::abs(q2 - u2[0]);
    CHECK_THAT(m["q_mean"].get<double>(), WithinRel(0.5 * (dq1 + dq2), 1e-12));
    CHECK_THAT(m["z0_rms"].get<double>(),
               WithinRel(std::sqrt(0.5 * (dq1 * dq1 + dq2 * dq2)), 1e-12));
    const double rp1 = std::abs(r1["final_state"][1].get<double>() - u1[1]) / std::abs(u1[1]);
    const double rp2 = std::abs(p2 - u2[1]) / std::abs(u2[1]);
    CHECK_THAT(m["p_max_rel"].get<double>(), WithinRel(std::max(rp1, rp2), 1e-12));
    // energy error at t_end: |H(U) − H(u)| with H = p²/2 + ω² q²/2
    const double H = 0.5 * (p2 * p2 + q2 * q2), Hu = 0.5 * (u2[1] * u2[1] + u2[0] * u2[0]);
    CHECK_THAT(m["H_final"].get<double>(), WithinRel(std::abs(H - Hu), 1e-10));
}

TEST_CASE("measures: ratio and spread checks use the listed methods' values, a wrong one fails",
          "[measures]") {
    const json c = run_measures_case(two_point_case());
    auto value_of = [&](const std::string& method, const char* measure) {
        for (const auto& r : c["runs"])
            if (r["method"] == method) return r["metrics"]["measure"][measure].get<double>();
        FAIL("no run of " << method);
        return 0.0;
    };
    const json* ratio = find_check(c, "rk3 beats csv1 in q");
    REQUIRE(ratio);
    CHECK((*ratio)["method"] == "rk3 / csv1");
    CHECK((*ratio)["passed"] == true);
    CHECK_THAT((*ratio)["value"].get<double>(),
               WithinRel(value_of("rk3", "q_mean") / value_of("csv1", "q_mean"), 1e-15));
    CHECK((*ratio)["inputs"][0]["rk3"] == value_of("rk3", "q_mean"));
    const json* spread = find_check(c, "spread of the final q error");
    REQUIRE(spread);
    const double a = value_of("rk3", "q_final"), b = value_of("csv1", "q_final");
    CHECK_THAT((*spread)["value"].get<double>(), WithinRel(std::max(a, b) / std::min(a, b), 1e-15));
    // negative control: the inverted claim fails, and the report counts it
    const json* wrong = find_check(c, "deliberately wrong: csv1 beats rk3");
    REQUIRE(wrong);
    CHECK((*wrong)["passed"] == false);
}

TEST_CASE("measures: growth rates on log-log (bounded, O(t h^2), O(t))", "[measures]") {
    // γ = 0: csv1's global error grows linearly in t (phase error), its energy error is bounded;
    // rk3's energy error grows linearly (its H drifts, F Fig 4.5).
    const json spec = {
        {"problem", {{"id", "oscillator"}, {"omega", 1.0}, {"gamma", 0.0}, {"q0", 1.0}}},
        {"methods", {"csv1", "rk3"}},
        {"t_end", 200.0},
        {"dt", 0.05},
        {"output_dt", 0.5},
        {"diagnostics", {"error"}},
        {"measures",
         {{"global", {{"over", "growth"}}},
          {"energy", {{"quantity", "energy-error"}, {"over", "growth"}, {"from", 20.0}}}}},
        {"expect",
         {{"csv1 global error O(t h^2)",
           {{"metric", "measure.global"}, {"methods", {"csv1"}}, {"near", 1.0}, {"tol", 0.1}}},
          {"csv1 energy error bounded",
           {{"metric", "measure.energy"}, {"methods", {"csv1"}}, {"le", 0.05}}},
          {"rk3 energy error grows linearly",
           {{"metric", "measure.energy"}, {"methods", {"rk3"}}, {"near", 1.0}, {"tol", 0.1}}}}}};
    const json c = run_measures_case(spec);
    for (const auto& ck : c["checks"]) {
        INFO(ck.dump());
        CHECK(ck["passed"] == true);
    }
}

TEST_CASE("measures: across_dt gives the log-log slope over the ladder", "[measures]") {
    const json spec = {
        {"problem", {{"id", "oscillator"}, {"omega", 1.0}, {"gamma", 0.1}, {"q0", 1.0}}},
        {"methods", {"csv1", "rk3"}},
        {"t_end", 10.0},
        {"dt_ladder", {0.1, 0.05, 0.025}},
        {"diagnostics", {"error"}},
        {"expect",
         {{"csv1 second order",
           {{"metric", "error.final_abs"},
            {"methods", {"csv1"}},
            {"across_dt", "loglog-slope"},
            {"near", 2.0},
            {"tol", 0.05}}},
          {"rk3/csv1 falls like h",
           {{"metric", "error.final_abs"},
            {"ratio", {"rk3", "csv1"}},
            {"across_dt", "loglog-slope"},
            {"near", 1.0},
            {"tol", 0.1}}}}}};
    const json c = run_measures_case(spec);
    REQUIRE(c["checks"].size() == 2);
    for (const auto& ck : c["checks"]) {
        INFO(ck.dump());
        CHECK(ck["passed"] == true);
        CHECK(ck["inputs"].size() == 3);
        CHECK_FALSE(ck.contains("dt"));
    }
}

TEST_CASE("measures: bad measures and comparisons, and silent cases, are input errors",
          "[measures]") {
    auto error_of = [](json spec) {
        try {
            dampsym::parse_case(spec, "bad.json", {});
        } catch (const dampsym::InputError& e) {
            return std::string(e.what());
        }
        return std::string("(accepted)");
    };
    json ok = two_point_case();
    ok["id"] = "x";
    CHECK(error_of(ok) == "(accepted)");
    struct Bad {
        const char* pointer; // JSON pointer of the field to change
        json value;
        const char* key; // the key the message must name
    };
    const Bad bad[] = {
        {"/measures/q_mean/component", "r", "measures.q_mean.component"},
        {"/measures/q_mean/component", "q[1]", "measures.q_mean.component"},
        {"/measures/q_mean/over", "median", "measures.q_mean.over"},
        {"/measures/q_mean/norm", "l1", "measures.q_mean.norm"},
        {"/measures/q_mean/quantity", "energy", "measures.q_mean.quantity"},
        {"/measures/q.mean", json{{"over", "max"}}, "measures.q.mean"},
        {"/expect/rk3 beats csv1 in q/ratio", json::array({"rk3"}),
         "expect.rk3 beats csv1 in q.ratio"},
        {"/expect/rk3 beats csv1 in q/across_dt", "slope", "expect.rk3 beats csv1 in q.across_dt"},
        {"/expect/rk3 beats csv1 in q/metric", "measure.nope", "expect.rk3 beats csv1 in q.metric"},
        {"/no_checks_because", "why not", "no_checks_because"},
    };
    for (const auto& b : bad) {
        json spec = ok;
        spec[json::json_pointer(b.pointer)] = b.value;
        const std::string msg = error_of(spec);
        INFO(b.pointer << " -> " << msg);
        CHECK(msg.find("bad.json") != std::string::npos);
        CHECK(msg.find(b.key) != std::string::npos);
    }
    // "over": "max" without an output grid (one output point)
    json nogrid = ok;
    nogrid.erase("output_dt");
    nogrid["dt"] = 2.0;
    CHECK(error_of(nogrid).find("measures.p_max_rel.over") != std::string::npos);
    // no check, no reason: exit-2 input error naming "expect"; a reason makes it valid
    json silent = ok;
    silent.erase("expect");
    CHECK(error_of(silent).find("no_checks_because") != std::string::npos);
    silent["no_checks_because"] = "a unit test";
    CHECK(error_of(silent) == "(accepted)");
    silent["no_checks_because"] = "";
    CHECK(error_of(silent).find("no_checks_because") != std::string::npos);
}
