// The command line (conventions §7), run in-process through dampsym::run_cli: exit statuses 0/1/2,
// error messages that name the file and the key, no report on bad input, --set overrides, list, a
// diverging run, and --jobs determinism. Case files live in tests/data/cases (valid) and
// tests/data/bad (one defect each); every test copies what it needs into a temporary --cases dir.
#include "cli_support.hpp"

#include <catch2/catch.hpp>
#include <cctype>
#include <cstdlib>
#include <string>
#include <sys/wait.h>
#include <vector>

namespace {

using dampsym_test::CliResult;
using dampsym_test::copy_data;
using dampsym_test::describe;
using dampsym_test::read_json;
using dampsym_test::run;
using dampsym_test::TempDir;
using json = nlohmann::json;
namespace fs = std::filesystem;

// Whether `text` mentions `key` as a whole key (not as part of a longer key or word).
bool names_key(const std::string& text, const std::string& key) {
    auto key_char = [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.';
    };
    for (auto pos = text.find(key); pos != std::string::npos; pos = text.find(key, pos + 1)) {
        const bool left = pos == 0 || !key_char(text[pos - 1]);
        const auto end = pos + key.size();
        const bool right = end == text.size() || !key_char(text[end]) || text[end] == '.';
        if (left && right) return true;
    }
    return false;
}

bool no_report(const fs::path& out) {
    return !fs::exists(out / "report.json") && !fs::exists(out / "report.md");
}

const json* find_check(const json& report, const std::string& method, const std::string& name) {
    for (const auto& c : report["cases"])
        for (const auto& ck : c["checks"])
            if (ck["method"] == method && ck["name"] == name) return &ck;
    return nullptr;
}

// Removes every "wall_seconds" field and every "timing" object (work-precision timings and their
// repetition counts): what schema_version 1 kept inside the cases.
void strip_timing(json& j) {
    if (j.is_object()) {
        j.erase("wall_seconds");
        j.erase("timing");
        for (auto& [k, v] : j.items()) strip_timing(v);
    } else if (j.is_array()) {
        for (auto& v : j) strip_timing(v);
    }
}

struct BadInput {
    const char* file; // under tests/data/bad/
    const char* key;  // the key the message must name ("" for malformed JSON)
    const char* also; // another word the message must contain
};

const BadInput bad_inputs[] = {
    {"bad-malformed.json", "", "malformed"},
    {"bad-top-key.json", "t_ned", "unknown key"},
    {"bad-problem-key.json", "problem.gama", "unknown key"},
    {"bad-problem-id.json", "problem.id", "oscilator"},
    {"bad-method-id.json", "methods[1]", "csv3"},
    {"bad-dt-zero.json", "dt", "> 0"},
    {"bad-dt-negative.json", "dt", "> 0"},
    {"bad-not-multiple.json", "dt", "multiple"},
    {"bad-just-beyond.json", "dt", "multiple"},
    {"bad-metric.json", "expect.typo in metric.metric", "error.final_abz"},
    {"bad-diagnostic.json", "diagnostics[1]", "eror"},
    {"bad-no-checks.json", "expect", "no_checks_because"},
    {"bad-measure.json", "measures.theta.component", "out of range"},
    {"bad-figures.json", "figures[1]", "orbits"}, // harness/case/figures_key.hpp
};

void check_bad(const std::vector<std::string>& args, const fs::path& out, const std::string& file,
               const std::string& key, const std::string& also) {
    const CliResult r = run(args);
    INFO(describe(args, r));
    CHECK(r.status == 2);
    CHECK(r.err.find(file) != std::string::npos);
    if (!key.empty()) CHECK(names_key(r.err, key));
    CHECK(r.err.find(also) != std::string::npos);
    CHECK(r.out.find("Reports:") == std::string::npos);
    CHECK(no_report(out));
}

} // namespace

