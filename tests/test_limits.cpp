// Hostile input and numerical faults (src/harness/run/limits.hpp): the chunked, guarded step loop
// is bitwise the bare loop; a case's time budget stops it (status timeout, the step reached, the
// case fails, the others are intact); SIGINT/SIGTERM stop a run, write the report marked
// interrupted and exit 130/143, a second signal exits at once and the previous report is never
// truncated; the memory estimate refuses a case above --max-memory (exit 2 naming the key); faults
// planted in one run (NaN, inf, a failed solve, an exception) give their status while the other
// runs and cases finish; I/O errors exit 3.
#include "cli_support.hpp"
#include "support/sanitizers.hpp"

#include "harness/problem_info.hpp"
#include "harness/run/case_job.hpp"
#include "harness/run/limits.hpp"
#include "harness/run/runner.hpp"
#include "methods/newton.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <fcntl.h>
#include <limits>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <thread>

using namespace dampsym_test;
using dampsym::CaseSpec;
using dampsym::FaultPlan;
using nlohmann::json;

extern char** environ;

namespace {

using Clock = std::chrono::steady_clock;

// z ← A z with a rotation-and-decay A: cheap, and every step's state is distinct.
struct ToyStepper {
    int calls = 0;
    dampsym::StepStatus step(double t, dampsym::Vec& z) {
        ++calls;
        const double c = 0.999 * std::cos(0.01 + 1e-3 * t), s = 0.999 * std::sin(0.01);
        const double q = z[0], p = z[1];
        z[0] = c * q + s * p;
        z[1] = -s * q + c * p;
        return dampsym::StepStatus::ok;
    }
};

struct Trace {
    std::vector<std::int64_t> n;
    std::vector<double> t, q;
    void operator()(std::int64_t k, double tk, const dampsym::Vec& z) {
        n.push_back(k);
        t.push_back(tk);
        q.push_back(z[0]);
    }
};

// A small oscillator case (tests/data/cases/cli-pass.json's shape).
json small_case(const std::string& id, double t_end, double dt) {
    return {{"id", id},
            {"title", "limits test"},
            {"problem", {{"id", "oscillator"}, {"omega", 1.0}, {"gamma", 0.1}}},
            {"methods", {"csv1", "symplectic-euler"}},
            {"t_end", t_end},
            {"dt", dt},
            {"diagnostics", {"error"}},
            {"expect",
             {{"small final error",
               {{"metric", "error.final_abs"}, {"methods", "all"}, {"le", 1.0}}}}}};
}

CaseSpec spec(const json& j) {
    return dampsym::parse_case(j, j["id"].get<std::string>() + ".json", {});
}

const json& run_of(const json& report, std::size_t c, std::size_t r) {
    return report["cases"][c]["runs"][r];
}

// Runs the binary with args; returns its pid (stdout/stderr to files in dir).
pid_t spawn(const std::vector<std::string>& args, const fs::path& dir) {
    std::vector<std::string> full{dampsym_test::binary_path()};
    full.insert(full.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& a : full) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    const std::string out = (dir / "stdout").string(), err = (dir / "stderr").string();
    posix_spawn_file_actions_addopen(&fa, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&fa, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    pid_t pid = -1;
    const int rc = posix_spawn(&pid, full[0].c_str(), &fa, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&fa);
    REQUIRE(rc == 0);
    return pid;
}

int wait_status(pid_t pid) {
    int raw = 0;
    REQUIRE(waitpid(pid, &raw, 0) == pid);
    return WIFEXITED(raw) ? WEXITSTATUS(raw) : 1000 + WTERMSIG(raw);
}

// Waits until `path` exists (the run has started writing) or the timeout passes.
void wait_for_text(const fs::path& path, const std::string& text, double seconds) {
    const auto end = Clock::now() + std::chrono::duration<double>(seconds);
    while (Clock::now() < end) {
        std::error_code ec;
        if (fs::exists(path, ec) && read_text(path).find(text) != std::string::npos) return;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
}

} // namespace

TEST_CASE("limits: the guarded loop is bitwise the bare loop, in any chunking", "[limits]") {
    for (std::int64_t n : {0, 1, 7, 1000, 100000}) {
        dampsym::Vec a(2), b(2);
        a << 1.0, 0.25;
        b = a;
        ToyStepper sa, sb;
        Trace ta, tb;
        const auto ra = dampsym::integrate(sa, a, 0.5, 0.01, n, &ta);
        dampsym::CaseGuard guard;
        guard.start();
        const auto rb = dampsym::integrate_guarded(sb, b, 0.5, 0.01, n, &tb, guard);
        CHECK(ra.status == rb.status);
        CHECK(ra.steps_done == rb.steps_done);
        CHECK(a[0] == b[0]); // bitwise
        CHECK(a[1] == b[1]);
        CHECK(ta.n == tb.n);
        CHECK(ta.t == tb.t);
        CHECK(ta.q == tb.q);
        CHECK(sa.calls == sb.calls);
    }
}

TEST_CASE("limits: a time budget stops the loop at a step boundary", "[limits]") {
    dampsym::Vec z(2);
    z << 1.0, 0.0;
    ToyStepper s;
    dampsym::CaseGuard guard;
    guard.set_timeout(0.2);
    guard.start();
    const auto t0 = Clock::now();
    const auto r = dampsym::integrate_guarded(s, z, 0.0, 1e-3, std::int64_t{1} << 40,
                                              static_cast<dampsym::NoObserver*>(nullptr), guard);
    const double took = std::chrono::duration<double>(Clock::now() - t0).count();
    CHECK(r.status == dampsym::RunStatus::timeout);
    CHECK(r.steps_done == s.calls); // z is the state at the step reached
    CHECK(r.steps_done > 0);
    CHECK(took < 0.5);
    // negative control: without a budget the same loop runs to the end
    dampsym::CaseGuard none;
    none.start();
    dampsym::Vec y(2);
    y << 1.0, 0.0;
    ToyStepper s2;
    const auto all = dampsym::integrate_guarded(s2, y, 0.0, 1e-3, 100000,
                                                static_cast<dampsym::NoObserver*>(nullptr), none);
    CHECK(all.status == dampsym::RunStatus::ok);
    CHECK(all.steps_done == 100000);
}

TEST_CASE("limits: --case-timeout stops a 2e9-step case within 3 s, the other case is intact",
          "[limits]") {
    const std::vector<CaseSpec> ok_only{spec(small_case("small", 2.0, 0.01))};
    const std::vector<CaseSpec> both{spec(small_case("small", 2.0, 0.01)),
                                     spec(small_case("huge", 1e6, 1e-3))}; // 2 x 1e9 steps
    dampsym::RunOptions opt;
    opt.jobs = 2;
    opt.time_budget = 0.0;
    opt.case_timeout = 1.0;
    const json alone = dampsym::run_cases(ok_only, opt);
    const auto t0 = Clock::now();
    const json report = dampsym::run_cases(both, opt);
    const double took = std::chrono::duration<double>(Clock::now() - t0).count();
    CHECK(took < 3.0);
    CHECK(report["cases"][0]["runs"] == alone["cases"][0]["runs"]); // intact
    CHECK(report["cases"][0]["checks"] == alone["cases"][0]["checks"]);
    for (std::size_t r = 0; r < 2; ++r) {
        const json& run = run_of(report, 1, r);
        INFO(run.dump());
        CHECK(run["status"] == "timeout");
        CHECK(run["steps"].get<std::int64_t>() < 1000000000);
        CHECK(run["failed_at_step"] == run["steps"]);
    }
    bool completion_failed = false;
    for (const auto& ck : report["cases"][1]["checks"]) {
        CHECK_FALSE(ck["passed"].get<bool>()); // its checks fail, never pass
        if (ck["name"] == "case completed") completion_failed = true;
    }
    CHECK(completion_failed);
    CHECK(report["summary"]["failed_cases"] == 1);
    // the case key wins over the option
    json keyed = small_case("keyed", 1e6, 1e-3);
    keyed["timeout_seconds"] = 0.3;
    opt.case_timeout = 100.0;
    const auto t1 = Clock::now();
    const json r2 = dampsym::run_cases({spec(keyed)}, opt);
    CHECK(std::chrono::duration<double>(Clock::now() - t1).count() < 2.0);
    CHECK(run_of(r2, 0, 0)["status"] == "timeout");
}

TEST_CASE("limits: timeout_seconds is validated (exit 2 naming the key)", "[limits]") {
    for (const json& bad : {json(0.0), json(-1.0), json("2"), json(nullptr)}) {
        json j = small_case("bad-timeout", 2.0, 0.01);
        j["timeout_seconds"] = bad;
        INFO(bad.dump());
        CHECK_THROWS_WITH(spec(j), Catch::Contains("timeout_seconds"));
    }
}

TEST_CASE("limits: faults planted in one run give their status, the rest finishes",
          "[limits][faults]") {
    const std::vector<CaseSpec> cases{spec(small_case("faulty", 2.0, 0.01)),
                                      spec(small_case("clean", 2.0, 0.01))};
    dampsym::RunOptions opt;
    opt.jobs = 2;
    opt.time_budget = 0.0;
    const json clean = dampsym::run_cases(cases, opt);
    REQUIRE(clean["summary"]["checks_failed"] == 0);
    struct Row {
        FaultPlan::Kind kind;
        const char* status;
        std::int64_t steps, failed_at;
    };
    for (const Row& row : {Row{FaultPlan::Kind::nan, "diverged", 37, 37},
                           Row{FaultPlan::Kind::inf, "diverged", 37, 37},
                           Row{FaultPlan::Kind::solve_failed, "solve-failed", 36, 37},
                           Row{FaultPlan::Kind::exception, "error", 0, -1}}) {
        dampsym::set_fault_plan(FaultPlan{"faulty", "csv1", row.kind, 37});
        json report;
        try {
            report = dampsym::run_cases(cases, opt);
        } catch (...) {
            dampsym::set_fault_plan(std::nullopt);
            throw;
        }
        dampsym::set_fault_plan(std::nullopt);
        INFO(row.status);
        const json& bad = run_of(report, 0, 0);
        INFO(bad.dump());
        CHECK(bad["method"] == "csv1");
        CHECK(bad["status"] == row.status);
        CHECK(bad["steps"] == row.steps);
        if (row.failed_at >= 0) CHECK(bad["failed_at_step"] == row.failed_at);
        if (row.kind == FaultPlan::Kind::exception)
            CHECK_THAT(bad["error"].get<std::string>(), Catch::Contains("injected fault"));
        // the other run of the case and the other case are untouched
        CHECK(run_of(report, 0, 1) == run_of(clean, 0, 1));
        CHECK(report["cases"][1] == clean["cases"][1]);
        // the faulty run's checks fail (never pass), and so does the case
        for (const auto& ck : report["cases"][0]["checks"])
            if (ck["method"] == "csv1" || ck["name"] == "case completed")
                CHECK_FALSE(ck["passed"].get<bool>());
        CHECK(report["summary"]["failed_cases"] == 1);
    }
}

TEST_CASE("limits: a reference that cannot meet its tolerance fails the checks that read it",
          "[limits][faults]") {
    // pendulum (no exact solution: a certified GSL reference); parameters unique to this test,
    // so that the poisoned reference is not shared through the reference cache
    json j = small_case("ref-fault", 1.0, 0.01);
    j["problem"] = {{"id", "pendulum"}, {"gamma", 0.0123456789}};
    j["methods"] = {"csv1"};
    j["expect"]["no error at all"] = {
        {"metric", "error.final_abs"}, {"methods", "all"}, {"ge", 0.0}}; // passes if evaluated
    const std::vector<CaseSpec> cases{spec(j), spec(small_case("clean", 2.0, 0.01))};
    dampsym::RunOptions opt;
    opt.time_budget = 0.0;
    const json clean = dampsym::run_cases({cases[1]}, opt);
    dampsym::set_fault_plan(
        FaultPlan{"ref-fault", "(reference)", FaultPlan::Kind::reference_nan, 50});
    json report;
    try {
        report = dampsym::run_cases(cases, opt);
    } catch (...) {
        dampsym::set_fault_plan(std::nullopt);
        throw;
    }
    dampsym::set_fault_plan(std::nullopt);
    const json& c = report["cases"][0];
    INFO(c["reference"].dump());
    CHECK(c["reference"]["ok"] == false);
    CHECK_THAT(c["reference"]["error"].get<std::string>(), Catch::Contains("non-finite"));
    CHECK(c["runs"][0]["status"] == "ok"); // the run itself finished
    REQUIRE(c["checks"].size() == 2);
    for (const auto& ck : c["checks"]) {
        CHECK_FALSE(ck["passed"].get<bool>()); // never pass, whatever the direction
        CHECK_THAT(ck["message"].get<std::string>(), Catch::Contains("reference failed"));
    }
    CHECK(report["cases"][1] == clean["cases"][0]);
}

TEST_CASE("limits: a stop request (SIGINT) stops every run at a step boundary", "[limits]") {
    const std::vector<CaseSpec> cases{spec(small_case("small", 2.0, 0.01))};
    dampsym::request_stop(SIGINT);
    const json report = dampsym::run_cases(cases, dampsym::RunOptions{});
    dampsym::clear_stop();
    for (const auto& run : report["cases"][0]["runs"]) {
        CHECK(run["status"] == "interrupted");
        CHECK(run["steps"] == 0);
    }
    CHECK(report["summary"]["checks_failed"].get<int>() > 0);
    json marked = report;
    dampsym::request_stop(SIGTERM);
    dampsym::mark_interrupted(marked);
    CHECK(dampsym::exit_status_after_run(0) == 143);
    dampsym::clear_stop();
    CHECK(marked["interrupted"]["signal"] == "SIGTERM");
    CHECK(dampsym::exit_status_after_run(1) == 1);
}

TEST_CASE("limits: memory estimate and --max-memory", "[limits]") {
    CHECK(dampsym::parse_memory_size("8G") == 8.0 * 1024 * 1024 * 1024);
    CHECK(dampsym::parse_memory_size("500M") == 500.0 * 1024 * 1024);
    CHECK(dampsym::parse_memory_size("1.5KiB") == 1536.0);
    CHECK(dampsym::parse_memory_size("4096") == 4096.0);
    for (const char* bad : {"", "x", "-1G", "0", "1Q", "nan", "1e999"})
        CHECK_THROWS_WITH(dampsym::parse_memory_size(bad), Catch::Contains("--max-memory"));
    CHECK(dampsym::default_max_memory() > 0.0);
    json big = small_case("big-grid", 1e5, 1e-2); // 1e7 output points
    big["output_dt"] = 1e-2;
    big["diagnostics"] = {"error", "energy"}; // energy reads the stored grid
    const CaseSpec c = spec(big);
    const auto est = dampsym::estimate_case_memory(c, 2);
    CHECK(est.key == "output_dt");
    CHECK(est.bytes > 1e7 * 2 * 8 * 2); // two grids in flight at least
    CHECK_THROWS_WITH(dampsym::check_memory({c}, 2, 200.0 * 1024 * 1024),
                      Catch::Contains("output_dt") && Catch::Contains("--max-memory") &&
                          Catch::Contains("big-grid.json"));
    // The error alone against the exact solution streams (grid_plan): nothing per output point,
    // unless --figures keeps the grid.
    big["diagnostics"] = {"error"};
    const CaseSpec streamed = spec(big);
    CHECK(dampsym::estimate_case_memory(streamed, 2).bytes < 65.0 * 1024 * 1024);
    CHECK_NOTHROW(dampsym::check_memory({streamed}, 2, 200.0 * 1024 * 1024));
    CHECK_THROWS_WITH(dampsym::check_memory({streamed}, 2, 200.0 * 1024 * 1024, true),
                      Catch::Contains("output_dt"));
    // negative control: the small case fits
    CHECK_NOTHROW(
        dampsym::check_memory({spec(small_case("s", 2.0, 0.01))}, 2, 200.0 * 1024 * 1024));
}

TEST_CASE("limits: the issue's memory case is refused in < 1 s naming output_dt", "[limits][cli]") {
    TempDir dir;
    // pendulum, t_end = 1e5, dt = output_dt = 1e-4, error over the grid (10^9 points)
    write_text(dir / "mem.json",
               R"({"id": "mem", "problem": {"id": "pendulum"}, "methods": ["csv1"],
                   "t_end": 1e5, "dt": 1e-4, "output_dt": 1e-4, "diagnostics": ["error"],
                   "no_checks_because": "memory test"})");
    write_text(dir / "mem2.json",
               R"({"id": "mem2", "problem": {"id": "pendulum"}, "methods": ["csv1"],
                   "t_end": 1e3, "dt": 1e-4, "output_dt": 1e-4, "diagnostics": ["error"],
                   "no_checks_because": "memory test"})"); // 1e7 points: the estimate
    for (const auto& args :
         {std::vector<std::string>{"run", (dir / "mem.json").string(), "--out",
                                   (dir / "out").string()},
          std::vector<std::string>{"run", (dir / "mem2.json").string(), "--out",
                                   (dir / "out").string(), "--max-memory", "200M"}}) {
        const auto t0 = Clock::now();
        const CliResult r = run(args);
        const double took = std::chrono::duration<double>(Clock::now() - t0).count();
        INFO(describe(args, r));
        CHECK(r.status == 2);
        CHECK(took < 1.0);
        // the memory estimate refuses it, naming the estimate and the key (the pendulum's
        // certified reference is stored on the grid: limits.hpp grid_plan)
        CHECK_THAT(r.err, Catch::Contains("output_dt") && Catch::Contains("would need about") &&
                              Catch::Contains("reference"));
        CHECK_FALSE(fs::exists(dir / "out" / "report.json"));
    }
    // --max-memory is validated
    const CliResult bad = run({"run", (dir / "mem2.json").string(), "--out", (dir / "out").string(),
                               "--max-memory", "lots"});
    CHECK(bad.status == 2);
    CHECK_THAT(bad.err, Catch::Contains("--max-memory"));
}

