// Limits of a run that an unattended CI job must survive (docs/case-keys.md "Time and memory
// limits", docs/ci.md "Exit status"):
//
// - Time: a case's time budget (`--case-timeout SECONDS` or the case key `timeout_seconds`). Its
//   clock starts when the case starts, before its reference: a numerical reference past it stops
//   (reference-failed, naming the budget; stop_reference_with) and a run past it stops at the next
//   step boundary with status "timeout" and the step reached; the case's later runs stop at step
//   0, its checks on those runs fail, the other cases go on, and the exit status is 1.
// - Signals: the first SIGINT/SIGTERM stops every run at its next step boundary (status
//   "interrupted"); the report of what finished is written, marked "interrupted", and the exit
//   status is 130/143. A second signal exits at once (the previous report in --out stays intact:
//   reports are replaced atomically). While the figures are drawn (`run --figures`, `plot`) the
//   signal is forwarded to the figure script, which stops quietly, and the exit status is
//   130/143 too (set_stop_child_group).
// - Memory: before anything runs, each case's peak memory is estimated (output grid × state size
//   × the copies held at once, reference grid, stability sweep) and a case above `--max-memory`
//   (default half the physical memory) is refused, exit 2, naming the estimate and the key to
//   change. The error diagnostic (and the case's measures) stream: when nothing else reads the
//   output grid, each grid point is compared on the fly and no trajectory is stored, and against
//   an exact solution the reference is evaluated at each output time instead of stored, so such a
//   case needs memory independent of its number of output points (grid_plan).
//
// The step loop itself stays the bare loop of core/integrate.hpp: integrate_guarded runs it in
// chunks and tests the stop state between chunks only (one clock read per chunk; chunks grow
// until they take ~2 ms, so the overhead is nil and the stop latency a few ms or one step).
#pragma once

#include "core/integrate.hpp"
#include "reference/gsl_reference.hpp"

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <sys/types.h>
#include <vector>

namespace CLI {
class App;
}

