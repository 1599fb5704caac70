// dampsym in CI (src/harness/ci/{shard,junit}.cpp, src/harness/report/{compare,provenance}.cpp,
// src/cli/cli.cpp): shard assignment and the engines' shard variables, merge, compare, JUnit,
// selection, exit status 3 for an unwritable --out, --version and the help footers. Small cases
// from tests/data/cases; the suite-sized tests (schemas, 3 shards + merge of the default suite) are
// in verify/test_reports.py.
#include "cli_support.hpp"
#include "harness/bounded_read.hpp"
#include "harness/case/case.hpp"
#include "harness/ci/junit.hpp"
#include "harness/ci/shard.hpp"
#include "harness/report/compare.hpp"

#include <catch2/catch.hpp>
#include <map>
#include <set>
#include <sys/stat.h>
#include <unistd.h>

namespace {

using dampsym_test::CliResult;
using dampsym_test::copy_data;
using dampsym_test::describe;
using dampsym_test::read_json;
using dampsym_test::read_text;
using dampsym_test::run;
using dampsym_test::TempDir;
using dampsym_test::write_text;
using json = nlohmann::json;
namespace fs = std::filesystem;

std::string stable_part(const std::string& report_text) {
    return report_text.substr(0, report_text.find("\n  \"provenance\": {"));
}

} // namespace

TEST_CASE("shard: --shard K/N parsing", "[ci]") {
    const auto s = dampsym::parse_shard("2/5");
    CHECK(s.index == 2);
    CHECK(s.count == 5);
    for (const char* bad : {"0/3", "4/3", "1/0", "a/3", "1/", "/3", "13", "-1/3", "1/3x", ""})
        CHECK_THROWS_AS(dampsym::parse_shard(bad), dampsym::InputError);
}

TEST_CASE("shard: Bazel, GitLab and Slurm variables name the same shards", "[ci]") {
    auto from = [](std::map<std::string, std::string> env) {
        return dampsym::shard_from_env([env](const char* name) -> const char* {
            const auto it = env.find(name);
            return it == env.end() ? nullptr : it->second.c_str();
        });
    };
    for (int k = 1; k <= 3; ++k) {
        const auto bazel =
            from({{"TEST_TOTAL_SHARDS", "3"}, {"TEST_SHARD_INDEX", std::to_string(k - 1)}});
        const auto gitlab = from({{"CI_NODE_TOTAL", "3"}, {"CI_NODE_INDEX", std::to_string(k)}});
        const auto slurm0 =
            from({{"SLURM_ARRAY_TASK_COUNT", "3"}, {"SLURM_ARRAY_TASK_ID", std::to_string(k - 1)}});
        const auto slurm5 = from({{"SLURM_ARRAY_TASK_COUNT", "3"},
                                  {"SLURM_ARRAY_TASK_ID", std::to_string(k + 4)},
                                  {"SLURM_ARRAY_TASK_MIN", "5"}});
        for (const auto& s : {bazel, gitlab, slurm0, slurm5}) {
            REQUIRE(s.has_value());
            CHECK(s->index == k);
            CHECK(s->count == 3);
        }
    }
    CHECK_FALSE(from({}).has_value());
    CHECK_FALSE(from({{"CI_NODE_TOTAL", "1"}}).has_value()); // GitLab sets it in every job
    CHECK_THROWS_AS(from({{"CI_NODE_TOTAL", "3"}, {"CI_NODE_INDEX", "0"}}), dampsym::InputError);
    CHECK_THROWS_AS(from({{"TEST_TOTAL_SHARDS", "3"}, {"TEST_SHARD_INDEX", "3"}}),
                    dampsym::InputError);
    CHECK_THROWS_AS(from({{"TEST_TOTAL_SHARDS", "x"}, {"TEST_SHARD_INDEX", "0"}}),
                    dampsym::InputError);
}

