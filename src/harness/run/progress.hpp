// Progress of run_cases for the command line's progress line (src/cli/cli.cpp). Declared apart
// from runner.hpp, which every generated case shard includes.
#pragma once

#include "harness/run/runner.hpp"

#include <cstddef>
#include <functional>
#include <string>

namespace dampsym {

struct RunProgress {
    std::size_t cases_done = 0, cases_total = 0;
    std::size_t tasks_done = 0, tasks_total = 0; // tasks_total grows once the runs are planned
    std::string current;                         // id of the case whose task ran last
    bool planned = false; // false while references are prepared (before the runs are known)
    // Set for the one call that follows the end of a case: its record (runs, checks; its clock
    // values not yet moved to the report's timings) and its index in the selection; null in the
    // calls after a task.
    const nlohmann::json* finished = nullptr;
    std::size_t finished_index = 0;
};

// Called from the worker threads, one call at a time, after every task and after every case.
using ProgressCallback = std::function<void(const RunProgress&)>;

nlohmann::json run_cases(const std::vector<CaseSpec>& cases, const RunOptions& options,
                         const ProgressCallback& progress);

} // namespace dampsym
