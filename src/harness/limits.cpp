#include "harness/limits.hpp"

#include "diagnostics/diagnostic.hpp"
#include "harness/case.hpp"
#include "harness/case_figures.hpp"
#include "harness/case_job.hpp"
#include "harness/problem_info.hpp"
#include "harness/report.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <mutex>
#include <unistd.h>

namespace dampsym {

std::atomic<int> g_stop_signal{0};

namespace {

extern "C" void on_stop_signal(int sig) {
    // Async-signal-safe only: an atomic exchange, write(2) and _exit(2).
    if (g_stop_signal.exchange(sig) != 0) {
        static const char msg[] = "\ndampsym: second signal: exiting at once\n";
        (void)!write(STDERR_FILENO, msg, sizeof msg - 1);
        _exit(128 + sig);
    }
    static const char msg[] = "\ndampsym: stopping at the next step boundary (signal again to "
                              "exit at once); writing the report of what finished\n";
    (void)!write(STDERR_FILENO, msg, sizeof msg - 1);
}

} // namespace

void install_stop_handlers() {
    struct sigaction sa {};
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
}

int stop_signal() noexcept {
    return g_stop_signal.load(std::memory_order_relaxed);
}
void request_stop(int signal) noexcept {
    g_stop_signal.store(signal);
}
void clear_stop() noexcept {
    g_stop_signal.store(0);
}

namespace {
std::int64_t now_ns() noexcept {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
}
} // namespace

void CaseGuard::start() noexcept {
    std::int64_t expected = -1;
    start_ns_.compare_exchange_strong(expected, now_ns() - spent_ns_.load());
}

void CaseGuard::pause() noexcept {
    const std::int64_t start = start_ns_.exchange(-1);
    if (start >= 0) spent_ns_.store(now_ns() - start);
}

std::optional<RunStatus> CaseGuard::stop_status() const noexcept {
    if (stop_requested()) return RunStatus::interrupted;
    if (timeout_ <= 0.0) return std::nullopt;
    const std::int64_t start = start_ns_.load(std::memory_order_relaxed);
    if (start < 0) return std::nullopt;
    const std::int64_t now =
        std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch())
            .count();
    if (static_cast<double>(now - start) * 1e-9 > timeout_) return RunStatus::timeout;
    return std::nullopt;
}

namespace {
std::atomic<bool> g_fault_set{false};
std::mutex g_fault_mutex;
std::optional<FaultPlan> g_fault;
} // namespace

void set_fault_plan(std::optional<FaultPlan> plan) {
    std::lock_guard<std::mutex> lock(g_fault_mutex);
    g_fault = std::move(plan);
    g_fault_set.store(g_fault.has_value());
}

const FaultPlan* fault_for(std::string_view case_id, std::string_view method) {
    if (!g_fault_set.load(std::memory_order_relaxed)) return nullptr;
    std::lock_guard<std::mutex> lock(g_fault_mutex);
    if (g_fault && g_fault->case_id == case_id && g_fault->method == method) return &*g_fault;
    return nullptr;
}

void poison_reference(ReferenceRequest& req, const FaultPlan* fault) {
    if (!fault || fault->kind != FaultPlan::Kind::reference_nan) return;
    req.rhs = [inner = req.rhs, after = fault->step,
               count = std::int64_t{0}](double t, const double* y, double* dydt) mutable {
        inner(t, y, dydt);
        if (++count >= after) dydt[0] = std::numeric_limits<double>::quiet_NaN();
    };
}

namespace {
constexpr const char* kReferenceStopped = "reference stopped: ";
std::string seconds_text(double s) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%g s", s);
    return buf;
}
} // namespace

void stop_reference_with(ReferenceRequest& req, const CaseGuard& guard) {
    req.rhs = [inner = req.rhs, &guard, count = std::uint32_t{0}](double t, const double* y,
                                                                  double* dydt) mutable {
        if ((++count & 255u) == 0)
            if (const auto stop = guard.stop_status())
                throw std::runtime_error(
                    std::string(kReferenceStopped) +
                    (*stop == RunStatus::timeout
                         ? "the case's time budget (timeout_seconds / --case-timeout, " +
                               seconds_text(guard.timeout()) + ") ran out"
                         : std::string("interrupted by a signal")));
        inner(t, y, dydt);
    };
}