TEST_CASE("cli: a passing case exits 0", "[cli]") {
    TempDir cases, out;
    copy_data("cases/cli-pass.json", cases.path());
    const std::vector<std::string> args{"--cases",  cases.str(), "run",
                                        "cli-pass", "--out",     out.str()};
    const CliResult r = run(args);
    INFO(describe(args, r));
    REQUIRE(r.status == 0);
    CHECK(r.err.empty());
    const json rep = read_json(out / "report.json");
    CHECK(rep["summary"]["checks_failed"] == 0);
    CHECK(rep["summary"]["checks_passed"] == 2);
    CHECK(fs::exists(out / "report.md"));
}

TEST_CASE("cli: a case with a wrong expected order exits 1", "[cli]") {
    TempDir cases, out;
    copy_data("cases/cli-wrong-order.json", cases.path());
    const std::vector<std::string> args{"--cases",         cases.str(), "run",
                                        "cli-wrong-order", "--out",     out.str()};
    const CliResult r = run(args);
    INFO(describe(args, r));
    REQUIRE(r.status == 1);
    const json rep = read_json(out / "report.json");
    CHECK(rep["summary"]["checks_failed"] == 1);
    CHECK(rep["summary"]["checks_passed"] == 1);
    // exactly the wrong expectation fails, and csv1's measured order is 2
    const json* bad = find_check(rep, "csv1", "csv1 third order (wrong on purpose)");
    REQUIRE(bad != nullptr);
    CHECK((*bad)["passed"] == false);
    REQUIRE((*bad)["value"].is_number());
    CHECK_THAT((*bad)["value"].get<double>(), Catch::Matchers::WithinAbs(2.0, 0.05));
    const json* good = find_check(rep, "rk3", "rk3 third order");
    REQUIRE(good != nullptr);
    CHECK((*good)["passed"] == true);
}

TEST_CASE("cli: bad input exits 2, names the file and the key, and writes no report", "[cli]") {
    for (const BadInput& b : bad_inputs) {
        INFO("bad input " << b.file);
        TempDir cases, out_root;
        const fs::path file = copy_data(std::string("bad/") + b.file, cases.path());
        const std::string id = file.stem().string();
        const fs::path out = out_root / "out";
        // by path
        check_bad({"--cases", cases.str(), "run", file.string(), "--out", out.string()}, out,
                  b.file, b.key, b.also);
        // by id, found in the --cases directory
        check_bad({"--cases", cases.str(), "run", id, "--out", out.string()}, out, b.file, b.key,
                  b.also);
        // together with a good case: everything is validated before anything runs
        copy_data("cases/cli-pass.json", cases.path());
        check_bad({"--cases", cases.str(), "run", (cases / "cli-pass.json").string(), file.string(),
                   "--out", out.string()},
                  out, b.file, b.key, b.also);
        CHECK_FALSE(fs::exists(out));
    }
}

TEST_CASE("cli: non-finite or out-of-range values from --set exit 2 naming the key", "[cli]") {
    struct SetCase {
        const char* set;
        const char* key;
    };
    for (const SetCase s :
         {SetCase{"problem.gamma=nan", "problem.gamma"},
          SetCase{"problem.omega=inf", "problem.omega"}, SetCase{"problem.q0=-inf", "problem.q0"},
          SetCase{"problem.gamma=-0.1", "problem.gamma"}, SetCase{"dt=0", "dt"},
          SetCase{"dt=-0.1", "dt"}, SetCase{"t_ned=3", "t_ned"},
          SetCase{"problem.gama=0.3", "problem.gama"}}) {
        INFO("--set " << s.set);
        TempDir cases, out_root;
        copy_data("cases/cli-pass.json", cases.path());
        const fs::path out = out_root / "out";
        const std::vector<std::string> args{"--cases", cases.str(), "run",   "cli-pass",
                                            "--set",   s.set,       "--out", out.string()};
        const CliResult r = run(args);
        INFO(describe(args, r));
        CHECK(r.status == 2);
        CHECK(r.err.find("cli-pass.json") != std::string::npos);
        CHECK(names_key(r.err, s.key));
        CHECK(no_report(out));
    }
}

