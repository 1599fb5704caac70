// Diagnostic "error": the global error against the reference (exact solution or certified GSL
// reference, docs/conventions.md §4) on the output grid and at t_end.
#pragma once

#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"
#include "diagnostics/series.hpp"

#include <string>
#include <string_view>

namespace dampsym {

struct ErrorDiagnostic {
    static constexpr std::string_view name = "error";
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = true;
    // Its metrics of one run from the run's view (harness/run/view.hpp: the problem, the case's
    // facts, the recorder and grid, the method, h, the final state, the counters).
    template <class V>
    static json produce(const V& run);
    // With --figures: its series on the measured run's output grid (harness/figures/series.hpp
    // GridSeries: the problem, the case, the grid and its times, the reference on the grid).
    template <class G>
    static void grid_series(const G& g, nlohmann::json& s);
};
DAMPSYM_DIAGNOSTIC(ErrorDiagnostic, 10);

// The running reduction of the error over the output grid t_1..t_end: fed one grid point
// at a time, either on the fly during the run (harness/run/grid_stream.hpp: no trajectory stored)
// or from a stored grid (error_metrics); the same operations in the same order either way, so the
// metrics are bitwise the same.
class ErrorAccumulator {
public:
    // ref_error: the reference's certified error estimate (0 for an exact solution).
    explicit ErrorAccumulator(double ref_error) : ref_error_(ref_error) {}
    // Grid point i >= 1 at time t (the initial point is exact): the run's state and the reference.
    void add(const Eigen::Ref<const Vec>& z, const Eigen::Ref<const Vec>& ref, double t);
    // The metrics, from the grid points added and the final state against the reference at t_end.
    json finish(const Eigen::Ref<const Vec>& z_final, const Eigen::Ref<const Vec>& ref_final,
                double t_end) const;

private:
    double rel_of(double e, double ref_norm, double t, std::string& undefined) const;
    double ref_error_;
    double max_abs_ = 0.0, max_rel_ = 0.0, sum_abs_ = 0.0;
    Eigen::Index count_ = 0;
    std::string rel_undefined_;
};

// grid: the run's states on the output grid (null when the case records none).
json error_metrics(const CaseFacts& c, const Mat* grid, const Vec& z_final);

template <class V>
json ErrorDiagnostic::produce(const V& run) {
    return run.stream ? run.stream->error_metrics(run.z)
                      : error_metrics(run.facts, run.stored_grid, run.z);
}

// error: |z_n − z(t_n)| on the grid, and each measure's pointwise value.
template <class G>
void ErrorDiagnostic::grid_series(const G& g, nlohmann::json& s) {
    if (!g.ref_on_grid) return;
    MinMaxDecimator e(g.cols() - 1);
    for (Eigen::Index i = 1; i < g.cols(); ++i)
        e.push(g.t(i), (g.grid.col(i) - g.ref.col(i)).norm());
    s[std::string(name) + ".abs"] = e.to_json();
}

} // namespace dampsym
