// Diagnostic "error": the global error against the reference (exact solution or certified GSL
// reference, docs/conventions.md §4) on the output grid and at t_end.
#pragma once

#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"

namespace dampsym {

struct ErrorDiagnostic {
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = true;
};

// grid: the run's states on the output grid (null when the case records none).
json error_metrics(const CaseFacts& c, const Mat* grid, const Vec& z_final);

} // namespace dampsym
