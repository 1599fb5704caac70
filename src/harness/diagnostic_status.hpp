// A diagnostic's own verdict on its metrics (checks.cpp): the conformal-symplectic pass reports
// "status": "jacobian-mismatch" when its step Jacobian is not the step's derivative
// (diagnostics/conformal_symplectic.hpp): its E_n then verifies nothing, and every check on its
// metrics fails with the pass's message.
#pragma once

#include "diagnostics/metric_json.hpp"

#include <string>

namespace dampsym::detail {

// The reason every check on metrics[diag] fails, or "" when there is none.
inline std::string diagnostic_status_failure(const json& metrics, const std::string& diag) {
    if (!metrics.is_object() || !metrics.contains(diag) || !metrics[diag].is_object()) return {};
    const json& d = metrics[diag];
    const json* status = d.contains("status") ? &d["status"] : nullptr;
    if (!status || !status->is_string() || *status != "jacobian-mismatch") return {};
    return "jacobian-mismatch: " + (d.contains("message") && d["message"].is_string()
                                        ? d["message"].get<std::string>()
                                        : std::string());
}

} // namespace dampsym::detail