TEST_CASE("cli: t_end within 1e-9 relative of a multiple of dt is accepted", "[cli]") {
    TempDir cases, out;
    copy_data("cases/cli-just-within.json", cases.path());
    const std::vector<std::string> args{"--cases",         cases.str(), "run",
                                        "cli-just-within", "--out",     out.str()};
    const CliResult r = run(args);
    INFO(describe(args, r));
    REQUIRE(r.status == 0);
    const json rep = read_json(out / "report.json");
    REQUIRE(rep["cases"].size() == 1);
    REQUIRE(rep["cases"][0]["runs"].size() == 1);
    CHECK(rep["cases"][0]["runs"][0]["steps"] == 10);
}

TEST_CASE("cli: run CASE --set problem.gamma=0.3 records the override", "[cli]") {
    TempDir cases, out;
    copy_data("cases/cli-pass.json", cases.path());
    const std::vector<std::string> args{"--cases", cases.str(),         "run",   "cli-pass",
                                        "--set",   "problem.gamma=0.3", "--out", out.str()};
    const CliResult r = run(args);
    INFO(describe(args, r));
    REQUIRE(r.status == 0);
    const json rep = read_json(out / "report.json");
    REQUIRE(rep["cases"].size() == 1);
    const json& c = rep["cases"][0];
    CHECK(c["overrides"] == json{{"problem.gamma", 0.3}});
    CHECK(c["problem"]["params"]["gamma"] == 0.3);
    CHECK(c["problem"]["params"]["omega"] == 1.0); // the rest of the case is unchanged

    // Without --set the case's own value is used and no override is recorded.
    TempDir out2;
    REQUIRE(run({"--cases", cases.str(), "run", "cli-pass", "--out", out2.str()}).status == 0);
    const json rep2 = read_json(out2 / "report.json");
    CHECK(rep2["cases"][0]["overrides"].empty());
    CHECK(rep2["cases"][0]["problem"]["params"]["gamma"] == 0.1);
    // and the override changed the numbers
    CHECK(rep2["cases"][0]["runs"][0]["final_state"] != c["runs"][0]["final_state"]);
}

TEST_CASE("cli: list and list --json exit 0 and list the case ids", "[cli]") {
    TempDir cases;
    const std::vector<std::string> ids{"cli-pass", "cli-wrong-order", "cli-diverged"};
    for (const auto& id : ids) copy_data("cases/" + id + ".json", cases.path());
    {
        const std::vector<std::string> args{"--cases", cases.str(), "list"};
        const CliResult r = run(args);
        INFO(describe(args, r));
        CHECK(r.status == 0);
        for (const auto& id : ids) CHECK(names_key(r.out, id));
    }
    {
        const std::vector<std::string> args{"--cases", cases.str(), "list", "--json"};
        const CliResult r = run(args);
        INFO(describe(args, r));
        REQUIRE(r.status == 0);
        const json j = json::parse(r.out);
        std::vector<std::string> listed;
        for (const auto& c : j["cases"]) listed.push_back(c["id"].get<std::string>());
        std::sort(listed.begin(), listed.end());
        std::vector<std::string> expected = ids;
        std::sort(expected.begin(), expected.end());
        CHECK(listed == expected);
    }
}

TEST_CASE("cli: usage errors exit 2 with a message and write no report", "[cli]") {
    TempDir cases, out_root;
    copy_data("cases/cli-pass.json", cases.path());
    const fs::path out = out_root / "out";
    const std::vector<std::vector<std::string>> usages{
        {},
        {"frobnicate"},
        {"--cases", cases.str(), "frobnicate"},
        {"--cases", cases.str(), "run", "--frobnicate", "--out", out.string()},
        {"--cases", cases.str(), "list", "--bogus"},
        {"--cases", cases.str(), "run", "cli-pass", "--jobs", "0", "--out", out.string()},
        {"--cases", cases.str(), "run", "cli-pass", "--jobs", "two", "--out", out.string()},
        {"--cases", cases.str(), "run", "cli-pass", "--set", "novalue", "--out", out.string()},
        {"--cases", cases.str(), "run", "no-such-case", "--out", out.string()},
        {"--cases", (cases / "missing").string(), "run", "cli-pass", "--out", out.string()},
    };
    for (const auto& args : usages) {
        const CliResult r = run(args);
        INFO(describe(args, r));
        CHECK(r.status == 2);
        CHECK_FALSE(r.err.empty());
        CHECK(no_report(out));
    }
}