TEST_CASE("limits: what a case keeps of its output grid (grid_plan)", "[limits][memory]") {
    const auto plan = [](const json& j, bool figures = false) {
        const CaseSpec c = spec(j);
        const dampsym::ProblemInfo* p = dampsym::find_problem(c.problem_id);
        REQUIRE(p);
        return dampsym::grid_plan(c, dampsym::detail::output_points(c), p->has_exact, figures);
    };
    json osc = small_case("osc", 10.0, 0.01);
    osc["output_dt"] = 0.1;
    auto p =
        plan(osc); // error against the exact solution: streamed, reference evaluated on the fly
    CHECK(p.grid);
    CHECK_FALSE(p.store_grid);
    CHECK_FALSE(p.store_reference);
    p = plan(osc, true); // --figures reads the stored grid
    CHECK(p.store_grid);
    CHECK(p.store_reference);
    json energy = osc;
    energy["diagnostics"] = {"error", "energy"};
    CHECK(plan(energy).store_grid);
    json growth = osc;
    growth["measures"] = {{"g", {{"over", "growth"}}}};
    CHECK(plan(growth).store_grid);
    json maxima = osc;
    maxima["measures"] = {{"m", {{"over", "max"}, {"norm", "rel"}}}};
    p = plan(maxima);
    CHECK_FALSE(p.store_grid);
    CHECK_FALSE(p.store_reference);
    json drift = osc; // dissipation-drift reads the reference's grid: stored, the run's streamed
    drift["diagnostics"] = {"error", "dissipation-drift"};
    p = plan(drift);
    CHECK_FALSE(p.store_grid);
    CHECK(p.store_reference);
    json pend = osc; // a certified numerical reference is stored (limits.hpp grid_plan)
    pend["problem"] = {{"id", "pendulum"}};
    p = plan(pend);
    CHECK_FALSE(p.store_grid);
    CHECK(p.store_reference);
    json nogrid = small_case("final-only", 10.0, 0.01);
    nogrid["dt_ladder"] = {0.01, 0.004}; // no common grid without output_dt: final time only
    nogrid.erase("dt");
    p = plan(nogrid);
    CHECK_FALSE(p.grid);
}

