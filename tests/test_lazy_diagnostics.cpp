// "Compute only what a case asks for": each run reports what it observed
// ("observed": bare loop or recorder, stored grid points, tracked invariants, step Jacobians),
// the case reports which reference it built, and these follow the requested diagnostics only:
//  - final error only (one output point): the bare step loop, no grid, an exact reference at t_end
//    only, no Jacobian evaluations for an explicit method;
//  - no "error": no reference at all (no GSL integration for the pendulum);
//  - invariants / conformal-symplectic: the recorder / the step-Jacobian pass only when asked;
//  - work-precision timing only for step ladders, only when the time budget is on, never for a
//    failed run; the local error only when asked.
#include "harness/case/case.hpp"
#include "harness/run/runner.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <string>

using json = nlohmann::json;

namespace {

json run_lazy_case(json spec, double time_budget = 0.0) {
    if (!spec.contains("id")) spec["id"] = "lazy";
    if (!spec.contains("title")) spec["title"] = "lazy diagnostics test";
    if (!spec.contains("expect"))
        spec["no_checks_because"] = "a unit test that inspects the run record, not a check";
    const dampsym::CaseSpec c = dampsym::parse_case(spec, "test_lazy_diagnostics.cpp", {});
    dampsym::RunOptions options;
    options.jobs = 1;
    options.time_budget = time_budget;
    const json report = dampsym::run_cases({c}, options);
    REQUIRE(report["cases"].size() == 1);
    // The work-precision timings sit in the report's timings section, one entry per run; put
    // them back beside their runs for the checks below.
    json out = report["cases"][0];
    const json& t = report["timings"]["cases"][0]["runs"];
    REQUIRE(t.size() == out["runs"].size());
    for (std::size_t i = 0; i < t.size(); ++i) {
        CHECK_FALSE(out["runs"][i].contains("timing"));
        if (t[i].contains("timing")) out["runs"][i]["timing"] = t[i]["timing"];
    }
    return out;
}

json oscillator_case(const json& diagnostics) {
    return {{"problem", {{"id", "oscillator"}, {"omega", 1.0}, {"gamma", 0.1}}},
            {"methods", {"csv1"}},
            {"t_end", 2.0},
            {"dt", 0.01},
            {"output_dt", 2.0},
            {"diagnostics", diagnostics}};
}

} // namespace

TEST_CASE("lazy: a final-error-only case runs the bare loop against the exact final state only",
          "[lazy]") {
    const json c = run_lazy_case(oscillator_case({"error"}));
    CHECK(c["reference"]["kind"] == "exact");
    CHECK(c["reference"]["points"] == 1);
    const json& r = c["runs"][0];
    CHECK(r["status"] == "ok");
    CHECK(r["observed"]["bare_loop"] == true);
    CHECK(r["observed"]["grid_points"] == 0);
    CHECK(r["observed"]["invariants"] == false);
    CHECK(r["observed"]["step_jacobians"] == false);
    CHECK(r["jac_evals"] == 0);
    CHECK(r["rhs_evals"] == 2 * 200); // csv1: two force evaluations per step, nothing else
    CHECK(r["metrics"].size() == 1);
    CHECK(r["metrics"].contains("error"));
    CHECK_FALSE(r.contains("timing"));
}

TEST_CASE("lazy: without the error diagnostic no reference is computed", "[lazy]") {
    json spec = {{"problem", {{"id", "pendulum"}, {"gamma", 0.1}}},
                 {"methods", {"csv1"}},
                 {"t_end", 2.0},
                 {"dt", 0.01},
                 {"diagnostics", {"energy"}}};
    const json c = run_lazy_case(spec);
    CHECK(c["reference"]["kind"] == "none"); // no certified GSL integration was run
    const json& r = c["runs"][0];
    CHECK(r["observed"]["bare_loop"] == false); // the energy diagnostic reads the grid
    CHECK(r["observed"]["grid_points"].get<int>() > 1);
    CHECK_FALSE(r["metrics"].contains("error"));
    CHECK(r["metrics"].contains("energy"));
    // asking for the error as well brings the certified reference in
    spec["diagnostics"] = {"energy", "error"};
    CHECK(run_lazy_case(spec)["reference"]["kind"] == "gsl-certified");
}