TEST_CASE("cli: a step size beyond stability is reported as diverged, and its check fails",
          "[cli]") {
    // csv1 and rk3 with ω = 10, dt = 0.5 (h²ω²/2 = 12.5, far outside F(3.17)); cimp is stable.
    TempDir cases, out;
    copy_data("cases/cli-diverged.json", cases.path());
    const std::vector<std::string> args{"--cases",      cases.str(), "run",
                                        "cli-diverged", "--out",     out.str()};
    const CliResult r = run(args);
    INFO(describe(args, r));
    REQUIRE(r.status == 1);
    const json rep = read_json(out / "report.json");
    const json& c = rep["cases"][0];
    int diverged = 0;
    for (const auto& run_j : c["runs"]) {
        const std::string m = run_j["method"];
        INFO(run_j.dump());
        if (m == "cimp") {
            CHECK(run_j["status"] == "ok");
            CHECK(run_j["steps"] == 200);
            continue;
        }
        ++diverged;
        CHECK(run_j["status"] == "diverged");
        REQUIRE(run_j.contains("failed_at_step"));
        const auto failed_at = run_j["failed_at_step"].get<std::int64_t>();
        CHECK(failed_at >= 1);
        CHECK(failed_at < 200);
        // The diverged state is reported at its own time: steps == failed_at_step.
        CHECK(run_j["steps"].get<std::int64_t>() == failed_at);
        const json* ck = find_check(rep, m, "bounded error");
        REQUIRE(ck != nullptr);
        CHECK((*ck)["passed"] == false);
        CHECK((*ck)["value"].is_null());
    }
    CHECK(diverged == 2);
    const json* ok = find_check(rep, "cimp", "bounded error");
    REQUIRE(ok != nullptr);
    CHECK((*ok)["passed"] == true);
    CHECK(rep["summary"]["checks_failed"] == 2);
}

TEST_CASE("cli: --jobs 1 and --jobs 2 give identical reports (timings aside)", "[cli]") {
    TempDir cases, out1, out2;
    copy_data("cases/cli-jobs.json", cases.path());
    copy_data("cases/cli-pass.json", cases.path());
    copy_data("cases/cli-diverged.json", cases.path());
    copy_data("cases/cli-jobs-sweep.json", cases.path()); // a sweep: 5 row tasks per method
    auto args = [&](const std::string& jobs, const TempDir& out) {
        return std::vector<std::string>{
            "--cases",        cases.str(), "run", "cli-jobs", "cli-pass", "cli-diverged",
            "cli-jobs-sweep", "--jobs",    jobs,  "--out",    out.str()};
    };
    const CliResult r1 = run(args("1", out1));
    const CliResult r2 = run(args("2", out2));
    INFO(describe(args("1", out1), r1));
    INFO(describe(args("2", out2), r2));
    CHECK(r1.status == r2.status);
    CHECK(r1.status != 2);
    json a = read_json(out1 / "report.json");
    json b = read_json(out2 / "report.json");
    CHECK(a["provenance"]["jobs"] == 1);
    CHECK(b["provenance"]["jobs"] == 2);
    // everything that may differ sits in provenance and timings; nothing clock-dependent is left
    for (json* r : {&a, &b}) {
        r->erase("provenance");
        r->erase("timings");
    }
    json stripped = a;
    strip_timing(stripped);
    CHECK(stripped == a);
    std::size_t runs = 0;
    for (const auto& c : a["cases"]) runs += c["runs"].size();
    CHECK(runs > 20); // the comparison covers many independently scheduled tasks
    std::size_t sweep_rows = 0;
    for (const auto& c : a["cases"])
        for (const auto& mm : c["method_metrics"])
            if (mm.contains("stability-sweep")) sweep_rows += mm["stability-sweep"]["rows"].size();
    CHECK(sweep_rows == 4 * 40); // and the sweep's rows, assembled from their tasks
    CHECK(a.dump() == b.dump());
    CHECK(a == b);
}