TEST_CASE("shard: every case in exactly one shard, costs balanced, deterministic", "[ci]") {
    std::vector<double> costs;
    std::vector<std::string> keys;
    for (int i = 0; i < 40; ++i) {
        costs.push_back(0.01 * ((i * 37) % 23 + 1));
        keys.push_back("case-" + std::to_string(i));
    }
    costs[7] = 0.9; // one large case
    for (int n : {1, 2, 3, 5}) {
        const auto a = dampsym::assign_shards(costs, keys, n);
        CHECK(a == dampsym::assign_shards(costs, keys, n));
        std::vector<double> load(static_cast<std::size_t>(n), 0.0);
        for (std::size_t i = 0; i < a.size(); ++i) {
            REQUIRE(a[i] >= 0);
            REQUIRE(a[i] < n);
            load[static_cast<std::size_t>(a[i])] += costs[i];
        }
        const double hi = *std::max_element(load.begin(), load.end());
        const double lo = *std::min_element(load.begin(), load.end());
        INFO("n = " << n << ", loads " << lo << " .. " << hi);
        CHECK(hi <= 1.5 * lo + 1e-12);
    }
    // the step-count fallback: scaled by the median seconds per step of the measured cases
    const auto est = dampsym::estimate_costs({"a", "b", "c"}, {1000.0, 2000.0, 4000.0},
                                             json{{"a", 0.1}, {"b", 0.2}});
    CHECK_THAT(est[0], Catch::Matchers::WithinRel(0.1, 1e-15));
    CHECK_THAT(est[2], Catch::Matchers::WithinRel(0.4, 1e-12));
}

TEST_CASE("ci: --shard 1/2 + 2/2 + merge equals the unsharded run before provenance", "[ci]") {
    TempDir cases, all, s1, s2, merged;
    for (const char* f : {"cases/cli-pass.json", "cases/cli-jobs.json", "cases/cli-diverged.json",
                          "cases/cli-wrong-order.json"})
        copy_data(f, cases.path());
    auto args = [&](const std::vector<std::string>& extra, const TempDir& out) {
        std::vector<std::string> a{"run",   "--cases", cases.str(),     "--suite", "all",
                                   "--out", out.str(), "--time-budget", "0",       "--quiet"};
        a.insert(a.end(), extra.begin(), extra.end());
        return a;
    };
    const CliResult r = run(args({"--shard", "none"}, all));
    INFO(describe(args({}, all), r));
    REQUIRE(r.status == 1);
    CHECK(r.out.find("cases") != std::string::npos);
    CHECK(run(args({"--shard", "1/2"}, s1)).status != 2);
    CHECK(run(args({"--shard", "2/2"}, s2)).status != 2);
    const json j1 = read_json(s1 / "report.json"), j2 = read_json(s2 / "report.json");
    CHECK(j1["cases"].size() + j2["cases"].size() == 4);
    CHECK(j1["cases"].size() >= 1);
    CHECK(j2["cases"].size() >= 1);
    const CliResult m = run({"merge", merged.str(), s1.str(), s2.str(), "--quiet"});
    INFO(m.out << m.err);
    CHECK(m.status == 1); // a check fails in cli-wrong-order
    CHECK(stable_part(read_text(merged / "report.json")) ==
          stable_part(read_text(all / "report.json")));
    CHECK(fs::exists(merged / "junit.xml"));
    CHECK(read_text(merged / "report.md").find("merged") != std::string::npos);
    // a missing or repeated shard is bad input
    CHECK(run({"merge", (merged / "x").string(), s1.str()}).status == 2);
    CHECK(run({"merge", (merged / "y").string(), s1.str(), s1.str()}).status == 2);
    // compare: equal, and a flipped check
    CHECK(run({"compare", all.str(), merged.str()}).status == 0);
    json flipped = read_json(all / "report.json");
    flipped["cases"][0]["checks"][0]["passed"] = !flipped["cases"][0]["checks"][0]["passed"];
    write_text(merged / "flipped.json", flipped.dump());
    const CliResult c = run({"compare", all.str(), (merged / "flipped.json").string(), "--json"});
    REQUIRE(c.status == 1);
    const json cj = json::parse(c.out);
    REQUIRE(cj["rows"].size() == 1);
    CHECK(cj["rows"][0]["kind"] == "check flipped");
}

