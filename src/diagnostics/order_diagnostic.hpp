// Diagnostics "order" and "local-order" (method level): the observed order, the log-log slope of
// the global error at t_end ("error.final_abs") or of the one-step error ("local-error.abs", B Fig
// 3.2) against dt over the ladder, fitted where the errors are above the round-off floor and 100x
// the reference's error estimate (docs/conventions.md §4; diagnostics/order_fit.hpp).
#pragma once

#include "core/problem_concepts.hpp"
#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"
#include "diagnostics/order_fit.hpp"

#include <limits>
#include <string_view>
#include <vector>

namespace dampsym {

struct OrderDiagnostic {
    static constexpr std::string_view name = "order";
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = true;
};
DAMPSYM_DIAGNOSTIC(OrderDiagnostic, 20);

struct LocalOrderDiagnostic {
    static constexpr std::string_view name = "local-order";
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = HasExactSolution<P>;
};
DAMPSYM_DIAGNOSTIC(LocalOrderDiagnostic, 160);

// The fit of (dt, error) points of one method: errors below `floor` are dropped; `ref_error` is
// the reference's estimate (0 for local errors), `roundoff` the round-off floor, for the report;
// errors not small against `solution_scale` (the solution's size) are dropped too (order_fit.hpp).
json order_fit_json(const std::vector<OrderPoint>& points, double roundoff, double ref_error,
                    double solution_scale = std::numeric_limits<double>::infinity());

} // namespace dampsym
