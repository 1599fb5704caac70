#include "diagnostics/order_diagnostic.hpp"

#include <algorithm>
#include <cmath>

namespace dampsym {

DiagnosticInfo OrderDiagnostic::info() {
    return {.name = std::string(name),
            .level = DiagnosticLevel::method,
            .what = "observed order: log-log slope of error.final_abs against dt",
            .needs = {.min_dts = 3},
            .metrics = {"slope", "r2", "points"},
            .implies = {"error"},
            .reads_reference = true};
}

DiagnosticInfo LocalOrderDiagnostic::info() {
    return {.name = std::string(name),
            .level = DiagnosticLevel::method,
            .what = "observed local order: log-log slope of local-error.abs against dt",
            .requirement = "an exact solution",
            .needs = {.min_dts = 3},
            .metrics = {"slope", "r2", "points"},
            .implies = {"local-error"}};
}

json order_fit_json(const std::vector<OrderPoint>& pts, double roundoff, double ref_error,
                    double solution_scale) {
    const double floor = std::max(roundoff, 100.0 * ref_error);
    const OrderFit fit = fit_order(pts, floor, solution_scale);
    json o = {{"ok", fit.ok},
              {"status", fit.status},
              {"window_dt", fit.window_h},
              {"local_orders", fit.local_orders},
              {"floor", floor},
              {"floor_source",
               100.0 * ref_error > roundoff ? "100x reference error estimate" : "round-off"}};
    if (!fit.local_orders.empty()) o["finest_local_order"] = fit.local_orders.back();
    if (fit.ok) {
        o["slope"] = fit.slope;
        o["r2"] = fit.r2;
        o["points"] = fit.window_h.size();
    } else {
        o["reason"] = fit.reason;
    }
    if (std::isfinite(solution_scale)) o["solution_scale"] = solution_scale;
    json dropped = json::array();
    for (const auto& dp : fit.dropped)
        dropped.push_back({{"dt", dp.h}, {"error", dp.error}, {"reason", dp.reason}});
    o["dropped"] = dropped;
    return o;
}

} // namespace dampsym
