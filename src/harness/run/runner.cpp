#include "harness/run/runner.hpp"

#include "diagnostics/cost_diagnostic.hpp"
#include "harness/case/figures_key.hpp"
#include "harness/report/report.hpp"
#include "harness/run/case_job.hpp"
#include "harness/run/progress.hpp"
#include "harness/user_methods/method_coefficients.hpp"

#include <atomic>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <utility>

#ifndef DAMPSYM_CASE_SHARDS
#error "DAMPSYM_CASE_SHARDS must be defined by the build (number of generated case shards)"
#endif

namespace dampsym {
namespace detail {

double seconds_since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

json state_json(const Vec& z) {
    json a = json::array();
    for (Eigen::Index i = 0; i < z.size(); ++i) a.push_back(z[i]); // NaN/inf are written as null
    return a;
}

ReferenceCache& reference_cache() {
    static ReferenceCache cache;
    return cache;
}

std::string reference_key(const CaseSpec& c, const std::vector<double>& times) {
    std::string key = c.problem_id;
    char buf[256];
    for (const auto& [k, v] : c.params.scalars) {
        std::snprintf(buf, sizeof buf, ";%s=%.17g", k.c_str(), v);
        key += buf;
    }
    for (const auto& [k, v] : c.params.arrays) {
        key += ";" + k + "=[";
        for (double x : v) {
            std::snprintf(buf, sizeof buf, "%.17g,", x);
            key += buf;
        }
        key += "]";
    }
    std::snprintf(buf, sizeof buf, ";%s;%.17g;%.17g;t0=%.17g;", c.reference.stepper.c_str(),
                  c.reference.epsrel, c.reference.epsabs, c.t0);
    key += buf;
    for (double t : times) {
        std::snprintf(buf, sizeof buf, "%.17g,", t);
        key += buf;
    }
    return key;
}

// From the diagnostic registry: a diagnostic that reads the grid, or "error" with a grid of more
// than one point (src/diagnostics/diagnostic.hpp DiagnosticNeeds).
bool case_needs_grid(const CaseSpec& c, std::int64_t points) {
    for (const std::string& name : c.diagnostics) {
        const DiagnosticInfo* d = find_diagnostic(name);
        if (d && (d->needs.grid || (d->needs.grid_if_points && points > 1))) return true;
    }
    return false;
}

std::vector<double> reference_times(const CaseSpec& c, std::int64_t points, bool grid) {
    if (!grid) return {c.t_end};
    std::vector<double> times(static_cast<std::size_t>(points + 1));
    for (std::int64_t i = 0; i <= points; ++i)
        times[static_cast<std::size_t>(i)] =
            c.t0 + static_cast<double>(i) * (c.t_end - c.t0) / static_cast<double>(points);
    times.back() = c.t_end;
    return times;
}

const json* lookup(const json& root, const std::string& dotted) {
    const json* node = &root;
    std::string::size_type start = 0;
    while (true) {
        const auto next = dotted.find('.', start);
        const std::string part =
            dotted.substr(start, next == std::string::npos ? std::string::npos : next - start);
        if (!node->is_object() || !node->contains(part)) return nullptr;
        node = &(*node)[part];
        if (next == std::string::npos) return node;
        start = next + 1;
    }
}

const char* op_name(CheckOp op) {
    switch (op) {
    case CheckOp::near:
        return "near";
    case CheckOp::le:
        return "le";
    case CheckOp::ge:
        return "ge";
    case CheckOp::lt:
        return "lt";
    case CheckOp::gt:
        return "gt";
    }
    return "?";
}

} // namespace detail

namespace {

using detail::Clock;
using detail::json;
using detail::seconds_since;

// Runs tasks on `jobs` threads; rethrows the first exception after all threads stop.
void run_parallel(std::vector<std::function<void()>>& tasks, int jobs) {
    std::atomic<std::size_t> next{0};
    std::exception_ptr error;
    std::mutex error_mutex;
    auto worker = [&] {
        for (std::size_t i; (i = next.fetch_add(1)) < tasks.size();) {
            try {
                tasks[i]();
            } catch (...) {
                std::lock_guard<std::mutex> lock(error_mutex);
                if (!error) error = std::current_exception();
            }
        }
    };
    const int n = std::max(1, std::min<int>(jobs, static_cast<int>(tasks.size())));
    std::vector<std::thread> threads;
    for (int i = 1; i < n; ++i) threads.emplace_back(worker);
    worker();
    for (auto& t : threads) t.join();
    if (error) std::rethrow_exception(error);
}

constexpr int kShards = DAMPSYM_CASE_SHARDS;

// The shards are compiled elsewhere (case_shard_K.cpp); here they are only called.
template <int... K>
std::unique_ptr<detail::CaseJob> make_case(const CaseSpec& c, std::integer_sequence<int, K...>) {
    std::unique_ptr<detail::CaseJob> job;
    ((job = job ? std::move(job) : detail::make_case_shard<K, kShards>(c)), ...);
    return job;
}

} // namespace

bool check_passes(const CheckSpec& cs, double value) {
    const double x = cs.use_abs ? std::abs(value) : value;
    switch (cs.op) {
    case CheckOp::near:
        return std::abs(x - cs.value) <= cs.tol;
    case CheckOp::le:
        return x <= cs.value;
    case CheckOp::ge:
        return x >= cs.value;
    case CheckOp::lt:
        return x < cs.value;
    case CheckOp::gt:
        return x > cs.value;
    }
    return false;
}

json run_cases(const std::vector<CaseSpec>& cases, const RunOptions& options) {
    return run_cases(cases, options, ProgressCallback{});
}

namespace {

// Moves every clock-dependent value of the case records into the report's "timings" section
// (one entry per case, in case order, one per run, in run order): runs[].wall_seconds,
// runs[].timing (work-precision repetitions) and metrics.cost.wall_seconds (the same number as
// the run's wall_seconds). What remains in "cases" is identical between runs of the same build.
json take_timings(json& out_cases) {
    json cases = json::array();
    for (auto& c : out_cases) {
        json runs = json::array();
        double sum = 0.0;
        for (auto& r : c["runs"]) {
            json t = {{"method", r["method"]}, {"dt", r["dt"]}};
            if (r.contains("wall_seconds")) {
                sum += r["wall_seconds"].get<double>();
                t["wall_seconds"] = std::move(r["wall_seconds"]);
                r.erase("wall_seconds");
            }
            if (r.contains("timing")) {
                t["timing"] = std::move(r["timing"]);
                r.erase("timing");
            }
            const std::string cost(CostDiagnostic::name);
            if (r.contains("metrics") && r["metrics"].contains(cost))
                r["metrics"][cost].erase("wall_seconds");
            runs.push_back(std::move(t));
        }
        cases.push_back({{"id", c["id"]}, {"runs_wall_seconds", sum}, {"runs", std::move(runs)}});
    }
    return cases;
}

// The report of the finished cases: their records, the summary and the clock-dependent timings
// (moved out of the records, docs/reports.md).
json assemble_report(json out_cases, const RunOptions& options, double wall_seconds) {
    json timings_cases = take_timings(out_cases);
    mark_refuted_methods(out_cases);
    json summary = summarize(out_cases);
    return {{"schema_version", kReportSchemaVersion},
            {"tool", {{"name", "dampsym"}, {"version", DAMPSYM_VERSION}}},
            {"cases", std::move(out_cases)},
            {"summary", std::move(summary)},
            {"timings",
             {{"wall_seconds", wall_seconds},
              {"time_budget_seconds", options.time_budget},
              {"protocol", "runs: wall time of the measured run (with its observers); timing: "
                           "one warm-up of the bare step loop, then the minimum of N "
                           "repetitions, N chosen so they total >= the budget (ladder cases "
                           "only; failed runs are not timed)"},
              {"cases", std::move(timings_cases)}}}};
}

} // namespace

namespace {

// One run of a selection: the cases' jobs, their tasks on --jobs threads, and the records.
// an exception in one task is recorded for its case (which then fails its completion
// check, limits.hpp) and the other tasks and cases go on. A case's record is made as soon as its
// last task ends (in that worker thread), so that its line can be printed while other cases run;
// from its own results only, so it is the same for any --jobs.
class SelectionRun {
public:
    SelectionRun(const std::vector<CaseSpec>& cases, const RunOptions& options,
                 const ProgressCallback& progress)
        : cases_(cases), options_(options), progress_(progress), task_errors_(cases.size()),
          prepared_(cases.size(), 1), records_(cases.size()), remaining_(cases.size(), 1) {
        for (const CaseSpec& c : cases) {
            auto job = make_case(c, std::make_integer_sequence<int, kShards>{});
            job->set_time_budget(options.time_budget);
            job->guard().set_timeout(case_timeout(c, options.case_timeout)); // limits.hpp
            // figures hook: a case with "figures": false keeps no series (case/figures_key.hpp)
            job->set_figures(static_cast<bool>(options.series_sink) && !case_figures_off(c));
            jobs_.push_back(std::move(job));
        }
        state_.cases_total = state_.tasks_total = cases.size();
    }

