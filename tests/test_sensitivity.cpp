// Verdicts that cannot be fooled (docs/conventions.md §5 "order", "No verdict without a
// measurement"; docs/matrix.md): Kutta's 3/8 rule with one coefficient off by 1e-6 fails its order
// check and the matrix (order and coefficient cells) while the exact rule passes both; a loaded
// method whose coefficients refute its declaration fails the run; a selection that leaves a
// comparison without its partner marks it "not run", never failed.
#include "cli_support.hpp"

#include <catch2/catch.hpp>
#include <string>
#include <vector>

namespace {

using dampsym_test::describe;
using dampsym_test::read_json;
using dampsym_test::run;
using dampsym_test::TempDir;
using dampsym_test::test_data;
using json = nlohmann::json;
namespace fs = std::filesystem;
using Catch::Matchers::Contains;

const json* sensitivity_check(const json& c, const std::string& method) {
    for (const auto& ck : c["checks"])
        if (ck["method"] == method) return &ck;
    return nullptr;
}

const json& sensitivity_row(const json& matrix, const std::string& id) {
    for (const auto& m : matrix["methods"])
        if (m["id"] == id) return m;
    throw std::runtime_error("no matrix row " + id);
}

} // namespace

TEST_CASE("sensitivity: Kutta 3/8 off by 1e-6 fails its order check on the pendulum, the exact "
          "rule passes",
          "[sensitivity]") {
    TempDir dir;
    const std::vector<std::string> args = {
        "run", (test_data / "cases" / "kutta38-pendulum-order.json").string(), "--out", dir.str()};
    const auto r = run(args);
    INFO(describe(args, r));
    REQUIRE(r.status == 1);
    const json rep = read_json(dir / "report.json");
    const json& c = rep["cases"][0];
    const json* good = sensitivity_check(c, "kutta38");
    const json* bad = sensitivity_check(c, "kutta38-perturbed");
    REQUIRE(good);
    REQUIRE(bad);
    CHECK((*good)["passed"] == true); // positive control: fourth order to the finest step
    CHECK((*bad)["passed"] == false);
    CHECK_THAT((*bad)["message"].get<std::string>(), Contains("order drops at small h"));
    const json& fit = c["method_metrics"]["kutta38-perturbed"]["order"];
    CHECK(fit["status"] == "order drops at small h");
    // the loaded method's coefficients refute its declaration: flagged in its runs, the summary,
    // the console and report.md
    CHECK(rep["summary"]["methods_refuted"] == 1);
    for (const auto& run_ : c["runs"])
        CHECK(run_.contains("coefficients_refuted") == (run_["method"] == "kutta38-perturbed"));
    CHECK_THAT(r.out, Contains("REFUTED kutta38-perturbed"));
    CHECK_THAT(dampsym_test::read_text(dir / "report.md"),
               Contains("kutta38-perturbed: its coefficients refute its declaration"));
}

TEST_CASE("sensitivity: steps whose error is not small against the solution stay out of the "
          "order fit",
          "[sensitivity]") {
    // The undamped oscillator on h = 2.5 ... 0.0625: at h >= 0.5 the error of cimp and gauss1 is
    // 20 % to 200 % of the solution; the old fit kept h = 1 (local orders agreeing by chance) and
    // reported 1.948, failing a second-order method against ±0.05.
    TempDir dir;
    const std::vector<std::string> args = {
        "run", (test_data / "cases" / "undamped-oscillator-coarse-ladder.json").string(), "--out",
        dir.str()};
    const auto r = run(args);
    INFO(describe(args, r));
    CHECK(r.status == 0);
    const json rep = read_json(dir / "report.json");
    for (const char* m : {"cimp", "gauss1"}) {
        const json& fit = rep["cases"][0]["method_metrics"][m]["order"];
        INFO(m << ": " << fit.dump());
        CHECK(fit["status"] == "ok");
        CHECK(fit["window_dt"][0] == 0.25);
        int large = 0;
        for (const auto& d : fit["dropped"])
            large += d["reason"] == "error not small against the solution" ? 1 : 0;
        CHECK(large == 4); // h = 2.5, 2, 1, 0.5
    }
}

TEST_CASE("sensitivity: the matrix fails Kutta 3/8 off by 1e-6 in its coefficient and order "
          "cells",
          "[sensitivity][matrix]") {
    TempDir dir;
    const fs::path methods = test_data / "methods";
    const std::vector<std::string> args = {"matrix",
                                           "--methods",
                                           (methods / "kutta38.json").string(),
                                           "--methods",
                                           (methods / "kutta38-perturbed.json").string(),
                                           "--method",
                                           "kutta38*",
                                           "--out",
                                           dir.str()};
    const auto r = run(args);
    INFO(describe(args, r));
    REQUIRE(r.status == 1);
    const json m = read_json(dir / "matrix.json");
    const json& good = sensitivity_row(m, "kutta38")["cells"];
    const json& bad = sensitivity_row(m, "kutta38-perturbed")["cells"];
    CHECK(good["coefficients"]["verdict"] == "holds");
    CHECK(good["order"]["verdict"] == "holds");
    CHECK(bad["coefficients"]["verdict"] == "fails");
    CHECK(bad["coefficients"]["agrees"] == false);
    CHECK(bad["order"]["verdict"] == "fails");
    CHECK_THAT(bad["order"]["detail"].get<std::string>(), Contains("order drops at small h"));
}

TEST_CASE("sensitivity: a comparison whose partner method was not selected is not run, and the "
          "run passes",
          "[sensitivity]") {
    TempDir dir;
    const std::string junit = (dir / "junit.xml").string();
    const std::vector<std::string> args = {
        "run",    "pend-table41-g0.05", "--method", "csv1", "--out", dir.str(), "--junit", junit,
        "--quiet"};
    const auto r = run(args);
    INFO(describe(args, r));
    CHECK(r.status == 0);
    const json rep = read_json(dir / "report.json");
    const json& c = rep["cases"][0];
    REQUIRE(c.contains("checks_not_run"));
    REQUIRE(c["checks_not_run"].size() == 1);
    const json& nr = c["checks_not_run"][0];
    CHECK(nr["name"] == "F Table 4.1: cimp needs more function calls than csv1");
    CHECK_THAT(nr["reason"].get<std::string>(), Contains("cimp, not selected"));
    CHECK(rep["summary"]["checks_not_run"] == 1);
    CHECK(rep["summary"]["checks_failed"] == 0);
    for (const auto& ck : c["checks"]) CHECK(ck["method"] == "csv1"); // the rest ran
    CHECK_THAT(r.out, Contains("1 not run"));
    CHECK_THAT(dampsym_test::read_text(dir / "report.md"), Contains("| not run |"));
    const std::string xml = dampsym_test::read_text(junit);
    CHECK_THAT(xml, Contains("skipped=\"1\""));
    CHECK_THAT(xml, Contains("<skipped message=\"compares with cimp, not selected (--method)\"/>"));
}
