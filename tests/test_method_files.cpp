// Method files (docs/method-files.md, src/harness/user_methods/method_files.hpp): the coefficient
// expression parser, the bad-file corpus (each defect = exit 2 naming the file and the key), the
// three ways to load a file, and the acceptance: the example files of examples/methods/ reproduce
// the built-in methods' final states, and the perturbed negative controls fail their coefficient
// conditions and their E_n check.
#include "cli_support.hpp"

#include "core/method.hpp"
#include "harness/case/case.hpp"
#include "harness/report/provenance.hpp"
#include "harness/user_methods/method_file_reader.hpp"
#include "harness/user_methods/method_files.hpp"
#include "methods/coefficient_expr.hpp"
#include "methods/exponential_tableaux.hpp"
#include "methods/families.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

namespace {

using dampsym_test::describe;
using dampsym_test::read_json;
using dampsym_test::run;
using dampsym_test::TempDir;
using dampsym_test::write_text;
using json = nlohmann::json;
namespace fs = std::filesystem;
using Catch::Matchers::Contains;

const fs::path examples = fs::path(dampsym::source_dir()) / "examples" / "methods";

// Final states of every run of a report, by method id (the case has one dt).
std::map<std::string, std::vector<double>> final_states(const json& report) {
    std::map<std::string, std::vector<double>> out;
    for (const auto& c : report["cases"])
        for (const auto& r : c["runs"])
            out[r["method"].get<std::string>()] = r["final_state"].get<std::vector<double>>();
    return out;
}

double metric(const json& report, const std::string& method, const std::string& diag,
              const std::string& name) {
    for (const auto& c : report["cases"])
        for (const auto& r : c["runs"])
            if (r["method"] == method) return r["metrics"][diag][name].get<double>();
    throw std::runtime_error("no run of " + method);
}

} // namespace

TEST_CASE("method files: coefficient expressions in long double", "[method-files]") {
    using dampsym::evaluate_coefficient_expr;
    CHECK(evaluate_coefficient_expr("1/2 - sqrt(3)/6") == 0.5L - std::sqrt(3.0L) / 6.0L);
    CHECK(evaluate_coefficient_expr("(3 + 2*sqrt(3))/3") == (3.0L + 2.0L * std::sqrt(3.0L)) / 3.0L);
    CHECK(evaluate_coefficient_expr("-(1)") == -1.0L);
    CHECK(evaluate_coefficient_expr(" 0.125 ") == 0.125L);
    CHECK(evaluate_coefficient_expr("2*3+4") == 10.0L); // precedence
    CHECK(evaluate_coefficient_expr("2-3-4") == -5.0L); // left associative
    CHECK(evaluate_coefficient_expr("12/4/3") == 1.0L); // left associative
    CHECK(static_cast<double>(evaluate_coefficient_expr("1/6")) == 1.0 / 6.0);
    CHECK(static_cast<double>(evaluate_coefficient_expr("0.1")) == 0.1);
    for (const char* bad : {"", "1e-3", "pi", "2^3", "(1", "1)", "sqrt 2", "sqrt(-1)", "1/0",
                            "1/(1-1)", "nan", "1..2", "exp(1)", "1 2"})
        CHECK_THROWS_AS(evaluate_coefficient_expr(bad), dampsym::CoefficientExprError);
}

