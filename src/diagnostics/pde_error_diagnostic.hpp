// Diagnostic "pde-error": the error of a scheme against the PDE's own solution, sampled on the
// problem's grid at the output times (not the semi-discrete system's solution, so it holds the
// space error too), for a problem that declares pde_solution(t0, t, out). B's modified Burgers
// (4.5) declares the solution by characteristics before its shock (src/pde/burgers/schemes.hpp), so
// B Fig 5.4's "(5.10) and (5.12) are more accurate than NSFD (4.18)" is a comparison of this metric
// (docs/conventions.md §5 "pde-error", docs/pde.md).
#pragma once

#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"

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
};

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

} // namespace dampsym
