// `dampsym compare BASE NEW`: did a change alter any number? Lists, per case and run, every final
// state, metric, run field and order fit that moved beyond |a − b| <= atol + rtol·max(|a|, |b|)
// (defaults 0: bitwise), every check whose verdict flipped, and cases, runs and checks added or
// removed. Clock-dependent values (the timings section, and wall_seconds/timing inside the runs of
// schema_version 1 reports) never count as a change; unless ignore_timings, the wall times are
// listed for information.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace dampsym {

struct CompareOptions {
    double rtol = 0.0;
    double atol = 0.0;
    bool ignore_timings = false;
};

// Throws InputError if a document is not a dampsym report. Result: {"equal", "rows": [...],
// "counts": {...}, "rtol", "atol", "base", "new", "timings"?}.
nlohmann::json compare_reports(const nlohmann::json& base, const nlohmann::json& next,
                               const CompareOptions& options);

std::string render_compare_markdown(const nlohmann::json& result);

} // namespace dampsym