TEST_CASE("method files: every bad file is exit 2 naming the file and the key", "[method-files]") {
    TempDir dir;
    const std::string rk = R"("family": "rk", "order": 1, "tableau": )";
    const std::string good_tab = R"({"A": [["0"]], "b": ["1"], "c": ["0"]})";
    struct Bad {
        const char* name;
        std::string text;
        const char* key;
        const char* what;
    };
    const std::vector<Bad> corpus{
        {"non-square",
         R"({"id": "b1", "family": "rk", "order": 1, "tableau": {"A": [["0", "0"], ["1"]], "b": ["1", "0"], "c": ["0", "1"]}})",
         "tableau.A[1]", "square"},
        {"b-length",
         R"({"id": "b2", "family": "rk", "order": 1, "tableau": {"A": [["0"]], "b": ["1", "0"], "c": ["0"]}})",
         "tableau.b", "expected 1"},
        {"c-length",
         R"({"id": "b3", "family": "rk", "order": 1, "tableau": {"A": [["0"]], "b": ["1"], "c": []}})",
         "tableau.c", "expected 1"},
        {"unknown-phi",
         R"({"id": "b4", "family": "exponential-rk", "order": 1, "tableau": {"c": ["0"], "A": [["0"]], "phi": [{"phi": "phi9"}], "b": ["1"], "phi0": "1"}})",
         "tableau.phi[0].phi", "unknown φ-function"},
        {"nan",
         R"({"id": "b5", "family": "rk", "order": 1, "tableau": {"A": [["0"]], "b": ["nan"], "c": ["0"]}})",
         "tableau.b[0]", "unexpected 'n'"},
        {"zero-division",
         R"({"id": "b6", "family": "rk", "order": 1, "tableau": {"A": [["0/0"]], "b": ["1"], "c": ["0"]}})",
         "tableau.A[0][0]", "division by zero"},
        {"shadows-builtin", "{\"id\": \"rk4\", " + rk + good_tab + "}", "id", "built-in"},
        {"declared-explicit",
         R"({"id": "b8", "family": "rk", "order": 2, "explicit": true, "tableau": {"A": [["0", "0"], ["1/2", "1/2"]], "b": ["1/2", "1/2"], "c": ["0", "1"]}})",
         "tableau.A[1][1]", "strictly lower"},
        {"unknown-key", "{\"id\": \"b9\", \"stages\": 1, " + rk + good_tab + "}", "stages",
         "unknown key"},
        {"unknown-tableau-key",
         R"({"id": "b10", "family": "rk", "order": 1, "tableau": {"A": [["0"]], "b": ["1"], "c": ["0"], "d": 1}})",
         "tableau.d", "unknown key"},
        {"unknown-family", R"({"id": "b11", "family": "multistep", "order": 1})", "family",
         "unknown family"},
        {"missing-order", "{\"id\": \"b12\", \"family\": \"rk\", \"tableau\": " + good_tab + "}",
         "order", "missing"},
        {"unknown-claim", "{\"id\": \"b13\", \"claims\": [\"symplectic\"], " + rk + good_tab + "}",
         "claims[0]", "unknown claim"},
        {"glm-U-shape",
         R"({"id": "b14", "family": "general-linear", "order": 1, "A": [["0"]], "U": [["1", "0"]], "B": [["1"]], "V": [["1"]], "c": ["0"]})",
         "U[0]", "expected 1"},
        {"glm-no-start",
         R"({"id": "b15", "family": "general-linear", "order": 1, "A": [["0"]], "U": [["1", "0"]], "B": [["1"], ["0"]], "V": [["1", "0"], ["0", "1"]], "c": ["0"]})",
         "starting", "starting method"},
        {"perk-stages",
         R"({"id": "b16", "family": "partitioned-exponential-rk", "order": 1, "q": {"c": ["0"], "A": [["0"]], "phi": ["1"], "b": ["1"], "phi0": "1"}, "p": {"c": ["0", "1"], "A": [["0", "0"], ["1", "0"]], "phi": ["1", "1"], "b": ["1", "0"], "phi0": "1"}})",
         "p.A", "same stages"},
        {"prk-cycle",
         R"({"id": "b17", "family": "partitioned-rk", "order": 1, "explicit": true, "q": {"A": [["1"]], "b": ["1"], "c": ["1"]}, "p": {"A": [["1"]], "b": ["1"], "c": ["1"]}})",
         "q.A", "cycle"},
        {"number-type", "{\"id\": \"b18\", " + rk + R"({"A": [[true]], "b": ["1"], "c": ["0"]}})",
         "tableau.A[0][0]", "number or an expression"},
        {"bad-id", "{\"id\": \"-x\", " + rk + good_tab + "}", "id", "not a valid method id"},
    };
    for (const auto& b : corpus) {
        const fs::path f = dir / (std::string(b.name) + ".json");
        write_text(f, b.text);
        const std::vector<std::string> args{"methods", "--check", "--methods", f.string()};
        const auto r = run(args);
        INFO(b.name << ": " << describe(args, r));
        CHECK(r.status == 2);
        CHECK_THAT(r.err, Contains(f.string() + ": " + b.key + ": "));
        CHECK_THAT(r.err, Contains(b.what));
        CHECK(dampsym::find_method(json::parse(b.text)["id"].get<std::string>()) ==
              (std::string(b.name) == "shadows-builtin" ? dampsym::find_method("rk4") : nullptr));
    }
}

