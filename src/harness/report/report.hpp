// Report writers: DIR/report.json (schema/report.schema.json, full precision) and DIR/report.md
// (for people: provenance, then one table per case, failing cases and failing checks first).
// Files are written to a temporary name (FILE.dampsym-tmp) and renamed, so a report is never
// half-written; only a regular file (or nothing) is replaced: a symbolic link, device or directory
// in its place is an error (OutputError, exit 3) naming it.
//
// report.json is written with its byte-stable part first (schema_version, tool, summary, cases:
// identical between runs of the same build and selection) and the two parts that are not after it
// (provenance: build, host, start time, command line; timings: every clock-dependent value).
#pragma once

#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

namespace dampsym {

// The shape of report.json (schema/report.schema.json). 2: clock values moved to "timings",
// "provenance" added, summary.jobs/timing/wall_seconds moved out of "summary".
constexpr int kReportSchemaVersion = 2;

// An output that cannot be written (exit status 3).
struct OutputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// The summary of a list of case records: cases, failed_cases, runs, checks_passed, checks_failed.
nlohmann::json summarize(const nlohmann::json& cases);

// report.json's text: the byte-stable sections first, then provenance and timings.
std::string report_json_text(const nlohmann::json& report);

std::string render_markdown(const nlohmann::json& report);
// The same with the figures of figures/manifest.json ({"cases": {id: [{"file", "caption"}]}},
// tools/figures/plot.py) embedded in each case's section.
std::string render_markdown(const nlohmann::json& report, const nlohmann::json& figures);
std::string render_summary(const nlohmann::json& report); // the one-screen terminal summary
// One case's line of that summary: "ok   ID   12 checks  0.31 s", or "FAIL ID  24 of 38 checks
// failed: " and the first three failing checks with method and dt, "(+21 more)"; `seconds` (the
// runs' wall time) is left out when null.
std::string render_case_line(const nlohmann::json& case_record, const nlohmann::json& seconds);
// Every failing check on its own line ("FAILED ID: name [method, dt=h]: metric = value, expected
// ..."), at most `limit`, then how many more.
std::string render_failed_checks(const nlohmann::json& report, std::size_t limit);
std::string render_totals(const nlohmann::json& report); // its last line
void write_reports(const nlohmann::json& report, const std::string& dir);

// The timings entry of run `run_index` of case `case_index` (null if the report has none).
const nlohmann::json* run_timing(const nlohmann::json& report, std::size_t case_index,
                                 std::size_t run_index);

// Checks, before any work, that DIR can hold report.json and report.md: creates DIR if needed,
// then creates and removes a probe file in it. Throws OutputError naming DIR and the reason.
void check_output_dir(const std::string& dir);
// The same for a single output file (e.g. --junit FILE): its directory must be writable and FILE
// must be absent or a regular file (check_replaceable).
void check_output_file(const std::string& file);

// The suffix of the temporary file that write_file_atomic renames over its target.
inline constexpr const char* kTemporarySuffix = ".dampsym-tmp";

// Throws OutputError naming `path` unless it is absent or a regular file (lstat: a symbolic link
// counts as a link, whatever it points to).
void check_replaceable(const std::string& path);

// Writes `text` to `path` atomically: to path + kTemporarySuffix (created afresh, never through a
// symbolic link), then renamed over `path`. Only a regular file or nothing is replaced
// (check_replaceable). Throws OutputError.
void write_file_atomic(const std::string& path, const std::string& text);

} // namespace dampsym
