// Report-shape validation of `dampsym compare` and `dampsym merge` (compare_input.cpp): the keys
// of schema/report.schema.json that they and the renderers of a merged report read, with their
// types, and the identities that compare matches by (case id; run method and dt; check name,
// method and dt), which must be unique or a flipped duplicate would hide behind its twin.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace dampsym::compare_detail {

// Throws InputError naming `which` and the key if r is not a dampsym report compare_reports can
// read: nested deeper than 64 levels, schema_version not 1 (the clock fields inside runs) or the
// current one, tool not dampsym, a required key missing or of the wrong type, or a case id, run
// (method, dt) or check (name, method, dt) given twice.
void require_report(const nlohmann::json& r, const std::string& which);

// As require_report, but schema_version must be the current one and every key the merged report's
// summary, Markdown, JUnit and annotations read is checked (merge).
void require_current_report(const nlohmann::json& r, const std::string& which);

// "method dt=0.05": the identity of a run; "name [method, dt=0.05]": that of a check.
std::string run_key(const nlohmann::json& run);
std::string check_key(const nlohmann::json& check);

} // namespace dampsym::compare_detail