TEST_CASE("limits: streamed error and measures equal the stored-grid ones bitwise",
          "[limits][memory]") {
    // The same cases run twice: streamed (no --figures) and with the grid stored (a series sink,
    // as --figures: grid_plan stores the grid then). Exact and certified references, every
    // streamable measure, relative ones included.
    std::vector<CaseSpec> cases;
    for (const char* problem : {"oscillator", "pendulum"}) {
        json j = small_case(std::string("stream-") + problem, 20.0, 0.01);
        if (std::string(problem) == "pendulum") j["problem"] = {{"id", "pendulum"}};
        j["output_dt"] = 0.05;
        j["measures"] = {
            {"max", {{"over", "max"}}},
            {"mean", {{"over", "mean"}, {"component", "q"}}},
            {"rms", {{"over", "rms"}, {"norm", "rel"}}},
            {"final", {{"over", "final"}}},
            {"energy", {{"quantity", "energy-error"}, {"norm", "rel"}, {"over", "mean"}}}};
        cases.push_back(spec(j));
    }
    const json streamed = dampsym::run_cases(cases, dampsym::RunOptions{});
    dampsym::RunOptions stored_opts;
    stored_opts.series_sink = [](const json&) {};
    const json stored = dampsym::run_cases(cases, stored_opts);
    for (std::size_t c = 0; c < cases.size(); ++c)
        for (std::size_t r = 0; r < 2; ++r) {
            const json& a = run_of(streamed, c, r);
            const json& b = run_of(stored, c, r);
            INFO(cases[c].id << " run " << r);
            REQUIRE(a["status"] == "ok");
            CHECK(a["metrics"]["error"].is_object());
            CHECK(a["metrics"]["measure"].size() == 5);
            CHECK(a["metrics"].dump() == b["metrics"].dump()); // every digit
            CHECK(a["final_state"] == b["final_state"]);
        }
    CHECK(streamed["cases"][0]["reference"] == stored["cases"][0]["reference"]);
}

