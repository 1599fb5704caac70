// Diagnostic "dissipation-drift": d(t) = ln(max q) + Γ(t) at the oscillation maxima of q (F(4.4));
// with a reference on the output grid also d(t) of the reference and the differences. The per-step
// part is MaximaPart (below: a MaximaFinder fed every step, diagnostics/maxima.hpp).
#pragma once

#include "diagnostics/capabilities.hpp"
#include "diagnostics/diagnostic.hpp"
#include "diagnostics/maxima.hpp"
#include "diagnostics/metric_json.hpp"
#include "diagnostics/observer_part.hpp"

#include <optional>
#include <string_view>
#include <vector>

namespace dampsym {

// The maxima of the run's q, located at every step. Its figure series are drawn from the maxima
// themselves (harness/figures/series.hpp), so it keeps none per step.
template <class P>
class MaximaPart {
public:
    MaximaPart(const P& p, const PartContext& ctx) : finder_(p, ctx.t0), t0_(ctx.t0) {}
    void start(const Vec& z0) { finder_.feed(t0_, z0); }
    void operator()(std::int64_t, double t, const Vec& z) { finder_.feed(t, z); }
    void series(nlohmann::json&) {}
    const std::vector<Maximum>& maxima() const { return finder_.maxima(); }
    std::int64_t nonpositive() const { return finder_.nonpositive(); }

private:
    MaximaFinder<P> finder_;
    double t0_;
};

struct DissipationDriftDiagnostic {
    static constexpr std::string_view name = "dissipation-drift";
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = HasOneDofMaxima<P>;
    template <class P>
    using Part = MaximaPart<P>;
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

// The run's maxima, when the recorder located them (its figure series).
template <class P, class R>
std::vector<Maximum> recorded_maxima(const R& rec) {
    if constexpr (DissipationDriftDiagnostic::supports<P>)
        if (rec.template enabled<DissipationDriftDiagnostic>())
            return rec.template part<DissipationDriftDiagnostic>().maxima();
    return {};
}

template <class V>
json DissipationDriftDiagnostic::produce(const V& run) {
    const auto& found = run.rec.template part<DissipationDriftDiagnostic>();
    return drift_metrics({found.maxima(), found.nonpositive()},
                         reference_maxima(run.problem, run.facts));
}

} // namespace dampsym
