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
// a check on it fails with that reason (harness/checks.cpp).
inline void set_undefined(json& o, const std::string& key, const std::string& reason) {
    o[key] = nullptr;
    o["undefined"][key] = reason;
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
