// Report-shape validation of `dampsym compare` (compare_input.cpp; issue 17).
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace dampsym::compare_detail {

// Throws InputError naming `which` and the key if r is not a dampsym report compare_reports can
// read (nested deeper than 64 levels, cases/runs/checks missing or of the wrong type, ...).
void require_report(const nlohmann::json& r, const std::string& which);

} // namespace dampsym::compare_detail
