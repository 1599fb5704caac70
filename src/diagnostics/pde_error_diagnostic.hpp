// Diagnostic "pde-error": the error of a scheme against the PDE's own solution, sampled on the
// problem's grid at the output times (not the semi-discrete system's solution, so it holds the
// space error too), for a problem that declares pde_solution(t0, t, out). B's modified Burgers
// (4.5) declares the solution by characteristics before its shock (src/pde/burgers.hpp), so B
// Fig 5.4's "(5.10) and (5.12) are more accurate than NSFD (4.18)" is a comparison of this
// metric (docs/conventions.md §5 "pde-error", docs/pde.md).
#pragma once

#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"

#include <functional>

namespace dampsym {

// A problem that knows its PDE's solution on its grid: pde_solution(t0, t, out) writes it (the
// first out.size() state components) and returns false where it has none (after a shock).
template <class P>
concept HasPdeSolution = requires(const P& p, Vec& out) {
    { p.pde_solution(0.0, 0.0, out) } -> std::same_as<bool>;
};

struct PdeErrorDiagnostic {
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = HasPdeSolution<P>;
};

// From the output grid: solution(t, out) the problem's pde_solution from the case's start.
json pde_error_metrics(const CaseFacts& c, const Mat& grid,
                       const std::function<bool(double, Vec&)>& solution);

} // namespace dampsym