TEST_CASE("method files: an id repeated by a second file is exit 2, the same file twice is not",
          "[method-files]") {
    TempDir dir;
    const std::string rk = R"("family": "rk", "order": 1, "tableau": )";
    const std::string good_tab = R"({"A": [["0"]], "b": ["1"], "c": ["0"]})";
    // Duplicate id: the same id in a second file (the first file is loaded, the second refused).
    write_text(dir / "dup1.json", "{\"id\": \"dup-id\", " + rk + good_tab + "}");
    write_text(dir / "dup2.json", "{\"id\": \"dup-id\", " + rk + good_tab + "}");
    const auto r = run({"methods", "--methods", (dir / "dup1.json").string(), "--methods",
                        (dir / "dup2.json").string()});
    CHECK(r.status == 2);
    CHECK_THAT(r.err, Contains((dir / "dup2.json").string() + ": id: duplicate id"));
    CHECK_THAT(r.err, Contains("dup1.json"));
    // Loading the same file again is not a duplicate.
    CHECK(run({"methods", "--methods", (dir / "dup1.json").string()}).status == 0);
}

TEST_CASE("method files: --methods, a case's method_files and the methods/ folder",
          "[method-files]") {
    TempDir dir;
    fs::create_directories(dir / "cases");
    fs::create_directories(dir / "methods");
    fs::create_directories(dir / "elsewhere");
    const auto tab = [](const std::string& id) {
        return "{\"id\": \"" + id +
               R"(", "family": "rk", "order": 2, "explicit": true, "tableau": {"A": [["0", "0"], ["1", "0"]], "b": ["1/2", "1/2"], "c": ["0", "1"]}})";
    };
    write_text(dir / "methods" / "folder-heun.json", tab("folder-heun"));
    write_text(dir / "elsewhere" / "case-heun.json", tab("case-heun"));
    write_text(dir / "elsewhere" / "cli-heun.json", tab("cli-heun"));
    write_text(dir / "cases" / "heuns.json", R"({
      "id": "heuns", "method_files": ["../elsewhere/case-heun.json"],
      "problem": {"id": "oscillator", "gamma": 0.1},
      "methods": ["heun", "folder-heun", "case-heun", "cli-heun"],
      "t_end": 1.0, "dt": 0.1, "diagnostics": ["error"],
      "expect": {"accurate": {"metric": "error.final_abs", "methods": ["heun", "folder-heun", "case-heun", "cli-heun"], "le": 1e-2}}})");
    const std::vector<std::string> args{
        "--cases",       (dir / "cases").string(),
        "run",           "heuns",
        "--methods",     (dir / "elsewhere" / "cli-heun.json").string(),
        "--out",         (dir / "out").string(),
        "--time-budget", "0"};
    const auto r = run(args);
    INFO(describe(args, r));
    REQUIRE(r.status == 0);
    const auto states = final_states(read_json(dir / "out" / "report.json"));
    REQUIRE(states.size() == 4);
    for (const char* m : {"folder-heun", "case-heun", "cli-heun"})
        CHECK(states.at(m) == states.at("heun")); // the same tableau as heun, B(3.8): bitwise

    // A missing method file named by a case: exit 2 naming the case file and the key.
    write_text(dir / "cases" / "missing.json", R"({
      "id": "missing", "method_files": ["nope.json"], "problem": {"id": "oscillator"},
      "methods": ["heun"], "t_end": 1.0, "dt": 0.1, "no_checks_because": "input test"})");
    const auto m =
        run({"run", (dir / "cases" / "missing.json").string(), "--out", (dir / "out2").string()});
    CHECK(m.status == 2);
    CHECK_THAT(m.err, Contains("missing.json: method_files[0]: method file"));
}

