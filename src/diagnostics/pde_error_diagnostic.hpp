// Diagnostic "pde-error": the error of a scheme against the PDE's own solution, sampled on the
// problem's grid at the output times (not the semi-discrete system's solution, so it holds the
// space error too), for a problem that declares pde_solution(t0, t, out). B's modified Burgers
// (4.5) declares the solution by characteristics before its shock (src/pde/burgers/schemes.hpp), so
// B Fig 5.4's "(5.10) and (5.12) are more accurate than NSFD (4.18)" is a comparison of this metric
// (docs/conventions.md §5 "pde-error", docs/pde.md).
#pragma once

#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"
#include "diagnostics/series.hpp"

#include <functional>
#include <string_view>

namespace dampsym {

// A problem that knows its PDE's solution on its grid: pde_solution(t0, t, out) writes it (the
// first out.size() state components) and returns false where it has none (after a shock).
template <class P>
concept HasPdeSolution = requires(const P& p, Vec& out) {
    { p.pde_solution(0.0, 0.0, out) } -> std::same_as<bool>;
};

struct PdeErrorDiagnostic {
    static constexpr std::string_view name = "pde-error";
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = HasPdeSolution<P>;
    // Its metrics of one run from the run's view (harness/run/view.hpp: the problem, the case's
    // facts, the recorder and grid, the method, h, the final state, the counters).
    template <class V>
    static json produce(const V& run);
    // With --figures: its series on the measured run's output grid (harness/figures/series.hpp
    // GridSeries: the problem, the case, the grid and its times, the reference on the grid).
    template <class G>
    static void grid_series(const G& g, nlohmann::json& s);
};
DAMPSYM_DIAGNOSTIC(PdeErrorDiagnostic, 190);

// From the output grid: solution(t, out) the problem's pde_solution from the case's start.
json pde_error_metrics(const CaseFacts& c, const Mat& grid,
                       const std::function<bool(double, Vec&)>& solution);

template <class V>
json PdeErrorDiagnostic::produce(const V& run) {
    const auto& p = run.problem;
    const double t0 = run.t0;
    return pde_error_metrics(run.facts, run.grid(),
                             [&p, t0](double t, Vec& u) { return p.pde_solution(t0, t, u); });
}

// B Fig 5.4: the field and the PDE's solution at the output times (at most 9; full precision:
// figures.data recomputes pde-error.max_abs from them).
template <class G>
void PdeErrorDiagnostic::grid_series(const G& g, nlohmann::json& s) {
    using P = typename G::Problem;
    using json = nlohmann::json;
    if constexpr (HasPdeSolution<P>) {
        StrideSampler pick(g.cols(), 9);
        json ts = json::array(), us = json::array(), ps = json::array(), xs = json::array();
        Vec v;
        for (Eigen::Index i = 0; i < g.cols(); ++i) {
            if (!pick.wants(i)) continue;
            if (!g.problem.pde_solution(g.c.t0, g.t(i), v) || v.size() > g.grid.rows()) break;
            ts.push_back(g.t(i));
            us.push_back(
                std::vector<double>(g.grid.col(i).data(), g.grid.col(i).data() + v.size()));
            ps.push_back(std::vector<double>(v.data(), v.data() + v.size()));
        }
        if constexpr (requires { g.problem.grid.x(0); })
            for (int n = 0; n < g.problem.dim(); ++n) xs.push_back(g.problem.grid.x(n));
        s["snapshots"] = {{"t", ts}, {"u", us}, {"pde", ps}, {"x", xs}};
    }
}

} // namespace dampsym
