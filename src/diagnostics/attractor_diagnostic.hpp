// Diagnostic "attractor": statistics of a scalar probe s(t) of the state over the second half of
// the run (t ≥ t0 + (t_end − t0)/2, the first half being left to the transient), on the output
// grid, for comparing the attractors that different methods settle on without comparing their
// trajectories (B Fig 5.10: "all the numerical methods are in agreement as they settle down to
// the same attractor"; on a chaotic attractor trajectories separate, distributions do not).
// The problem declares the probe: probe(z) and probe_name (nls-driven: |ψ(0, t)|, B's amplitude).
// Metrics (docs/conventions.md §5 "attractor"): mean, std, min, max, q10, q50, q90 of s; mean_se,
// the batch-means standard error of the mean (10 consecutive batches) and mean_rse = mean_se /
// |mean|, which size the tolerance of a comparison between methods; the upward crossings of the
// mean level (linear interpolation), their mean interval `period` and its relative spread
// `period_spread` = (max − min) / mean of the intervals: ~0 on a periodic attractor (the output
// grid's interpolation error), O(1) on a chaotic one.
#pragma once

#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"
#include "diagnostics/series.hpp"

#include <array>
#include <functional>
#include <string_view>

namespace dampsym {

template <class P>
concept HasProbe = requires(const P& p, const Vec& z) {
    { p.probe(z) } -> std::convertible_to<double>;
    { P::probe_name } -> std::convertible_to<std::string_view>;
};

// Optionally, the probe as a point of a plane (the driven NLS: (Re, Im) ψ(0, t)), which the
// `portrait` figure draws (B Fig 5.10's right panels); not a metric.
template <class P>
concept HasProbePlane = HasProbe<P> && requires(const P& p, const Vec& z) {
    { p.probe_plane(z) } -> std::convertible_to<std::array<double, 2>>;
    P::probe_plane_names;
};

struct AttractorDiagnostic {
    static constexpr std::string_view name = "attractor";
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = HasProbe<P>;
    // Its metrics of one run from the run's view (harness/run/view.hpp: the problem, the case's
    // facts, the recorder and grid, the method, h, the final state, the counters).
    template <class V>
    static json produce(const V& run);
    // With --figures: its series on the measured run's output grid (harness/figures/series.hpp
    // GridSeries: the problem, the case, the grid and its times, the reference on the grid).
    template <class G>
    static void grid_series(const G& g, nlohmann::json& s);
};
DAMPSYM_DIAGNOSTIC(AttractorDiagnostic, 200);

json attractor_metrics(const CaseFacts& c, const Mat& grid, std::string_view probe_name,
                       const std::function<double(const Vec&)>& probe);

template <class V>
json AttractorDiagnostic::produce(const V& run) {
    using P = typename V::Problem;
    const auto& p = run.problem;
    return attractor_metrics(run.facts, run.grid(), P::probe_name,
                             [&p](const Vec& v) { return p.probe(v); });
}

// B Fig 5.10: the attractor diagnostic's probe on the output grid (the whole run: the transient
// too; the statistics are of its second half), and the probe as a point of its plane at (at most
// kPortraitPoints) output times.
template <class G>
void AttractorDiagnostic::grid_series(const G& g, nlohmann::json& s) {
    using P = typename G::Problem;
    using json = nlohmann::json;
    const std::string key(name);
    if constexpr (HasProbe<P>) {
        MinMaxDecimator d(g.cols() - 1);
        for (Eigen::Index i = 1; i < g.cols(); ++i) d.push(g.t(i), g.problem.probe(g.grid.col(i)));
        json j = d.to_json();
        j["probe"] = std::string(P::probe_name);
        s[key + ".probe"] = j;
    }
    if constexpr (HasProbePlane<P>) {
        StrideSampler pick(g.cols() - 1, kPortraitPoints);
        json t = json::array(), pts = json::array();
        for (Eigen::Index i = 1; i < g.cols(); ++i) {
            if (!pick.wants(i - 1)) continue;
            const auto xy = g.problem.probe_plane(g.grid.col(i));
            t.push_back(g.t(i));
            pts.push_back({drawn_value(xy[0]), drawn_value(xy[1])});
        }
        s[key + ".plane"] = {
            {"t", t},
            {"points", pts},
            {"names", {std::string(P::probe_plane_names[0]), std::string(P::probe_plane_names[1])}},
            {"stride", pick.stride()}};
    }
}

} // namespace dampsym