TEST_CASE("method files: rk4, glifrk2, csv1-perk, etdprk2, glm4, stormer-verlet and etdrk2 from "
          "files "
          "reproduce the built-in final states",
          "[method-files][acceptance]") {
    TempDir dir;
    const std::vector<std::string> args{
        "run",           (examples / "cases" / "file-vs-builtin-pendulum.json").string(),
        "--out",         dir.str(),
        "--time-budget", "0",
        "--jobs",        "2"};
    const auto r = run(args);
    INFO(describe(args, r));
    REQUIRE(r.status == 0);
    const auto states = final_states(read_json(dir / "report.json"));
    for (const char* m :
         {"rk4", "glifrk2", "csv1-perk", "etdprk2", "glm4", "stormer-verlet", "etdrk2"}) {
        const auto& a = states.at(m);
        const auto& b = states.at(std::string(m) + "-file");
        REQUIRE(a.size() == b.size());
        for (std::size_t i = 0; i < a.size(); ++i) {
            INFO(m << " component " << i << ": built-in " << a[i] << ", file " << b[i]
                   << ", relative difference " << std::abs(a[i] - b[i]) / std::abs(a[i]));
            CHECK(std::abs(a[i] - b[i]) <= 1e-15 * std::abs(a[i]));
        }
    }
}

TEST_CASE("method files: a coefficient perturbed by 1e-6 fails its coefficient condition and "
          "its E_n check (negative controls)",
          "[method-files][acceptance]") {
    // Coefficient level: the symplecticity of glifrk2's underlying tableau (B(1.18)) and
    // csv1-perk's B(2.23) hold for the exact files and fail for the perturbed ones.
    for (const auto& [file, check] : std::vector<std::pair<std::string, std::string>>{
             {"glifrk2", "symplectic"}, {"csv1-perk", "conformal-condition"}}) {
        for (const bool perturbed : {false, true}) {
            const std::string path =
                (examples / (file + (perturbed ? "-perturbed" : "") + ".json")).string();
            const std::vector<std::string> args{"methods", "--check", "--json", "--methods", path};
            const auto r = run(args);
            INFO(describe(args, r));
            CHECK(r.status == (perturbed ? 1 : 0));
            const json doc = json::parse(r.out);
            REQUIRE(doc["methods"].size() == 1); // only the named file's method
            bool found = false;
            for (const auto& m : doc["methods"]) {
                for (const auto& c : m["checks"])
                    if (c["name"] == check) {
                        found = true;
                        CHECK(c["holds"].get<bool>() == !perturbed);
                        if (perturbed) CHECK(c["value"].get<double>() > 1e-7);
                    }
            }
            CHECK(found);
        }
    }
    // Step level: E_n from the exact step Jacobian (conventions §5); the case's checks say
    // E_n <= 1e-13 for the exact files and >= 1e-8 for etdprk2 and the perturbed files.
    TempDir dir;
    const std::vector<std::string> args{
        "run",           (examples / "cases" / "file-methods-cs-oscillator.json").string(),
        "--out",         dir.str(),
        "--time-budget", "0"};
    const auto r = run(args);
    INFO(describe(args, r));
    REQUIRE(r.status == 0);
    const json report = read_json(dir / "report.json");
    CHECK(metric(report, "glifrk2-file", "conformal-symplectic", "max_rel") <= 1e-13);
    CHECK(metric(report, "csv1-perk-file", "conformal-symplectic", "max_rel") <= 1e-13);
    CHECK(metric(report, "glifrk2-perturbed", "conformal-symplectic", "max_rel") >= 1e-8);
    CHECK(metric(report, "csv1-perk-perturbed", "conformal-symplectic", "max_rel") >= 1e-8);
    // Claimed to be conformal symplectic, the perturbed files fail a check that says so.
    const auto p = run({"run", (examples / "cases" / "file-methods-cs-oscillator.json").string(),
                        "--out", (dir / "strict").string(), "--time-budget", "0", "--set",
                        "expect.conformal methods from files: E_n below 1e-13 at every "
                        "step.methods=[\"glifrk2-perturbed\", \"csv1-perk-perturbed\"]"});
    CHECK(p.status == 1);
}

