// Diagnostic "dissipation-drift": d(t) = ln(max q) + Γ(t) at the oscillation maxima of q (F(4.4));
// with a reference on the output grid also d(t) of the reference and the differences. The per-step
// hook is the Recorder's "maxima" part (a MaximaFinder, diagnostics/maxima.hpp).
#pragma once

#include "diagnostics/capabilities.hpp"
#include "diagnostics/diagnostic.hpp"
#include "diagnostics/maxima.hpp"
#include "diagnostics/metric_json.hpp"

#include <optional>
#include <vector>

namespace dampsym {

struct DissipationDriftDiagnostic {
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = HasOneDofMaxima<P>;
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

} // namespace dampsym
