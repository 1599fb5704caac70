// What the compiled-once metric producers (src/diagnostics/*_diagnostic.cpp) read of a case in
// progress, and the JSON conventions they share. Nothing here depends on the problem type.
#pragma once

#include "core/types.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <limits>
#include <string>

namespace dampsym {

using json = nlohmann::json;

// Law residuals and relative metrics are defined only on a scale that is a positive normal number
// (docs/conventions.md, "Law residuals and their scales").
inline bool scale_defined(double s) {
    return s >= std::numeric_limits<double>::min();
}

// A metric with no defined value here: null, and its reason under "undefined" in the same object;
// a check on it fails with that reason (harness/run/checks.cpp).
inline void set_undefined(json& o, const std::string& key, const std::string& reason) {
    o[key] = nullptr;
    o["undefined"][key] = reason;
}

// No verdict without a measurement: why diagnostic `diag`'s own measurement in `metrics` did not
// complete, or "" when it did. A diagnostic that measures in a pass of its own reports the pass's
// "status" (conformal-symplectic: "diverged", "solve-failed" at "failed_at_step"; an order fit:
// "order drops at small h", ...) and how much it measured ("steps_measured"); a check on any
// metric of a pass that is not "ok", or that measured nothing, fails with this reason, whatever
// the check's direction (a negative control too: a measurement that did not happen shows no
// defect either) — harness/run/checks.cpp, and the matrix's cells alike.
inline std::string incomplete_measurement(const json& metrics, const std::string& diag) {
    if (!metrics.is_object() || !metrics.contains(diag) || !metrics[diag].is_object()) return {};
    const json& d = metrics[diag];
    if (d.contains("status") && d["status"].is_string() && d["status"] != "ok") {
        std::string why = diag + ": " + d["status"].get<std::string>();
        if (d.contains("failed_at_step") && d["failed_at_step"].is_number_integer())
            why += " at step " + std::to_string(d["failed_at_step"].get<std::int64_t>());
        if (d.contains("message") && d["message"].is_string())
            why += ": " + d["message"].get<std::string>();
        else if (d.contains("reason") && d["reason"].is_string())
            why += ": " + d["reason"].get<std::string>();
        return why;
    }
    if (d.contains("steps_measured") && d["steps_measured"].is_number() &&
        d["steps_measured"].get<double>() <= 0.0)
        return diag + ": measured no step";
    return {};
}

// The case facts of a run: its time span, output grid and reference.
struct CaseFacts {
    double t0 = 0.0, t_end = 0.0;
    std::int64_t points = 1;  // output grid t0..t_end has points + 1 times
    bool needs_grid = false;  // whether the runs record the states on it
    Mat ref;                  // reference states (one column per reference time)
    double ref_error = 0.0;   // the reference's certified error estimate (0 for exact ones)
    bool reference_ok = true; // false when the certified reference failed

    double grid_time(Eigen::Index i) const {
        if (i == points) return t_end;
        return t0 + static_cast<double>(i) * (t_end - t0) / static_cast<double>(points);
    }
};

} // namespace dampsym
