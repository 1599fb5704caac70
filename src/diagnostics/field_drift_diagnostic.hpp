// Diagnostic "field-drift": the dissipation drift of a damped wave field, B (5.6),
//   d(t) = ln max_x u(x, t) + Γ(t) − Γ(t0),
// on the output grid, for a PDE problem whose state begins with the field u on the grid (the
// problem's field_size(): B's damped Klein–Gordon, u = q). For B (5.1)'s plane wave u =
// e^{−Γ(t)} cos(Kx − Wt) the exact d(t) is 0 up to the grid's sampling of the crest (between
// ln cos(KΔx/2) and 0); a scheme that dissipates at the wrong rate makes d(t) drift (B Fig 5.2:
// "no drift in the rate of dissipation (5.6)"). docs/conventions.md §5 "field-drift".
#pragma once

#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"

#include <functional>
#include <string_view>

namespace dampsym {

// A problem whose state starts with a field sampled on a grid: field_size() values.
template <class P>
concept HasField = requires(const P& p) {
    { p.field_size() } -> std::convertible_to<int>;
};

struct FieldDriftDiagnostic {
    static constexpr std::string_view name = "field-drift";
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = HasField<P>;
    // Its metrics of one run from the run's view (harness/run/view.hpp: the problem, the case's
    // facts, the recorder and grid, the method, h, the final state, the counters).
    template <class V>
    static json produce(const V& run);
};

// From the output grid: Gamma(t) the problem's Γ, n the field size.
json field_drift_metrics(const CaseFacts& c, const Mat& grid, int n,
                         const std::function<double(double)>& Gamma);

template <class V>
json FieldDriftDiagnostic::produce(const V& run) {
    const auto& p = run.problem;
    return field_drift_metrics(run.facts, run.grid(), p.field_size(),
                               [&p](double t) { return p.Gamma(t); });
}

} // namespace dampsym