// Peak resident memory (KiB) of `dampsym ARGS`, its exit status in `status`.
long peak_rss_kib(const std::vector<std::string>& args, const fs::path& dir, int& status) {
    const pid_t pid = spawn(args, dir);
    int raw = 0;
    struct rusage ru {};
    REQUIRE(wait4(pid, &raw, 0, &ru) == pid);
    status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 1000 + WTERMSIG(raw);
    return ru.ru_maxrss;
}

TEST_CASE("limits: a case whose error streams runs in bounded memory whatever its output grid",
          "[limits][cli][memory]") {
    TempDir dir;
#if DAMPSYM_TEST_ASAN
    // 3e5 output points: the sanitizer build's full-size run took 40 s at -O1 (the Release build
    // runs the 1e7 points and the stored-grid negative control below)
    const double t_end = 3e2;
#else
    const double t_end = 1e4; // 1e7 output points
#endif
    json j = small_case("streamed", t_end, 1e-3);
    j["methods"] = {"csv1"};
    j["output_dt"] = 1e-3;
    j["measures"] = {{"max", {{"over", "max"}}}};
    write_text(dir / "streamed.json", j.dump());
    const auto t0 = Clock::now();
    int status = -1;
    const long kib = peak_rss_kib(
        {"run", (dir / "streamed.json").string(), "--out", (dir / "out").string(), "--quiet"},
        dir.path(), status);
    const double took = std::chrono::duration<double>(Clock::now() - t0).count();
    INFO("peak RSS " << kib << " KiB, " << took << " s; stderr: " << read_text(dir / "stderr"));
    CHECK(status == 0);
    CHECK(kib <= 200 * 1024);
    const json report = read_json(dir / "out" / "report.json");
    const json& rec = run_of(report, 0, 0);
    const double points = std::round(t_end / 1e-3) + 1;
    CHECK(rec["observed"]["grid_points"].get<double>() == points);
    CHECK(report["cases"][0]["reference"]["points"].get<double>() == points);
    CHECK(rec["metrics"]["error"]["max_abs"].get<double>() > 0.0);
    CHECK(rec["metrics"]["error"]["max_abs"].get<double>() < 1e-3);
    // Stored (--figures), the grid of 1e7 points would not fit in 200 MiB: refused before
    // running (exit 2, < 1 s).
    j["t_end"] = 1e4;
    write_text(dir / "long.json", j.dump());
    const CliResult refused = run({"run", (dir / "long.json").string(), "--out",
                                   (dir / "out2").string(), "--figures", "--max-memory", "200M"});
    CHECK(refused.status == 2);
    CHECK_THAT(refused.err, Catch::Contains("output_dt") && Catch::Contains("MiB"));
#if !DAMPSYM_TEST_ASAN
    // Negative control: with a diagnostic that reads the stored grid (energy), the same run's
    // peak memory is above the bound.
    j["diagnostics"] = {"error", "energy"};
    write_text(dir / "stored.json", j.dump());
    const long stored_kib = peak_rss_kib(
        {"run", (dir / "stored.json").string(), "--out", (dir / "out3").string(), "--quiet"},
        dir.path(), status);
    INFO("stored: peak RSS " << stored_kib << " KiB");
    CHECK(status == 0);
    CHECK(stored_kib > 200 * 1024);
#endif
}

