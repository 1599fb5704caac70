// The Markdown tables of report.md (report/tables.cpp), used by render_markdown (report.cpp).
#pragma once

#include <nlohmann/json.hpp>

#include <sstream>
#include <string>

namespace dampsym::report_detail {

using json = nlohmann::json;

std::string num(const json& v, int digits = 4);
bool case_passed(const json& c);
// What a check expects: "≤ 1e-12", "2 ± 0.05", "|x| ≤ 0.3".
std::string expected_text(const json& ck);
std::string check_line(const json& ck, const char* result = nullptr);
void measures_table(std::ostringstream& os, const json& c);
// diag: "order" (global error at t_end) or "local-order" (one-step error, slope p + 1).
void order_table(std::ostringstream& os, const json& c, std::string_view diag);
void sweep_table(std::ostringstream& os, const json& c);
void work_precision_table(std::ostringstream& os, const json& c, const json* t);
void runs_table(std::ostringstream& os, const json& c, const json* t);
void metrics_table(std::ostringstream& os, const json& c);

} // namespace dampsym::report_detail