    json run() {
        std::vector<std::function<void()>> tasks;
        for (std::size_t i = 0; i < jobs_.size(); ++i)
            tasks.emplace_back([this, i] {
                // the case's reference counts in its time budget; the clock is paused while
                // the case waits for its runs' turn (limits.hpp)
                jobs_[i]->guard().start();
                if (!isolated(i, [&] { jobs_[i]->prepare(); })) prepared_[i] = 0;
                jobs_[i]->guard().pause();
                task_done(i);
            });
        run_parallel(tasks, options_.jobs);
        std::vector<std::size_t> without_tasks; // failed to prepare, or nothing to run
        std::vector<std::function<void()>> planned = plan(without_tasks);
        for (const std::size_t i : without_tasks) finish_case(i);
        run_parallel(planned, options_.jobs);
        json out_cases = json::array();
        for (auto& record : records_) out_cases.push_back(std::move(record));
        return out_cases;
    }

private:
    bool isolated(std::size_t i, const std::function<void()>& f) {
        try {
            f();
            return true;
        } catch (const std::exception& e) {
            std::lock_guard<std::mutex> lock(errors_mutex_);
            task_errors_[i].emplace_back(e.what());
        } catch (...) {
            std::lock_guard<std::mutex> lock(errors_mutex_);
            task_errors_[i].emplace_back("non-standard exception");
        }
        return false;
    }

