// Runs validated cases and assembles report JSON (conventions §7). Work is split into independent
// tasks (one per method × step size, one per method-level sweep) run on --jobs threads; results are
// stored by index and assembled in a fixed order, so the numbers do not depend on --jobs.
#pragma once

#include "harness/case/case.hpp"

#include <nlohmann/json.hpp>

#include <functional>
#include <vector>

namespace dampsym {

struct RunOptions {
    int jobs = 1;
    // Work-precision timing protocol for every case with a step ladder (>= 2 step sizes): after
    // the measured run, one warm-up of the bare step loop, then the minimum of N repetitions with
    // N chosen so that the repetitions take >= time_budget seconds in total. 0 switches it off.
    double time_budget = 0.02;
    // Time budget of each case in seconds (--case-timeout; a case's timeout_seconds wins; 0 =
    // none): src/harness/run/limits.hpp.
    double case_timeout = 0.0;
    // Figures hook: when set (dampsym run --figures), every case keeps the time series
    // of its figures and the sink receives each case's series (docs/reports.md "Series files")
    // as soon as the case has finished, on the thread that finished it (so concurrently with
    // other cases': the sink must be thread-safe); when empty, nothing is kept.
    std::function<void(const nlohmann::json& case_series)> series_sink;
};

// Returns the report: {"schema_version", "tool", "cases": [...], "summary": {...}}.
nlohmann::json run_cases(const std::vector<CaseSpec>& cases, const RunOptions& options);

// Evaluates one check against a metric value (exposed for tests).
bool check_passes(const CheckSpec& check, double value);

} // namespace dampsym
