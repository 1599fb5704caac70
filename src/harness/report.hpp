// Report writers: DIR/report.json (SPEC §7, full precision) and DIR/report.md (for people: one
// table per case, failing cases and failing checks first). Files are written to a temporary name
// and renamed, so a report is never half-written.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace dampsym {

std::string render_markdown(const nlohmann::json& report);
std::string render_summary(const nlohmann::json& report); // the one-screen terminal summary
void write_reports(const nlohmann::json& report, const std::string& dir);

// Writes `text` to `path` atomically (temporary file + rename).
void write_file_atomic(const std::string& path, const std::string& text);

} // namespace dampsym