    // The runs' tasks of every prepared case; the cases without any in `without_tasks`.
    std::vector<std::function<void()>> plan(std::vector<std::size_t>& without_tasks) {
        std::vector<std::function<void()>> planned;
        std::lock_guard<std::mutex> lock(progress_mutex_);
        for (std::size_t i = 0; i < jobs_.size(); ++i) {
            std::vector<std::function<void()>> mine;
            if (prepared_[i]) jobs_[i]->add_tasks(mine);
            remaining_[i] = mine.size();
            if (mine.empty()) without_tasks.push_back(i);
            for (auto& t : mine)
                planned.emplace_back([this, i, task = std::move(t)] {
                    isolated(i, task);
                    task_done(i);
                });
        }
        state_.tasks_total += planned.size();
        state_.planned = true;
        return planned;
    }

    // Progress: every task is attributed to its case; a case is done when its last task is.
    void task_done(std::size_t i) {
        bool last = false;
        {
            std::lock_guard<std::mutex> lock(progress_mutex_);
            ++state_.tasks_done;
            last = --remaining_[i] == 0 && state_.planned;
            state_.current = cases_[i].id;
            if (progress_) progress_(state_);
        }
        if (last) finish_case(i);
    }

    // The case's record (runs stopped by a timeout or a signal and failed tasks fail the case,
    // limits.hpp), then the progress call that announces it.
    void finish_case(std::size_t i) {
        json record;
        const bool finished = prepared_[i] && isolated(i, [&] { record = jobs_[i]->finish(); });
        // figures hook: the case's series file, written by the thread that finished the case
        // while the other cases run (the sink is thread-safe; an output error is recorded by it,
        // any other failure is the case's error)
        if (prepared_[i] && options_.series_sink)
            isolated(i, [&] { options_.series_sink(jobs_[i]->series()); });
        if (finished) {
            json done = completion_check(record, task_errors_[i]);
            if (!task_errors_[i].empty()) record["errors"] = task_errors_[i];
            if (!done.is_null()) record["checks"].push_back(std::move(done));
        } else {
            record = failed_case_record(cases_[i], task_errors_[i]);
        }
        records_[i] = std::move(record);
        std::lock_guard<std::mutex> lock(progress_mutex_);
        ++state_.cases_done;
        state_.current = cases_[i].id;
        state_.finished = &records_[i];
        state_.finished_index = i;
        if (progress_) progress_(state_);
        state_.finished = nullptr;
    }

    const std::vector<CaseSpec>& cases_;
    const RunOptions& options_;
    const ProgressCallback& progress_;
    std::vector<std::unique_ptr<detail::CaseJob>> jobs_;
    std::vector<std::vector<std::string>> task_errors_;
    std::vector<char> prepared_;
    std::vector<json> records_;
    std::vector<std::size_t> remaining_;
    std::mutex errors_mutex_, progress_mutex_;
    RunProgress state_;
};

} // namespace

json run_cases(const std::vector<CaseSpec>& cases, const RunOptions& options,
               const ProgressCallback& progress) {
    const auto start = Clock::now();
    json out_cases = SelectionRun(cases, options, progress).run();
    return assemble_report(std::move(out_cases), options, seconds_since(start));
}

} // namespace dampsym
