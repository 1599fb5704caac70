#include "harness/runner.hpp"

#include "harness/case_job.hpp"

#include <atomic>
#include <exception>
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

// Output grid shared by every step size of a case: a common multiple of all dt, at most ~20000
// points; the last point is t_end.
std::int64_t output_points(const CaseSpec& c) {
    const double span = c.t_end - c.t0;
    if (c.output_dt) return std::llround(span / *c.output_dt);
    std::size_t coarse = 0;
    for (std::size_t i = 1; i < c.dts.size(); ++i)
        if (c.dts[i] > c.dts[coarse]) coarse = i;
    for (double dt : c.dts) {
        const double r = c.dts[coarse] / dt;
        if (std::abs(r - std::round(r)) > 1e-9 * r) return 1; // no common grid: final time only
    }
    const std::int64_t n = c.steps[coarse];
    for (std::int64_t k = 1; k <= n; ++k)
        if (n % k == 0 && n / k <= 20000) return n / k;
    return 1;
}

bool case_needs_grid(const CaseSpec& c, std::int64_t points) {
    return c.wants("energy") || c.wants("poincare") || c.wants("temperature") ||
           (c.wants("error") && points > 1);
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
    const auto start = Clock::now();
    std::vector<std::unique_ptr<detail::CaseJob>> jobs;
    for (const CaseSpec& c : cases) {
        std::unique_ptr<detail::CaseJob> job;
        job = make_case(c, std::make_integer_sequence<int, kShards>{});
        job->set_time_budget(options.time_budget);
        jobs.push_back(std::move(job));
    }
    std::vector<std::function<void()>> tasks;
    for (auto& j : jobs) tasks.emplace_back([&j] { j->prepare(); });
    run_parallel(tasks, options.jobs);
    tasks.clear();
    for (auto& j : jobs) j->add_tasks(tasks);
    run_parallel(tasks, options.jobs);

    json out_cases = json::array();
    std::int64_t passed = 0, failed = 0, runs = 0, failed_cases = 0;
    for (auto& j : jobs) {
        json c = j->finish();
        bool case_ok = true;
        for (const auto& ck : c["checks"]) {
            if (ck["passed"].get<bool>()) {
                ++passed;
            } else {
                ++failed;
                case_ok = false;
            }
        }
        if (!case_ok) ++failed_cases;
        runs += static_cast<std::int64_t>(c["runs"].size());
        out_cases.push_back(std::move(c));
    }
    return {{"schema_version", 1},
            {"tool", {{"name", "dampsym"}, {"version", DAMPSYM_VERSION}}},
            {"cases", out_cases},
            {"summary",
             {{"cases", cases.size()},
              {"failed_cases", failed_cases},
              {"runs", runs},
              {"checks_passed", passed},
              {"checks_failed", failed},
              {"jobs", options.jobs},
              {"timing",
               {{"time_budget_seconds", options.time_budget},
                {"protocol", "one warm-up of the bare step loop, then the minimum of N "
                             "repetitions, N chosen so they total >= the budget; "
                             "failed runs are not timed"}}},
              {"wall_seconds", seconds_since(start)}}}};
}

} // namespace dampsym