TEST_CASE("limits: I/O errors exit 3 from the executable with one message", "[limits][cli]") {
    TempDir dir;
    copy_data("cases/cli-pass.json", dir.path());
    write_text(dir / "a-file", "x");
    for (const std::string& out : {std::string("/proc/x"), (dir / "a-file").string()}) {
        const pid_t pid =
            spawn({"run", (dir / "cli-pass.json").string(), "--out", out}, dir.path());
        INFO(out);
        CHECK(wait_status(pid) == 3);
        const std::string err = read_text(dir / "stderr");
        CHECK_THAT(err, Catch::Contains(out));
        CHECK(std::count(err.begin(), err.end(), '\n') == 1);
    }
}

TEST_CASE("limits: SIGINT/SIGTERM write the report marked interrupted, a second signal exits at "
          "once and the previous report stays whole",
          "[limits][signals]") {
    TempDir dir;
    copy_data("cases/cli-pass.json", dir.path());
    write_text(dir / "long.json", small_case("long", 1e6, 1e-3).dump()); // 2e9 steps
    const fs::path out = dir / "out";
    fs::create_directories(out);
    const std::string previous = "{\"previous\": \"report\"}\n";
    for (int sig : {SIGINT, SIGTERM}) {
        write_text(out / "report.json", previous);
        const pid_t pid =
            spawn({"run", (dir / "cli-pass.json").string(), (dir / "long.json").string(), "--out",
                   out.string(), "--jobs", "2", "--time-budget", "0"},
                  dir.path());
        // the note on the long case is printed once the handlers are installed
        wait_for_text(dir / "stderr", "predicted duration", 20.0);
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
        const auto t0 = Clock::now();
        kill(pid, sig);
        const int status = wait_status(pid);
        const double took = std::chrono::duration<double>(Clock::now() - t0).count();
        INFO("signal " << sig << ", stderr: " << read_text(dir / "stderr"));
        CHECK(status == 128 + sig);
        CHECK(took < 3.0);
        const json report = read_json(out / "report.json");
        CHECK(report["interrupted"]["signal"] == (sig == SIGINT ? "SIGINT" : "SIGTERM"));
        CHECK(report["cases"][0]["id"] == "cli-pass"); // what finished is there
        for (const auto& run : report["cases"][1]["runs"]) CHECK(run["status"] == "interrupted");
    }
    // A second signal: exit at once (status 130, the previous report untouched, never truncated).
    write_text(out / "report.json", previous);
    const pid_t pid =
        spawn({"run", (dir / "long.json").string(), "--out", out.string(), "--time-budget", "0"},
              dir.path());
    wait_for_text(dir / "stderr", "predicted duration", 20.0);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    kill(pid, SIGINT);
    wait_for_text(dir / "stderr", "stopping at the next step", 5.0);
    kill(pid, SIGINT);
    const int status = wait_status(pid);
    CHECK(status == 130);
    const std::string now = read_text(out / "report.json");
    // either the previous report (the second signal came first) or the whole new one
    if (now != previous) CHECK_NOTHROW(json::parse(now));
}

