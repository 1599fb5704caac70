#include "harness/run/limits.hpp"

#include "harness/case/case.hpp"
#include "harness/case/recorded_file.hpp"
#include "harness/finite_option.hpp"
#include "harness/report/report.hpp"
#include "harness/run/case_job.hpp"

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

std::atomic<pid_t> g_child_group{0}; // the figure script's process group while it runs, else 0

extern "C" void on_stop_signal(int sig) {
    // Async-signal-safe only: atomics, kill(2), write(2) and _exit(2).
    const pid_t child = g_child_group.load();
    if (g_stop_signal.exchange(sig) != 0) {
        if (child > 0) kill(-child, SIGKILL); // nothing of dampsym's goes on writing after it
        static const char msg[] = "\ndampsym: second signal: exiting at once\n";
        (void)!write(STDERR_FILENO, msg, sizeof msg - 1);
        _exit(128 + sig);
    }
    if (child > 0) kill(-child, sig); // the figure script stops with dampsym (its own group)
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

void set_stop_child_group(pid_t group) noexcept {
    g_child_group.store(group);
    const int sig = stop_signal();
    if (group > 0 && sig != 0) kill(-group, sig); // a signal that came before the group was set
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
    // the sink is called from the threads that finish cases
    auto mutex = std::make_shared<std::mutex>();
    return [sink = std::move(sink), &errors, mutex](const nlohmann::json& item) {
        try {
            sink(item);
        } catch (const OutputError& e) {
            std::lock_guard<std::mutex> lock(*mutex);
            errors.emplace_back(e.what());
        }
    };
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
                          {"file", recorded_case_file(c.file)},
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
        ->check(finite_number())
        ->check(CLI::Range(0.0, 1e9));
    run.add_option("--max-memory", limits.max_memory,
                   "refuse (exit 2) a case whose estimated peak memory exceeds SIZE (bytes, or "
                   "with K/M/G/T); default half the physical memory. The error diagnostic and "
                   "measures stream over the output grid (no memory per output point) unless "
                   "another diagnostic, a growth measure, --figures or a certified numerical "
                   "reference stores it (docs/case-keys.md)")
        // validated at parse time: an empty SIZE would otherwise pass for the default
        ->check(CLI::Validator(
            [](std::string& text) -> std::string {
                try {
                    (void)parse_memory_size(text);
                    return "";
                } catch (const InputError& e) {
                    return e.what();
                }
            },
            "SIZE"));
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
