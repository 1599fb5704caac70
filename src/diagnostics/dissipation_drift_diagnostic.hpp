// Diagnostic "dissipation-drift": d(t) = ln(max q) + Γ(t) at the oscillation maxima of q (F(4.4));
// with a reference on the output grid also d(t) of the reference and the differences. The per-step
// part is MaximaPart (below: a MaximaFinder fed every step, diagnostics/maxima.hpp).
#pragma once

#include "diagnostics/capabilities.hpp"
#include "diagnostics/diagnostic.hpp"
#include "diagnostics/maxima.hpp"
#include "diagnostics/metric_json.hpp"
#include "diagnostics/observer_part.hpp"
#include "diagnostics/series.hpp"

#include <optional>
#include <string_view>
#include <vector>

namespace dampsym {

// d(t_max) at the maxima, as a figure series.
inline nlohmann::json maxima_series(const std::vector<Maximum>& mx) {
    MinMaxDecimator d(static_cast<std::int64_t>(mx.size()));
    for (const auto& m : mx) d.push(m.t, m.d);
    return d.to_json();
}

// The maxima of the run's q, located at every step; with a series, d(t) at them.
template <class P>
class MaximaPart {
public:
    MaximaPart(const P& p, const PartContext& ctx)
        : finder_(p, ctx.t0), t0_(ctx.t0), series_(ctx.series_steps > 0) {}
    void start(const Vec& z0) { finder_.feed(t0_, z0); }
    void operator()(std::int64_t, double t, const Vec& z) { finder_.feed(t, z); }
    void series(nlohmann::json& s); // below the diagnostic, whose name keys it
    const std::vector<Maximum>& maxima() const { return finder_.maxima(); }
    std::int64_t nonpositive() const { return finder_.nonpositive(); }

private:
    MaximaFinder<P> finder_;
    double t0_;
    bool series_;
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
    // With --figures: its series on the measured run's output grid (harness/figures/series.hpp
    // GridSeries: the problem, the case, the grid and its times, the reference on the grid).
    template <class G>
    static void grid_series(const G& g, nlohmann::json& s);
};
DAMPSYM_DIAGNOSTIC(DissipationDriftDiagnostic, 50);

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

template <class P>
void MaximaPart<P>::series(nlohmann::json& s) {
    if (series_) s[std::string(DissipationDriftDiagnostic::name) + ".d"] = maxima_series(maxima());
}

template <class V>
json DissipationDriftDiagnostic::produce(const V& run) {
    const auto& found = run.rec.template part<DissipationDriftDiagnostic>();
    return drift_metrics({found.maxima(), found.nonpositive()},
                         reference_maxima(run.problem, run.facts));
}

// F (4.4): d(t) at the run's oscillation maxima, and the reference's by the same locator on the
// reference samples (drift_metrics).
template <class G>
void DissipationDriftDiagnostic::grid_series(const G& g, nlohmann::json& s) {
    using P = typename G::Problem;
    const std::string key(name);
    if constexpr (HasOneDofMaxima<P>) {
        if (g.ref_on_grid && g.cols() > 2) {
            MaximaFinder<P> finder(g.problem, g.c.t0);
            for (Eigen::Index i = 0; i < g.cols(); ++i) finder.feed(g.t(i), g.ref.col(i));
            s[key + ".d_reference"] = maxima_series(finder.maxima());
        }
    }
}

} // namespace dampsym