// ---- the Newton residual of a solve-failed run
// ---------------------------------------------------

TEST_CASE("limits: a Newton solve that cannot converge leaves its iterations and residual",
          "[limits][faults]") {
    // x² + 1 = 0 has no real root: Newton wanders for all max_iterations
    dampsym::StageNewton newton(1);
    dampsym::Counters counters;
    newton.X[0] = 0.5;
    const int it = newton.solve(dampsym::NewtonPolicy::full, counters, [&](bool) {
        newton.R[0] = newton.X[0] * newton.X[0] + 1.0;
        newton.S(0, 0) = 2.0 * newton.X[0];
    });
    CHECK(it == 0);
    CHECK(counters.failed_solve_iterations == dampsym::StageNewton::max_iterations);
    CHECK(counters.failed_solve_residual >= 1.0); // |x² + 1| ≥ 1 at every iterate
    CHECK(std::isfinite(counters.failed_solve_update));
    // a NaN residual ends the solve at once; the residual is recorded as non-finite (null)
    dampsym::Counters nan_counters;
    newton.X[0] = 0.5;
    CHECK(newton.solve(dampsym::NewtonPolicy::full, nan_counters, [&](bool) {
        newton.R[0] = std::numeric_limits<double>::quiet_NaN();
        newton.S(0, 0) = 1.0;
    }) == 0);
    CHECK(nan_counters.failed_solve_iterations == 1);
    CHECK(std::isnan(nan_counters.failed_solve_residual));
    CHECK(dampsym::solve_failure_json(nan_counters)["residual"].is_null());
    // negative control: a solve that converges records nothing
    dampsym::Counters ok_counters;
    newton.X[0] = 3.0;
    CHECK(newton.solve(dampsym::NewtonPolicy::full, ok_counters, [&](bool) {
        newton.R[0] = newton.X[0] * newton.X[0] - 4.0;
        newton.S(0, 0) = 2.0 * newton.X[0];
    }) > 0);
    CHECK(ok_counters.failed_solve_iterations == 0);
}