TEST_CASE("compare: tolerances, added and removed runs, old-format clock fields", "[ci]") {
    const json run_a = {
        {"method", "csv1"},
        {"dt", 0.1},
        {"status", "ok"},
        {"steps", 10},
        {"wall_seconds", 0.5},
        {"final_state", {1.0, 2.0}},
        {"metrics", {{"error", {{"final_abs", 1e-3}}}, {"cost", {{"wall_seconds", 1.0}}}}}};
    const json base = {{"schema_version", 1},
                       {"cases",
                        {{{"id", "c"},
                          {"file", "/a/c.json"},
                          {"runs", {run_a}},
                          {"checks", json::array()},
                          {"method_metrics", {{"csv1", {{"order", {{"slope", 2.0}}}}}}}}}}};
    json next = base;
    next["cases"][0]["file"] = "/b/c.json";            // not a result
    next["cases"][0]["runs"][0]["wall_seconds"] = 0.7; // clock
    next["cases"][0]["runs"][0]["metrics"]["cost"]["wall_seconds"] = 2.0;
    CHECK(dampsym::compare_reports(base, next, {})["equal"] == true);
    next["cases"][0]["method_metrics"]["csv1"]["order"]["slope"] = 2.0 + 1e-10;
    const json moved = dampsym::compare_reports(base, next, {});
    REQUIRE(moved["rows"].size() == 1);
    CHECK(moved["rows"][0]["kind"] == "order fit");
    CHECK(dampsym::compare_reports(base, next, {1e-9, 0.0, false})["equal"] == true);
    CHECK(dampsym::compare_reports(base, next, {0.0, 1e-9, false})["equal"] == true);
    next = base;
    json extra = run_a;
    extra["dt"] = 0.05;
    next["cases"][0]["runs"].push_back(extra);
    const json added = dampsym::compare_reports(base, next, {});
    REQUIRE(added["rows"].size() == 1);
    CHECK(added["rows"][0]["kind"] == "run added");
    CHECK(added["rows"][0]["run"] == "csv1 dt=0.05");
    CHECK(dampsym::compare_reports(next, base, {})["rows"][0]["kind"] == "run removed");
    CHECK_THROWS_AS(dampsym::compare_reports(json{{"cases", 3}}, base, {}), dampsym::InputError);
}

TEST_CASE("junit: escaping, failures with value and expected, errors for failed runs", "[ci]") {
    const json report = {{"cases",
                          {{{"id", "a<b>&\"c\""},
                            {"title", "t"},
                            {"source", "F Fig. 4.4"},
                            {"file", "x.json"},
                            {"problem", {{"id", "oscillator"}}},
                            {"runs", json::array()},
                            {"checks",
                             {{{"name", "ok"},
                               {"method", "m"},
                               {"metric", "error.final_abs"},
                               {"op", "le"},
                               {"expected", 1.0},
                               {"value", 0.5},
                               {"passed", true}},
                              {{"name", "bad"},
                               {"method", "m"},
                               {"dt", 0.1},
                               {"metric", "error.final_abs"},
                               {"op", "near"},
                               {"expected", 1.0},
                               {"tolerance", 0.1},
                               {"value", 2.0},
                               {"passed", false}},
                              {{"name", "gone"},
                               {"method", "m"},
                               {"metric", "error.final_abs"},
                               {"op", "le"},
                               {"expected", 1.0},
                               {"value", nullptr},
                               {"passed", false},
                               {"message", "run diverged at step 3"}}}}}}}};
    const std::string x = dampsym::render_junit(report);
    INFO(x);
    CHECK(x.find("name=\"a&lt;b&gt;&amp;&quot;c&quot;\"") != std::string::npos);
    CHECK(x.find("tests=\"3\" failures=\"1\" errors=\"1\"") != std::string::npos);
    CHECK(x.find("name=\"bad [m, dt=0.1]\"") != std::string::npos);
    CHECK(x.find("<failure type=\"check-failed\" message=\"metric error.final_abs: value 2, "
                 "expected 1 +- 0.1\"") != std::string::npos);
    CHECK(x.find("<error type=\"run-failed\" message=\"run diverged at step 3\"") !=
          std::string::npos);
    CHECK(x.find("<property name=\"source\" value=\"F Fig. 4.4\"/>") != std::string::npos);
}

