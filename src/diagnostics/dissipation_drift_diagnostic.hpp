// Diagnostic "dissipation-drift": d(t) = ln(max q) + Γ(t) at the oscillation maxima of q (F(4.4));
// with a reference on the output grid also d(t) of the reference and the differences. The per-step
// hook is the Recorder's "maxima" part (a MaximaFinder, diagnostics/maxima.hpp).
#pragma once

#include "diagnostics/capabilities.hpp"
#include "diagnostics/diagnostic.hpp"
#include "diagnostics/maxima.hpp"
#include "diagnostics/metric_json.hpp"

#include <optional>
#include <string_view>
#include <vector>

namespace dampsym {

struct DissipationDriftDiagnostic {
    static constexpr std::string_view name = "dissipation-drift";
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = HasOneDofMaxima<P>;
    // Its metrics of one run from the run's view (harness/run/view.hpp: the problem, the case's
    // facts, the recorder and grid, the method, h, the final state, the counters).
    template <class V>
    static json produce(const V& run);
};

struct MaximaSeries {
    std::vector<Maximum> maxima;
    std::int64_t nonpositive = 0; // maxima of q at or below 0 (no d(t) there)
};

// ref: the maxima of the reference on the output grid, when there is one.
json drift_metrics(const MaximaSeries& run, const std::optional<MaximaSeries>& ref);

// Typed hook: the maxima of the reference samples (the same locator as the run's).
template <class P>
std::optional<MaximaSeries> reference_maxima(const P& problem, const CaseFacts& c) {
    if constexpr (HasOneDofMaxima<P>) {
        if (c.reference_ok && c.ref.cols() > 2 && c.ref.cols() == c.points + 1) {
            MaximaFinder<P> finder(problem, c.t0);
            for (Eigen::Index i = 0; i < c.ref.cols(); ++i)
                finder.feed(c.grid_time(i), c.ref.col(i));
            return MaximaSeries{finder.maxima(), finder.nonpositive()};
        }
    }
    return std::nullopt;
}

template <class V>
json DissipationDriftDiagnostic::produce(const V& run) {
    return drift_metrics({run.rec.maxima(), run.rec.nonpositive_maxima()},
                         reference_maxima(run.problem, run.facts));
}

} // namespace dampsym