TEST_CASE("limits: a solve-failed run reports the Newton iterations and residual",
          "[limits][faults]") {
    // gauss2 on the pendulum with h = 20: its stage Newton does not converge in the first step
    json j = small_case("newton-fails", 40.0, 20.0);
    j["problem"] = {{"id", "pendulum"}, {"gamma", 0.1}};
    j["methods"] = {"gauss2", "implicit-euler"};
    j["diagnostics"] = {"energy"};
    j.erase("expect");
    j["no_checks_because"] = "the run records are what is tested";
    dampsym::RunOptions opt;
    opt.time_budget = 0.0;
    const json report = dampsym::run_cases({spec(j)}, opt);
    const json& bad = run_of(report, 0, 0);
    INFO(bad.dump());
    REQUIRE(bad["status"] == "solve-failed");
    CHECK(bad["failed_at_step"] == 1);
    REQUIRE(bad.contains("solve_failure"));
    CHECK(bad["solve_failure"]["iterations"] == dampsym::StageNewton::max_iterations);
    REQUIRE(bad["solve_failure"]["residual"].is_number());
    CHECK(bad["solve_failure"]["residual"].get<double>() > 1e-8); // far from converged
    // negative control: the run that converges has no solve_failure
    CHECK(run_of(report, 0, 1)["status"] == "ok");
    CHECK_FALSE(run_of(report, 0, 1).contains("solve_failure"));
}

// ---- the reference in the case's time budget ---------------------------------------------------

namespace {
// Undamped pendulum over a long span: a certified GSL reference of seconds, a cheap run.
json slow_reference_case(const std::string& id, double t_end, double q0) {
    json j = small_case(id, t_end, 1.0);
    j["problem"] = {{"id", "pendulum"}, {"gamma", 0.0}, {"q0", q0}};
    j["methods"] = {"csv1"};
    j["output_dt"] = t_end / 100.0;
    j.erase("expect");
    j["expect"]["error bounded"] = {
        {"metric", "error.final_abs"}, {"methods", "all"}, {"le", 10.0}};
    return j;
}
} // namespace