TEST_CASE("cli: selection by --filter, repeated --suite, --problem and --method", "[ci]") {
    TempDir cases, out;
    copy_data("cases/cli-pass.json", cases.path());        // csv1, cimp; no suite
    copy_data("cases/cli-wrong-order.json", cases.path()); // csv1, rk3
    copy_data("cases/cli-jobs.json", cases.path());
    auto ids = [&](std::vector<std::string> args) {
        args.insert(args.begin(), {"--cases", cases.str(), "list", "--json"});
        const CliResult r = run(args);
        INFO(describe(args, r));
        std::vector<std::string> out_ids;
        if (r.status != 0) return std::vector<std::string>{"exit " + std::to_string(r.status)};
        const json listed = json::parse(r.out);
        for (const auto& c : listed["cases"]) out_ids.push_back(c["id"]);
        return out_ids;
    };
    CHECK(ids({}).size() == 3);
    CHECK(ids({"--filter", "cli-p*"}) == std::vector<std::string>{"cli-pass"});
    CHECK(ids({"--filter", "cli-p*", "--filter", "*order"}) ==
          std::vector<std::string>{"cli-pass", "cli-wrong-order"});
    CHECK(ids({"--problem", "oscillator"}).size() == 3);
    CHECK(ids({"--problem", "pendulum"}) == std::vector<std::string>{"exit 2"});
    CHECK(ids({"--suite", "nosuch"}) == std::vector<std::string>{"exit 2"});
    CHECK(ids({"--method", "rk3"}) == std::vector<std::string>{"cli-jobs", "cli-wrong-order"});
    CHECK(ids({"--method", "cimp"}) == std::vector<std::string>{"cli-jobs", "cli-pass"});
    CHECK(ids({"--method", "rk3", "--filter", "*order"}) ==
          std::vector<std::string>{"cli-wrong-order"});
    // --method restricts the runs and checks of a case; global options after the subcommand
    const std::vector<std::string> args{"run",     "cli-wrong-order", "--method",
                                        "rk3",     "--out",           out.str(),
                                        "--cases", cases.str(),       "--quiet"};
    const CliResult r = run(args);
    INFO(describe(args, r));
    REQUIRE(r.status == 0); // the failing check is csv1's
    const json rep = read_json(out / "report.json");
    for (const auto& rj : rep["cases"][0]["runs"]) CHECK(rj["method"] == "rk3");
    for (const auto& ck : rep["cases"][0]["checks"]) CHECK(ck["method"] == "rk3");
    CHECK(rep["cases"][0]["methods"] == json{"rk3"});
    // --quiet: only the totals line
    CHECK(r.out.find('\n') == r.out.size() - 1);
    const CliResult none = run({"--cases", cases.str(), "run", "--suite", "all", "--filter",
                                "nothing-*", "--out", (out / "none").string()});
    CHECK(none.status == 2);
    CHECK(none.err.find("nothing-*") != std::string::npos);
}

TEST_CASE("cli: an unwritable --out or --junit exits 3 before any case runs", "[ci]") {
    TempDir cases, root;
    copy_data("cases/cli-pass.json", cases.path());
    write_text(root / "file", "x");
    fs::create_directories(root / "dir" / "report.json");
    // (an empty --out is a usage error, exit 2: test_cli.cpp "cli: output paths")
    std::vector<std::string> outs{(root / "file").string(),         // a regular file
                                  (root / "file" / "sub").string(), // under a regular file
                                  (root / "dir").string(),          // report.json is a directory
                                  "/proc/dampsym-no-such-dir"};     // not creatable, even by root
    const bool root_user = ::geteuid() == 0;
    if (!root_user) { // a read-only directory stops only other users
        fs::create_directories(root / "ro");
        fs::permissions(root / "ro", fs::perms::owner_read | fs::perms::owner_exec);
        outs.push_back((root / "ro").string());
    } else {
        WARN("running as root: the read-only directory case is skipped (root may write there)");
    }
    for (const auto& o : outs) {
        const std::vector<std::string> args{"--cases", cases.str(), "run", "cli-pass", "--out", o};
        const CliResult r = run(args);
        INFO(describe(args, r));
        CHECK(r.status == 3);
        CHECK(r.out.find("checks") == std::string::npos); // nothing ran
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    }
    const std::vector<std::string> junit{"--cases", cases.str(),
                                         "run",     "cli-pass",
                                         "--out",   (root / "ok").string(),
                                         "--junit", (root / "dir").string()};
    const CliResult j = run(junit);
    INFO(describe(junit, j));
    CHECK(j.status == 3);
    CHECK_FALSE(fs::exists(root / "ok" / "report.json"));
    if (!root_user) fs::permissions(root / "ro", fs::perms::owner_all);
}

TEST_CASE("cli: --version, help footers with examples and exit codes, validators", "[ci]") {
    const CliResult v = run({"--version"});
    CHECK(v.status == 0);
    CHECK(v.out.rfind("dampsym ", 0) == 0);
    for (const std::vector<std::string>& h :
         {std::vector<std::string>{"--help"}, {"run", "--help"}, {"merge", "--help"}}) {
        const CliResult r = run(h);
        INFO(describe(h, r));
        CHECK(r.status == 0);
        CHECK(r.out.find("Examples:") != std::string::npos);
        CHECK(r.out.find("3 internal or I/O error") != std::string::npos);
    }
    CHECK(run({"compare", "--help"}).out.find("Exit status: 0 nothing moved") != std::string::npos);
    for (const std::vector<std::string>& bad : {std::vector<std::string>{"run", "--jobs", "0"},
                                                {"run", "--time-budget", "61"},
                                                {"run", "--annotations", "gitlab"},
                                                {"compare", "a", "b", "--rtol", "-1"}}) {
        const CliResult r = run(bad);
        INFO(describe(bad, r));
        CHECK(r.status == 2);
    }
}