bool reference_stopped(const ReferenceSolution& sol) {
    return !sol.ok && sol.error.find(kReferenceStopped) != std::string::npos;
}

nlohmann::json solve_failure_json(const Counters& counters) {
    auto number = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(); };
    return {{"iterations", counters.failed_solve_iterations},
            {"residual", number(counters.failed_solve_residual)},
            {"last_update", number(counters.failed_solve_update)}};
}

std::function<void(const nlohmann::json&)>
recording_output_errors(std::function<void(const nlohmann::json&)> sink,
                        std::vector<std::string>& errors) {
    return [sink = std::move(sink), &errors](const nlohmann::json& item) {
        try {
            sink(item);
        } catch (const OutputError& e) {
            errors.emplace_back(e.what());
        }
    };
}

double default_max_memory() {
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
    if (pages <= 0 || page <= 0) return 4.0 * 1024 * 1024 * 1024; // unknown: 4 GiB
    return 0.5 * static_cast<double>(pages) * static_cast<double>(page);
}

double parse_memory_size(const std::string& text) {
    const std::string what = "--max-memory " + brief(text) +
                             ": expected a size in bytes with an optional suffix K, M, G or T "
                             "(powers of 1024), e.g. 8G";
    if (text.empty()) throw InputError(what);
    errno = 0;
    char* end = nullptr;
    const double x = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || errno == ERANGE || !std::isfinite(x) || !(x > 0.0))
        throw InputError(what);
    std::string suffix(end);
    if (suffix.size() == 3 && suffix.substr(1) == "iB") // KiB, MiB, ...
        suffix.resize(1);
    else if (suffix.size() == 2 && (suffix[1] == 'B' || suffix[1] == 'b')) // KB, MB, ...
        suffix.pop_back();
    double scale = 1.0;
    if (suffix.empty() || suffix == "B" || suffix == "b")
        scale = 1.0;
    else if (suffix == "K" || suffix == "k")
        scale = 1024.0;
    else if (suffix == "M" || suffix == "m")
        scale = 1024.0 * 1024;
    else if (suffix == "G" || suffix == "g")
        scale = 1024.0 * 1024 * 1024;
    else if (suffix == "T" || suffix == "t")
        scale = 1024.0 * 1024 * 1024 * 1024;
    else
        throw InputError(what);
    return x * scale;
}

std::string format_bytes(double bytes) {
    char buf[64];
    if (bytes >= 1024.0 * 1024 * 1024)
        std::snprintf(buf, sizeof buf, "%.1f GiB", bytes / (1024.0 * 1024 * 1024));
    else if (bytes >= 1024.0 * 1024)
        std::snprintf(buf, sizeof buf, "%.1f MiB", bytes / (1024.0 * 1024));
    else
        std::snprintf(buf, sizeof buf, "%.0f KiB", bytes / 1024.0);
    return buf;
}

GridPlan grid_plan(const CaseSpec& c, std::int64_t points, bool has_exact, bool figures) {
    GridPlan p;
    // A "growth" measure is a least-squares fit over all its points (MeasureAccumulator keeps
    // them).
    bool streamable =
        !figures && std::none_of(c.measures.begin(), c.measures.end(), [](const MeasureSpec& m) {
            return m.over == MeasureStat::growth;
        });
    bool reference_grid = false;
    for (const std::string& name : c.diagnostics) {
        const DiagnosticInfo* d = find_diagnostic(name);
        if (!d) continue;
        if (d->needs.grid || (d->needs.grid_if_points && points > 1)) {
            p.grid = true;
            if (!d->needs.streams) streamable = false;
        }
        reference_grid = reference_grid || d->needs.reference_grid;
    }
    p.store_grid = p.grid && !streamable;
    p.store_reference = p.grid && (p.store_grid || !has_exact || reference_grid);
    return p;
}