TEST_CASE("cli: the dampsym executable returns run_cli's exit status", "[cli]") {
    TempDir cases, out_root;
    copy_data("cases/cli-pass.json", cases.path());
    copy_data("cases/cli-wrong-order.json", cases.path());
    const std::string bin = dampsym_test::binary_path();
    auto status_of = [&](const std::string& rest) {
        const std::string cmd =
            "'" + bin + "' --cases '" + cases.str() + "' " + rest + " > /dev/null 2>&1";
        const int raw = std::system(cmd.c_str());
        return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    };
    const std::string out = " --out '" + (out_root / "out").string() + "'";
    CHECK(status_of("list") == 0);
    CHECK(status_of("run cli-pass" + out) == 0);
    CHECK(status_of("run cli-wrong-order" + out) == 1);
    CHECK(status_of("run cli-pass --set problem.gamma=nan" + out) == 2);
    CHECK(status_of("frobnicate") == 2);
    // an unwritable --out: exit 3 with one line, not an abort (a path under a regular file fails
    // for root too)
    CHECK(status_of("run cli-pass --out '" + (cases / "cli-pass.json").string() + "/sub'") == 3);
    CHECK(status_of("--version") == 0);
}

TEST_CASE("cli: output paths: an empty --out or --junit, or --junit naming another output of the "
          "run, exit 2, a symbolic link in place of an output is refused (exit 3), not replaced",
          "[cli]") {
    TempDir cases, root;
    copy_data("cases/cli-pass.json", cases.path());
    const fs::path out = root / "out";
    const std::vector<std::string> base{"--cases", cases.str(), "run", "cli-pass", "-q"};
    auto with = [&](std::vector<std::string> extra) {
        std::vector<std::string> args = base;
        args.insert(args.end(), extra.begin(), extra.end());
        return args;
    };
    for (const auto& extra : std::vector<std::vector<std::string>>{
             {"--out", ""},
             {"--out", out.string(), "--junit", ""},
             {"--out", out.string(), "--junit", (out / "report.json").string()},
             {"--out", out.string(), "--junit", (out / "sub" / ".." / "report.md").string()},
             {"--out", out.string(), "--figures", "--junit", (out / "figures.md").string()},
             {"--out", out.string(), "--figures", "--junit",
              (out / "series" / "j.xml").string()}}) {
        const auto args = with(extra);
        const CliResult r = run(args);
        INFO(describe(args, r));
        CHECK(r.status == 2);
        CHECK_THAT(r.err, Catch::Contains(extra.size() == 2 ? "--out" : "--junit"));
        CHECK(no_report(out));
    }
    for (const auto& args : std::vector<std::vector<std::string>>{
             {"plot", ""}, {"matrix", "--out", ""}, {"merge", "", (root / "none").string()}}) {
        const CliResult r = run(args);
        INFO(describe(args, r));
        CHECK(r.status == 2);
        CHECK_THAT(r.err, Catch::Contains("empty"));
    }
    // a symbolic link where --junit or report.md goes: exit 3 naming it; link and target intact
    const fs::path target = root / "target.txt";
    dampsym_test::write_text(target, "keep\n");
    const fs::path link = root / "junit.xml";
    fs::create_symlink(target, link);
    auto args = with({"--out", out.string(), "--junit", link.string()});
    CliResult r = run(args);
    INFO(describe(args, r));
    CHECK(r.status == 3);
    CHECK_THAT(r.err, Catch::Contains(link.string()));
    fs::create_directories(out);
    fs::create_symlink(target, out / "report.md");
    args = with({"--out", out.string()});
    r = run(args);
    INFO(describe(args, r));
    CHECK(r.status == 3);
    CHECK_THAT(r.err, Catch::Contains((out / "report.md").string()));
    CHECK(fs::is_symlink(link));
    CHECK(fs::is_symlink(out / "report.md"));
    CHECK(dampsym_test::read_text(target) == "keep\n");
    // the negative control: the same run with the link gone and --junit a regular path writes both
    fs::remove(out / "report.md");
    args = with({"--out", out.string(), "--junit", (root / "j.xml").string()});
    r = run(args);
    INFO(describe(args, r));
    CHECK(r.status == 0);
    CHECK(fs::is_regular_file(out / "report.md"));
    CHECK(fs::is_regular_file(root / "j.xml"));
}