TEST_CASE("cli: --annotations github and GITHUB_STEP_SUMMARY", "[ci]") {
    TempDir cases, out;
    copy_data("cases/cli-wrong-order.json", cases.path());
    const fs::path summary = out / "summary.md";
    ::setenv("GITHUB_STEP_SUMMARY", summary.c_str(), 1);
    const CliResult r =
        run({"--cases", cases.str(), "run", "cli-wrong-order", "--out", (out / "r").string(),
             "--annotations", "github", "--time-budget", "0", "--junit", (out / "j.xml").string()});
    ::unsetenv("GITHUB_STEP_SUMMARY");
    INFO(r.out << r.err);
    CHECK(r.status == 1);
    const auto pos = r.out.find("::error file=");
    REQUIRE(pos != std::string::npos);
    CHECK(r.out.find("cli-wrong-order.json,title=dampsym cli-wrong-order%3A csv1 third order",
                     pos) != std::string::npos);
    const std::string s = read_text(summary);
    CHECK(s.find("FAILED") != std::string::npos);
    CHECK(s.find("csv1 third order (wrong on purpose) [csv1]") != std::string::npos);
    CHECK(s.find("rk3 third order") == std::string::npos); // passing checks are not listed
    const std::string x = read_text(out / "j.xml");
    CHECK(x.find("<failure") != std::string::npos);
}

// the size limit is exact (max_bytes accepted, one more byte refused), a FIFO is
// refused without blocking, and the shard count limit is exact (10000 accepted, 10001 refused).
TEST_CASE("bounded reads: exact size limit, FIFO refused, shard count limit", "[ci]") {
    TempDir dir;
    const std::string ten = (dir / "ten").string(), eleven = (dir / "eleven").string();
    write_text(ten, "0123456789");
    write_text(eleven, "0123456789A");
    CHECK(dampsym::read_regular_file(ten, 10, "report") == "0123456789");
    CHECK_THROWS_WITH(dampsym::read_regular_file(eleven, 10, "report"),
                      Catch::Contains("11 bytes, more than"));
    const std::string fifo = (dir / "fifo").string();
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    CHECK_THROWS_WITH(dampsym::read_regular_file(fifo, 10, "report"), Catch::Contains("a FIFO"));
    CHECK_THROWS_WITH(dampsym::read_regular_file(dir.str(), 10, "report"),
                      Catch::Contains("a directory"));
    CHECK(dampsym::not_regular_reason((dir / "absent").string(), true).empty());
    CHECK_FALSE(dampsym::not_regular_reason((dir / "absent").string(), false).empty());
    CHECK(dampsym::parse_shard("10000/10000").count == 10000);
    CHECK_THROWS_AS(dampsym::parse_shard("1/10001"), dampsym::InputError);
    const auto env = [](std::string total) {
        return [total](const char* name) -> const char* {
            if (std::string(name) == "TEST_TOTAL_SHARDS") return total.c_str();
            if (std::string(name) == "TEST_SHARD_INDEX") return "0";
            return nullptr;
        };
    };
    CHECK(dampsym::shard_from_env(env("10000"))->count == 10000);
    CHECK_THROWS_AS(dampsym::shard_from_env(env("10001")), dampsym::InputError);
}

// 200 characters shown whole, 201 cut with "… (N more characters)"; control characters escaped.
TEST_CASE("messages: long inputs cut, control characters escaped", "[ci]") {
    const std::string two_hundred(200, 'x');
    CHECK(dampsym::quote_for_message(two_hundred) == two_hundred);
    CHECK(dampsym::quote_for_message(two_hundred + "y") == two_hundred + "… (1 more characters)");
    CHECK(dampsym::quote_for_message(two_hundred + "yé\n") ==
          two_hundred + "… (3 more characters)");
    CHECK(dampsym::quote_for_message("a\nb\x01\tc") == "a\\nb\\x01\\tc");
    CHECK(dampsym::quote_for_message("é", 1) == "é"); // one character, two bytes
}