// What a case holds at once (typed_case.hpp, recorder.hpp, gsl_reference.cpp):
// - per run in flight (at most min(jobs, runs)): the Recorder's output grid, (points+1) × dim
//   doubles, when the grid is stored (grid_plan);
// - per case: the reference on the grid when it is stored, (points+1) × dim doubles held three
//   times (the certified solve, its certifier, the case's copy), its times (points+1 doubles, three
//   times) and the reference cache's key (~26 characters per time);
// - the stability sweep: its rows (about 64 bytes per (γ, h) cell).
// A streamed grid (grid_plan) costs nothing per point.
MemoryEstimate estimate_case_memory(const CaseSpec& c, int jobs, bool figures) {
    MemoryEstimate est;
    const double dim = std::max(1, c.dim);
    const std::int64_t intervals = detail::output_points(c);
    const double points = static_cast<double>(intervals) + 1.0;
    const ProblemInfo* prob = find_problem(c.problem_id);
    // as the runner: a case with "figures": false keeps no series (runner.cpp set_figures)
    const GridPlan plan =
        grid_plan(c, intervals, prob && prob->has_exact, figures && !case_figures_off(c));
    bool reference = false;
    for (const std::string& name : c.diagnostics)
        if (const DiagnosticInfo* d = find_diagnostic(name))
            reference = reference || d->needs.reference;
    const double runs = static_cast<double>(c.methods.size() * c.dts.size());
    const double at_once = std::max(1.0, std::min<double>(std::max(1, jobs), runs));
    double grid_bytes = 0.0, ref_bytes = 0.0, sweep_bytes = 0.0;
    if (plan.store_grid) grid_bytes = at_once * points * dim * 8.0;
    if (reference && plan.store_reference)
        ref_bytes = 3.0 * points * (dim + 1.0) * 8.0 + 26.0 * points;
    if (c.sweep) {
        const auto cells = [](const Range3& r) {
            return std::floor((r.to - r.from) / r.step + 1e-9) + 1.0;
        };
        sweep_bytes = static_cast<double>(c.methods.size()) * cells(c.sweep->gamma) *
                      cells(c.sweep->h) * 64.0;
    }
    est.bytes = 64.0 * 1024 * 1024 + grid_bytes + ref_bytes + sweep_bytes; // + the program itself
    char buf[512];
    if (sweep_bytes > grid_bytes + ref_bytes) {
        std::snprintf(buf, sizeof buf, "stability sweep: %.3g cells x %zu methods",
                      sweep_bytes / 64.0 / static_cast<double>(c.methods.size()), c.methods.size());
        est.largest = buf;
        est.key = "stability_sweep";
    } else if (grid_bytes > 0.0) {
        std::snprintf(buf, sizeof buf,
                      "output grid of %.3g points x %d state components (%g runs at once%s)",
                      points, c.dim, at_once, ref_bytes > 0.0 ? ", plus the reference on it" : "");
        est.largest = buf;
        est.key = c.output_dt ? "output_dt" : "t_end";
    } else {
        // The runs stream the grid; the certified numerical reference is stored (grid_plan).
        std::snprintf(buf, sizeof buf,
                      "certified reference on the output grid of %.3g points x %d state "
                      "components; the runs compare on the fly, but a numerical reference is "
                      "stored: docs/case-keys.md",
                      points, c.dim);
        est.largest = buf;
        est.key = c.output_dt ? "output_dt" : "t_end";
    }
    return est;
}

void check_memory(const std::vector<CaseSpec>& cases, int jobs, double max_bytes, bool figures) {
    for (const CaseSpec& c : cases) {
        const MemoryEstimate est = estimate_case_memory(c, jobs, figures);
        if (est.bytes <= max_bytes) continue;
        throw InputError(c.file + ": " + est.key + ": case '" + c.id + "' would need about " +
                         format_bytes(est.bytes) + " of memory (" + est.largest +
                         "), above --max-memory " + format_bytes(max_bytes) + "; raise " + est.key +
                         (est.key == "output_dt" ? " (fewer output points)" : "") +
                         " or --max-memory");
    }
}

void validate_limit_keys(const nlohmann::json& j, const std::string& file) {
    if (!j.contains("timeout_seconds")) return;
    const nlohmann::json& v = j["timeout_seconds"];
    if (!v.is_number() || !(v.get<double>() > 0.0) || !std::isfinite(v.get<double>()))
        throw InputError(file + ": timeout_seconds: must be a number > 0 (seconds), got " +
                         brief(v));
}