namespace dampsym {

struct CaseSpec;

// ---- command line (dampsym run) -----------------------------------------------------------------

struct CliLimits {
    double case_timeout = 0.0; // --case-timeout SECONDS (0 = none)
    std::string max_memory;    // --max-memory SIZE ("" = half the physical memory)
};
// Adds --case-timeout and --max-memory to `dampsym run`.
void add_limit_options(CLI::App& run, CliLimits& limits);
// Before running: the memory check (exit 2 through InputError) and the stop handlers.
void before_run(const std::vector<CaseSpec>& cases, int jobs, const CliLimits& limits,
                bool figures = false);
// After running, before the report is written: marks it "interrupted" (with the signal) if a stop
// was requested.
void mark_interrupted(nlohmann::json& report);
// The exit status: 128 + signal after a stop request (130 SIGINT, 143 SIGTERM), else `status`.
int exit_status_after_run(int status);

// ---- signals ----------------------------------------------------------------------------------

// Installs the SIGINT/SIGTERM handlers of `dampsym run` (first signal: request a stop; second:
// _exit(128 + signal) at once).
void install_stop_handlers();
// The process group of a child that must stop with dampsym (the figure script,
// harness/figures/figures.hpp, runs in its own group, so that a terminal's Ctrl-C reaches dampsym
// alone): the first signal is forwarded to the group, a second one kills it (SIGKILL) before
// dampsym exits. 0: none. A stop already requested is forwarded at once.
void set_stop_child_group(pid_t group) noexcept;
// The signal that requested a stop (SIGINT, SIGTERM), or 0.
int stop_signal() noexcept;
extern std::atomic<int> g_stop_signal; // set by the handlers; read it through stop_requested()
inline bool stop_requested() noexcept {
    return g_stop_signal.load(std::memory_order_relaxed) != 0;
}
// For tests: request a stop as the signal would / clear it.
void request_stop(int signal) noexcept;
void clear_stop() noexcept;

// ---- a case's time budget -----------------------------------------------------------------------

class CaseGuard {
public:
    using Clock = std::chrono::steady_clock;
    // seconds <= 0: no budget.
    void set_timeout(double seconds) { timeout_ = seconds; }
    double timeout() const { return timeout_; }
    // Starts the case's clock, or resumes it after pause() (while it runs, further calls are
    // no-ops: the first of concurrent runs counts).
    void start() noexcept;
    // Pauses the clock, keeping the time spent so far (called after the case's reference, before
    // its runs wait for their turn; not concurrently with start()).
    void pause() noexcept;
    // The status a run of this case must stop with now, if any (interrupted before timeout).
    std::optional<RunStatus> stop_status() const noexcept;

private:
    double timeout_ = 0.0;
    std::atomic<std::int64_t> start_ns_{-1}; // when the clock would have started; -1: not running
    std::atomic<std::int64_t> spent_ns_{0};  // time spent before the last pause
};

// ---- test-only fault injection ------------------------------------------------------------------

// A fault planted in one run (case id and method) by a test (tests/test_limits.cpp); nothing in
// the command line can set one. Before step `step` (1-based) the state is poisoned with NaN or
// inf (as a right-hand side returning NaN/inf at that step would: the run diverges at that step),
// the step's solve is reported failed (as a Newton solve that cannot converge), or an exception is
// thrown (a fault in one task while the others run).
// With method "(reference)" and kind reference_nan, the case's numerical reference has a
// right-hand side that returns NaN from its `step`-th evaluation on (a reference that cannot meet
// its tolerance: reference-failed, and the checks that read it fail).
struct FaultPlan {
    enum class Kind { nan, inf, solve_failed, exception, reference_nan };
    std::string case_id, method;
    Kind kind = Kind::nan;
    std::int64_t step = 1;
};
void set_fault_plan(std::optional<FaultPlan> plan); // tests only
// The plan for this run, or null (always null unless a test set one: one relaxed atomic load).
const FaultPlan* fault_for(std::string_view case_id, std::string_view method);

// Wraps req.rhs as a reference_nan plan says (no-op for a null plan).
void poison_reference(ReferenceRequest& req, const FaultPlan* fault);

// Wraps req.rhs so that the reference stops once `guard` says stop (the case's time budget ran
// out, or a signal): the rhs then throws, so the reference fails (ok = false) with a message
// naming the budget. The guard must outlive the request. Tested every 256 evaluations.
void stop_reference_with(ReferenceRequest& req, const CaseGuard& guard);
// Whether a reference failed because its guard stopped it (such a result is not shared with
// other cases through the reference cache: their budgets may differ).
bool reference_stopped(const ReferenceSolution& sol);

// The run record's "solve_failure" (status solve-failed): iterations, residual and last update of
// the Newton solve that failed (Counters::failed_solve_*; null where non-finite).
nlohmann::json solve_failure_json(const Counters& counters);

// Wraps a streaming output (the --figures series files) so that an I/O error (OutputError) is
// recorded in `errors` and the run goes on: the report is still written, with the errors, and
// the exit status is 3. `errors` must outlive the sink; the sink is called from one thread.
std::function<void(const nlohmann::json&)>
recording_output_errors(std::function<void(const nlohmann::json&)> sink,
                        std::vector<std::string>& errors);

// Like integrate() (bitwise the same states), in chunks of growing length with guard.stop_status()
// tested between chunks. A stop gives {timeout|interrupted, steps done, steps done}.
template <class Stepper, class Observer = NoObserver>
IntegrateOutcome integrate_guarded(Stepper& stepper, Vec& z, double t0, double h, std::int64_t n,
                                   Observer* observer, const CaseGuard& guard,
                                   const FaultPlan* fault = nullptr) {
    using Clock = std::chrono::steady_clock;
    std::int64_t k = 0, chunk = 1;
    while (k < n) {
        if (const auto stop = guard.stop_status()) return {*stop, k, k};
        if (fault && k == fault->step - 1) {
            if (fault->kind == FaultPlan::Kind::solve_failed)
                return {RunStatus::solve_failed, k, k + 1};
            if (fault->kind == FaultPlan::Kind::exception)
                throw std::runtime_error("injected fault: exception before step " +
                                         std::to_string(fault->step));
            z[0] = fault->kind == FaultPlan::Kind::nan ? std::numeric_limits<double>::quiet_NaN()
                                                       : std::numeric_limits<double>::infinity();
        }
        const auto chunk_start = Clock::now();
        std::int64_t end = n - k > chunk ? k + chunk : n;
        if (fault && k < fault->step - 1 && end > fault->step - 1) end = fault->step - 1;
        const IntegrateOutcome r = integrate_steps(stepper, z, t0, h, k, end, observer);
        if (r.status != RunStatus::ok) return r;
        k = end;
        if (chunk < (std::int64_t{1} << 24) &&
            Clock::now() - chunk_start < std::chrono::milliseconds(2))
            chunk *= 2;
    }
    return {RunStatus::ok, n, 0};
}

// ---- memory ---------------------------------------------------------------------------------

// Half the physical memory (the default of --max-memory), in bytes.
double default_max_memory();
// Parses --max-memory: bytes with an optional suffix K, M, G, T (powers of 1024; "8G", "500M").
// Throws InputError naming --max-memory.
double parse_memory_size(const std::string& text);
std::string format_bytes(double bytes);

// What a case keeps of its output grid t0..t_end. The error diagnostic and the case's
// measures are running reductions over the grid (ErrorAccumulator, MeasureAccumulator): when
// nothing else reads the grid — no diagnostic that needs the stored grid (energy, poincare,
// temperature), no "growth" measure (a least-squares fit over all its points), no --figures
// series — the runs feed them each grid point on the fly (harness/run/grid_stream.hpp) and store no
// trajectory. The reference is then not stored either when it is the problem's exact solution and
// no diagnostic reads the reference's grid (dissipation-drift): the exact solution is evaluated at
// each output time, during each run. A certified numerical reference stays stored on the grid: it
// is one adaptive GSL integration (with its certifier) shared by every run of the case and, through
// the reference cache, by other cases, and its certified error estimate — which decides where a
// relative error is defined — is a maximum over the whole grid, known only once the whole
// reference is computed; evaluating it in chunks alongside each run would repeat it per run and
// change the metric's definition. Such a case is refused above --max-memory for its reference.
struct GridPlan {
    bool grid = false;            // the runs observe the output grid (points + 1 states)
    bool store_grid = false;      // ... and store it (else: streamed, nothing kept per point)
    bool store_reference = false; // the reference is stored on the grid (else, with a grid: the
                                  // exact solution is evaluated at each output time)
};
// points: the output grid's intervals (output_points); has_exact: the problem has an exact
// solution; figures: `dampsym run --figures` (its series read the stored grid).
GridPlan grid_plan(const CaseSpec& c, std::int64_t points, bool has_exact, bool figures);

struct MemoryEstimate {
    double bytes = 0.0;
    std::string largest; // what dominates, e.g. "output grid: 1e+07 points x 4 components x 3"
    std::string key;     // the case key to change, e.g. "output_dt"
};
// Peak memory of a case with `jobs` runs at once (a rough upper estimate, docs/case-keys.md).
// figures: with --figures (the grid is then stored: grid_plan).
MemoryEstimate estimate_case_memory(const CaseSpec& c, int jobs, bool figures = false);
// Throws InputError naming the file, the estimate and the key to change for the first case above
// max_bytes.
void check_memory(const std::vector<CaseSpec>& cases, int jobs, double max_bytes,
                  bool figures = false);

// Validates the case keys of this file (timeout_seconds: a number > 0). Throws InputError naming
// file and key. Called from parse_case (case.cpp).
void validate_limit_keys(const nlohmann::json& j, const std::string& file);

// ---- reporting ----------------------------------------------------------------------------------

// The failing check "case completed" for a case record with runs that did not finish (status
// timeout, interrupted or error) or tasks that threw (task_errors), else null. Appended to the
// case's checks by the runner, so such a case always fails (exit status 1), whatever its checks.
nlohmann::json completion_check(const nlohmann::json& case_record,
                                const std::vector<std::string>& task_errors);
// The record of a case whose preparation (reference) or assembly threw: no runs, the failing
// completion check.
nlohmann::json failed_case_record(const CaseSpec& c, const std::vector<std::string>& task_errors);

// The time budget of a case: its key timeout_seconds, else --case-timeout (0 = none).
double case_timeout(const CaseSpec& c, double cli_timeout);

} // namespace dampsym
