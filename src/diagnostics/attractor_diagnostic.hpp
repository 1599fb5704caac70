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
};

json attractor_metrics(const CaseFacts& c, const Mat& grid, std::string_view probe_name,
                       const std::function<double(const Vec&)>& probe);

template <class V>
json AttractorDiagnostic::produce(const V& run) {
    using P = typename V::Problem;
    const auto& p = run.problem;
    return attractor_metrics(run.facts, run.grid(), P::probe_name,
                             [&p](const Vec& v) { return p.probe(v); });
}

} // namespace dampsym