nlohmann::json completion_check(const nlohmann::json& case_record,
                                const std::vector<std::string>& task_errors) {
    std::string message;
    int incomplete = 0;
    if (case_record.contains("runs"))
        for (const auto& r : case_record["runs"]) {
            const std::string st = r.value("status", std::string());
            if (st != "timeout" && st != "interrupted" && st != "error") continue;
            ++incomplete;
            if (incomplete > 5) continue;
            message += (message.empty() ? "" : "; ") + r.value("method", std::string("?")) +
                       " at dt = " + r.value("dt", nlohmann::json()).dump() + ": " + st;
            if (st == "error")
                message += " (" + r.value("error", std::string()) + ")";
            else
                message += " at step " + std::to_string(r.value("steps", std::int64_t{0})) +
                           " of " + std::to_string(r.value("steps_planned", std::int64_t{0}));
        }
    if (incomplete > 5) message += "; and " + std::to_string(incomplete - 5) + " more";
    for (const auto& e : task_errors) {
        ++incomplete;
        message += (message.empty() ? "" : "; ") + std::string("task failed: ") + e;
    }
    if (incomplete == 0) return nullptr;
    return {{"name", "case completed"},
            {"metric", "run.status"},
            {"method", "(all)"},
            {"op", "le"},
            {"expected", 0},
            {"negative_control", false},
            {"passed", false},
            {"value", incomplete},
            {"message", "runs or tasks that did not finish: " + message}};
}

nlohmann::json failed_case_record(const CaseSpec& c, const std::vector<std::string>& task_errors) {
    nlohmann::json params = nlohmann::json::object();
    for (const auto& [k, v] : c.params.scalars) params[k] = v;
    for (const auto& [k, v] : c.params.arrays) params[k] = v;
    nlohmann::json out = {{"id", c.id},
                          {"title", c.title},
                          {"source", c.source},
                          {"file", c.file},
                          {"problem", {{"id", c.problem_id}, {"params", params}}},
                          {"methods", c.methods},
                          {"t0", c.t0},
                          {"t_end", c.t_end},
                          {"dt_ladder", c.dts},
                          {"diagnostics", c.diagnostics},
                          {"overrides", c.overrides},
                          {"reference", {{"kind", "none"}}},
                          {"runs", nlohmann::json::array()},
                          {"method_metrics", nlohmann::json::object()},
                          {"errors", task_errors}};
    out["checks"] = nlohmann::json::array({completion_check(out, task_errors)});
    return out;
}

void add_limit_options(CLI::App& run, CliLimits& limits) {
    run.add_option("--case-timeout", limits.case_timeout,
                   "seconds per case (its reference and its runs); a run past it stops at the "
                   "next step with status timeout (a reference: reference-failed), the case fails, "
                   "the others go on (exit 1); "
                   "a case's timeout_seconds wins; default 0 = none")
        ->check(CLI::Range(0.0, 1e9));
    run.add_option("--max-memory", limits.max_memory,
                   "refuse (exit 2) a case whose estimated peak memory exceeds SIZE (bytes, or "
                   "with K/M/G/T); default half the physical memory. The error diagnostic and "
                   "measures stream over the output grid (no memory per output point) unless "
                   "another diagnostic, a growth measure, --figures or a certified numerical "
                   "reference stores it (docs/case-keys.md)");
}

void before_run(const std::vector<CaseSpec>& cases, int jobs, const CliLimits& limits,
                bool figures) {
    const double max_bytes =
        limits.max_memory.empty() ? default_max_memory() : parse_memory_size(limits.max_memory);
    check_memory(cases, jobs, max_bytes, figures);
    install_stop_handlers();
}

void mark_interrupted(nlohmann::json& report) {
    const int sig = stop_signal();
    if (sig == 0) return;
    report["interrupted"] = {
        {"signal", sig == SIGINT    ? "SIGINT"
                   : sig == SIGTERM ? "SIGTERM"
                                    : "signal"},
        {"note", "stopped at a step boundary: runs with status interrupted did not finish"}};
}

int exit_status_after_run(int status) {
    const int sig = stop_signal();
    return sig != 0 ? 128 + sig : status;
}

double case_timeout(const CaseSpec& c, double cli_timeout) {
    if (c.raw.is_object() && c.raw.contains("timeout_seconds") &&
        c.raw["timeout_seconds"].is_number())
        return c.raw["timeout_seconds"].get<double>();
    return cli_timeout;
}

} // namespace dampsym
