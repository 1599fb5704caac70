// What the runner (src/harness/run/runner.cpp) sees of a case in progress: the type-erased CaseJob,
// the shared reference cache, small helpers, and the shard factory make_case_shard<K, N>, which
// is defined in typed_case.hpp and explicitly instantiated in the generated case_shard_K.cpp
// translation units (so the heavy per-problem template code compiles there, in parallel).
#pragma once

#include "harness/case/case.hpp"
#include "harness/run/limits.hpp"
#include "harness/run/runner.hpp"
#include "reference/gsl_reference.hpp"

#include <nlohmann/json.hpp>

#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace dampsym::detail {

using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start);

json state_json(const Vec& z);

// Numerical references are computed once per problem instance (problem, parameters, initial state,
// output times, tolerances) and shared by every method, step size and case that needs them.
class ReferenceCache {
public:
    // A solution that its case's time budget stopped (reference_stopped, limits.hpp) is not kept:
    // its computing case gets it, every other caller computes the reference again under its own
    // budget (a case with a longer budget, or none, never inherits a stopped reference).
    template <class Compute>
    std::shared_ptr<const ReferenceSolution> get(const std::string& key, Compute&& compute) {
        for (;;) {
            std::shared_ptr<Entry> e;
            {
                std::lock_guard<std::mutex> lock(m_);
                auto& slot = map_[key];
                if (!slot) slot = std::make_shared<Entry>();
                e = slot;
            }
            bool mine = false;
            std::call_once(e->once, [&] {
                e->solution = std::make_shared<const ReferenceSolution>(compute());
                mine = true;
            });
            if (mine || !reference_stopped(*e->solution)) {
                if (reference_stopped(*e->solution)) forget(key, e);
                return e->solution;
            }
            forget(key, e);
        }
    }

private:
    struct Entry {
        std::once_flag once;
        std::shared_ptr<const ReferenceSolution> solution;
    };
    void forget(const std::string& key, const std::shared_ptr<Entry>& e) {
        std::lock_guard<std::mutex> lock(m_);
        auto it = map_.find(key);
        if (it != map_.end() && it->second == e) map_.erase(it);
    }
    std::mutex m_;
    std::map<std::string, std::shared_ptr<Entry>> map_;
};

ReferenceCache& reference_cache();

std::string reference_key(const CaseSpec& c, const std::vector<double>& times);

// A case in progress, type-erased at case level only (the step loops inside are not).
class CaseJob {
public:
    virtual ~CaseJob() = default;
    virtual void prepare() = 0;
    virtual void add_tasks(std::vector<std::function<void()>>& tasks) = 0;
    virtual json finish() = 0;
    // Work-precision timing of ladder runs (RunOptions::time_budget; 0 = off).
    void set_time_budget(double seconds) { time_budget_ = seconds; }
    // The case's time budget and the stop requests its runs obey (src/harness/run/limits.hpp).
    CaseGuard& guard() { return guard_; }
    // Figures hook: with --figures the runs keep time series (harness/figures/series.hpp)
    // and series() returns them after finish(); without, nothing is kept and series() is null.
    void set_figures(bool on) { figures_ = on; }
    virtual json series() { return nullptr; }

protected:
    double time_budget_ = 0.0;
    CaseGuard guard_;
    bool figures_ = false;
};

// Output grid shared by every step size of a case: a common multiple of all dt, at most ~20000
// points; the last point is t_end.
std::int64_t output_points(const CaseSpec& c);

// Whether a case's diagnostics read the trajectory on the output grid (else only the final state).
bool case_needs_grid(const CaseSpec& c, std::int64_t points);

// Times at which a case's reference is sampled: the output grid t0..t_end (points + 1 times) when
// `grid`, else t_end only.
std::vector<double> reference_times(const CaseSpec& c, std::int64_t points, bool grid);

// The certified-reference request for a case (conventions §4): y' = problem.rhs from the problem's
// initial state, sampled at `times`, with the case's stepper and tolerances. The rhs owns its
// buffers, so an evaluation allocates nothing (one integration calls it ~10⁵ times, from one
// thread; copies of the request have their own buffers).
template <class P>
ReferenceRequest reference_request(const P& problem, const CaseSpec& c, std::vector<double> times) {
    ReferenceRequest req;
    req.dim = problem.dim();
    req.t0 = c.t0;
    req.y0 = problem.initial_state();
    req.times = std::move(times);
    req.stepper = c.reference.stepper;
    req.epsrel = c.reference.epsrel;
    req.epsabs = c.reference.epsabs;
    req.rhs = [problem, z = Vec(problem.dim()), f = Vec(problem.dim())](double t, const double* y,
                                                                        double* dydt) mutable {
        z = Eigen::Map<const Vec>(y, z.size());
        problem.rhs(t, z, f);
        Eigen::Map<Vec>(dydt, f.size()) = f;
    };
    return req;
}

const json* lookup(const json& root, const std::string& dotted);

const char* op_name(CheckOp op);

template <int K, int N>
std::unique_ptr<CaseJob> make_case_shard(const CaseSpec& c);

} // namespace dampsym::detail
