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
#include "diagnostics/series.hpp"

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
    // With --figures: its series on the measured run's output grid (harness/figures/series.hpp
    // GridSeries: the problem, the case, the grid and its times, the reference on the grid).
    template <class G>
    static void grid_series(const G& g, nlohmann::json& s);
};
DAMPSYM_DIAGNOSTIC(FieldDriftDiagnostic, 180);

// From the output grid: Gamma(t) the problem's Γ, n the field size.
json field_drift_metrics(const CaseFacts& c, const Mat& grid, int n,
                         const std::function<double(double)>& Gamma);

template <class V>
json FieldDriftDiagnostic::produce(const V& run) {
    const auto& p = run.problem;
    return field_drift_metrics(run.facts, run.grid(), p.field_size(),
                               [&p](double t) { return p.Gamma(t); });
}

// d(t) = ln max_x u + Γ(t) − Γ(t0) of field_drift_metrics, B (5.6); up to the first output time
// where max_x u <= 0 (where the metric is undefined).
template <class G>
void FieldDriftDiagnostic::grid_series(const G& g, nlohmann::json& s) {
    using P = typename G::Problem;
    if constexpr (HasField<P>) {
        if (g.cols() <= 2) return;
        const int n = g.problem.field_size();
        const double gamma0 = g.problem.Gamma(g.c.t0);
        MinMaxDecimator d(g.cols() - 1);
        for (Eigen::Index i = 1; i < g.cols() && n >= 1 && n <= g.grid.rows(); ++i) {
            const double m = g.grid.col(i).head(n).maxCoeff();
            if (!(m > 0.0)) break;
            d.push(g.t(i), std::log(m) + (g.problem.Gamma(g.t(i)) - gamma0));
        }
        s[std::string(name) + ".d"] = d.to_json();
    }
}

} // namespace dampsym