TEST_CASE("method files: the φ-function vocabulary against long-double formulas",
          "[method-files]") {
    TempDir dir;
    const fs::path f = dir / "phis.json";
    write_text(f, R"({"id": "phi-vocabulary", "family": "exponential-rk", "order": 1,
      "tableau": {"c": ["0"], "A": [[{"phi": "phi2"}]], "phi": [{"phi": "phi3", "arg": "-2"}],
                  "b": [[{"coef": "3", "phi": "phi1"}, {"coef": "-1/2", "phi": "exp", "arg": "1/2"}]],
                  "phi0": {"phi": "phi0", "arg": "-1"}}})");
    const auto methods = dampsym::load_method_file(f.string());
    REQUIRE(methods.size() == 1);
    const auto* data = dampsym::method_data<dampsym::ExponentialCoefficients>(*methods[0]);
    REQUIRE(data != nullptr);
    for (const double x : {-3.0, -0.7, -1e-3, -1e-9, 0.0, 1e-9, 1e-3, 0.4, 1.0, 2.5}) {
        dampsym::ExponentialTableau t;
        dampsym::erk_coefficients(*data->data, x, t);
        const long double z = x;
        // Series for small |z| (the closed forms cancel), closed forms otherwise.
        const auto phi = [](int k, long double w) {
            if (std::abs(w) < 1e-2L) {
                long double fact = 1, sum = 0, term;
                for (int i = 2; i <= k; ++i) fact *= i;
                term = 1 / fact;
                for (int n = 0; n < 12; ++n) {
                    sum += term;
                    term *= w / (n + k + 1);
                }
                return sum;
            }
            const long double e = std::expm1(w);
            if (k == 1) return e / w;
            if (k == 2) return (e - w) / (w * w);
            return (e - w - w * w / 2) / (w * w * w);
        };
        INFO("x = " << x);
        CHECK_THAT(t.A(0, 0), Catch::Matchers::WithinRel(static_cast<double>(phi(2, z)), 1e-14));
        CHECK_THAT(t.phi[0],
                   Catch::Matchers::WithinRel(static_cast<double>(phi(3, -2 * z)), 1e-14));
        CHECK_THAT(t.b[0], Catch::Matchers::WithinRel(
                               static_cast<double>(3 * phi(1, z) - std::exp(z / 2) / 2), 1e-14));
        CHECK(t.phi0 == std::exp(-x));
    }
}

TEST_CASE("method files: the reader knows exactly the families whose traits name a file family",
          "[method-files][families]") {
    std::vector<std::string> traits;
    dampsym::for_each_type(dampsym::MethodFamilies{}, [&]<class D>() {
        const std::string name(dampsym::Family<D>::file_family);
        if (!name.empty() && std::find(traits.begin(), traits.end(), name) == traits.end())
            traits.push_back(name);
    });
    std::vector<std::string> reader = dampsym::method_file::known_families();
    std::sort(traits.begin(), traits.end());
    std::sort(reader.begin(), reader.end());
    CHECK(reader == traits);
    CHECK(traits.size() == 5); // rk (plain and under the integrating factor) and four more
}

TEST_CASE("families: every built-in row with coefficients gets its family's checks",
          "[families][coefficients]") {
    // a row whose family has coefficients must have checks, and a row of a family whose code is
    // the method (hand-written schemes, C plugins) none: no family is skipped silently. (Not "has
    // a method-file family": a family may have coefficients and no method files.)
    for (const dampsym::MethodInfo& m : dampsym::method_catalog()) {
        const bool has_coefficients =
            dampsym::visit_family(m, []<class D>(dampsym::Family<D>, const D&) {
                return !std::is_same_v<D, dampsym::HandWrittenScheme> &&
                       !std::is_same_v<D, dampsym::PluginStep>;
            });
        INFO(m.id);
        CHECK(dampsym::method_checks(m).empty() == !has_coefficients);
    }
}