TEST_CASE("limits: the reference's time counts in the case's time budget", "[limits]") {
    // t_end 1e5: the reference takes ~6 s (Release); the budget is 0.3 s
    json slow = slow_reference_case("slow-reference", 1e5, 0.987654321);
    slow["timeout_seconds"] = 0.3;
    const std::vector<CaseSpec> cases{spec(slow), spec(small_case("clean", 2.0, 0.01))};
    dampsym::RunOptions opt;
    opt.time_budget = 0.0;
    const json clean = dampsym::run_cases({cases[1]}, opt);
    const auto t0 = Clock::now();
    const json report = dampsym::run_cases(cases, opt);
    const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
    const json& c = report["cases"][0];
    INFO(c["reference"].dump());
    CHECK(c["reference"]["ok"] == false);
    CHECK_THAT(c["reference"]["error"].get<std::string>(), Catch::Contains("time budget"));
    CHECK(c["runs"][0]["status"] == "timeout");
    CHECK(c["runs"][0]["steps"] == 0);
    for (const auto& ck : c["checks"]) CHECK_FALSE(ck["passed"].get<bool>());
    CHECK(report["cases"][1] == clean["cases"][0]);
    CHECK(wall < 3.0);
}

TEST_CASE("limits: a reference stopped by one case's budget is not reused by another case",
          "[limits]") {
    // the same problem and grid (one reference-cache key); the first case's budget (1 ms) stops
    // the reference, the second case has none and must get a complete reference
    json a = slow_reference_case("tiny-budget", 2000.0, 0.876543219);
    a["timeout_seconds"] = 1e-3;
    json b = slow_reference_case("no-budget", 2000.0, 0.876543219);
    dampsym::RunOptions opt;
    opt.jobs = 1;
    opt.time_budget = 0.0;
    const json report = dampsym::run_cases({spec(a), spec(b)}, opt);
    INFO(report["cases"][0]["reference"].dump());
    INFO(report["cases"][1]["reference"].dump());
    CHECK(report["cases"][0]["reference"]["ok"] == false);
    CHECK(report["cases"][1]["reference"]["ok"] == true);
    CHECK(run_of(report, 1, 0)["status"] == "ok");
    CHECK(report["cases"][1]["checks"][0]["passed"] == true);
}

// ---- streaming outputs: a full disk is an I/O error (exit 3), never a crash
// ----------------------

namespace {
// Runs the binary with a file-size limit (RLIMIT_FSIZE: writes past it fail as on a full disk).
int run_with_file_limit(const std::vector<std::string>& args, const fs::path& dir, rlim_t bytes) {
    std::vector<std::string> full{dampsym_test::binary_path()};
    full.insert(full.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& a : full) argv.push_back(a.data());
    argv.push_back(nullptr);
    const std::string out = (dir / "stdout").string(), err = (dir / "stderr").string();
    const pid_t pid = fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
        const rlimit lim{bytes, bytes};
        setrlimit(RLIMIT_FSIZE, &lim);
        const int o = open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        const int e = open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (o < 0 || e < 0) _exit(120);
        dup2(o, 1);
        dup2(e, 2);
        execv(argv[0], argv.data());
        _exit(121);
    }
    return wait_status(pid);
}
} // namespace

TEST_CASE("limits: a report that cannot be written (full disk) exits 3 with a message",
          "[limits][cli]") {
    TempDir dir;
    copy_data("cases/cli-pass.json", dir.path());
    const fs::path out = dir / "out";
    // 1 KiB: report.json (~5 KiB) cannot be written
    const int status = run_with_file_limit({"run", (dir / "cli-pass.json").string(), "--out",
                                            out.string(), "--time-budget", "0", "--quiet"},
                                           dir.path(), 1024);
    const std::string err = read_text(dir / "stderr");
    INFO(err);
    CHECK(status == 3); // not killed by SIGXFSZ (1000 + 25)
    CHECK_THAT(err, Catch::Contains("report.json: cannot write"));
    std::error_code ec;
    CHECK_FALSE(fs::exists(out / "report.json.dampsym-tmp", ec)); // no partial file left behind
}

TEST_CASE("limits: a --figures series file that cannot be written: the report is written, "
          "exit 3",
          "[limits][cli]") {
    TempDir dir;
    copy_data("cases/cli-pass.json", dir.path());
    const fs::path out = dir / "out";
    // 8 KiB: the report (~5 KiB) fits, the case's series file (~11 KiB) does not
    const int status =
        run_with_file_limit({"run", (dir / "cli-pass.json").string(), "--out", out.string(),
                             "--time-budget", "0", "--quiet", "--figures"},
                            dir.path(), 8 * 1024);
    const std::string err = read_text(dir / "stderr");
    INFO(err);
    CHECK(status == 3);
    CHECK_THAT(err, Catch::Contains("series"));
    CHECK_THAT(err, Catch::Contains("cli-pass.json"));
    REQUIRE(fs::exists(out / "report.json"));
    const json report = json::parse(read_text(out / "report.json"));
    REQUIRE(report.contains("output_errors"));
    CHECK(report["output_errors"].size() == 1);
    CHECK(report["summary"]["checks_failed"] == 0); // the results themselves are intact
}