TEST_CASE("lazy: invariants and step Jacobians only when asked", "[lazy]") {
    const json inv = run_lazy_case(oscillator_case({"invariants"}));
    const json& r1 = inv["runs"][0];
    CHECK(r1["observed"]["bare_loop"] == false);
    CHECK(r1["observed"]["invariants"] == true);
    CHECK(r1["observed"]["step_jacobians"] == false);
    CHECK(inv["reference"]["kind"] == "none");
    CHECK(r1["jac_evals"] == 0);
    CHECK(r1["metrics"].contains("invariants"));
    CHECK_FALSE(r1["metrics"].contains("conformal-symplectic"));

    const json cs = run_lazy_case(oscillator_case({"conformal-symplectic"}));
    const json& r2 = cs["runs"][0];
    CHECK(r2["observed"]["step_jacobians"] == true);
    CHECK(r2["observed"]["bare_loop"] == true); // the Jacobian pass is separate from the run
    CHECK(r2["jac_evals"] == 0);                // ... and does not touch the run's counters
    CHECK(r2["metrics"].contains("conformal-symplectic"));
    CHECK_FALSE(r2["metrics"].contains("invariants"));
}

TEST_CASE("lazy: work-precision timing only for step ladders with the budget on", "[lazy]") {
    json ladder = oscillator_case({"error"});
    ladder.erase("dt");
    ladder["dt_ladder"] = {0.02, 0.01};
    const json timed = run_lazy_case(ladder, 0.002);
    for (const auto& r : timed["runs"]) {
        REQUIRE(r.contains("timing"));
        CHECK(r["timing"]["repetitions"].get<int>() >= 1);
        CHECK(r["timing"]["repetitions_wall_seconds"].get<double>() >= 0.002);
        CHECK(r["timing"]["wall_seconds_min"].get<double>() > 0.0);
        CHECK(r["timing"]["wall_seconds_min"].get<double>() <=
              r["timing"]["repetitions_wall_seconds"].get<double>());
    }
    const json untimed =
        run_lazy_case(ladder, 0.0); // (a named report: the loop must not outlive it)
    for (const auto& r : untimed["runs"]) CHECK_FALSE(r.contains("timing"));
    CHECK_FALSE(run_lazy_case(oscillator_case({"error"}), 0.002)["runs"][0].contains("timing"));
    // a diverged run is recorded as failed, not timed (explicit Euler, h·ω = 3 on γ = 0.1)
    json diverging = ladder;
    diverging["methods"] = {"euler"};
    diverging["t_end"] = 6000.0;
    diverging["output_dt"] = 6000.0;
    diverging["dt_ladder"] = {3.0, 1.5};
    const json failed = run_lazy_case(diverging, 0.002);
    for (const auto& r : failed["runs"]) {
        CHECK(r["status"] == "diverged");
        CHECK_FALSE(r.contains("timing"));
    }
}

TEST_CASE("lazy: the local error is computed only when asked", "[lazy]") {
    CHECK_FALSE(
        run_lazy_case(oscillator_case({"error"}))["runs"][0]["metrics"].contains("local-error"));
    const json c = run_lazy_case(oscillator_case({"local-error"}));
    const json& m = c["runs"][0]["metrics"];
    REQUIRE(m.contains("local-error"));
    // csv1 is second order: one step of h = 0.01 errs by O(h³) (non-zero, far below h²)
    CHECK(m["local-error"]["abs"].get<double>() > 0.0);
    CHECK(m["local-error"]["abs"].get<double>() < 1e-5);
    CHECK(c["reference"]["kind"] == "none"); // the one-step comparison uses the exact solution
}
