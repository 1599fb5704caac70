// Diagnostic "stability-sweep" (method level): F's condition and power-boundedness of the one-step
// matrix over a (γ, h) grid (docs/conventions.md §5, F Figs 3.1–3.3), against F's closed forms and
// the stability function of an RK tableau. The sweep of one method is split into independent tasks
// of sweep_rows_per_task γ rows; each writes only its own pre-sized row and sweep_json assembles
// the rows in grid order, so the report does not depend on --jobs or on the order tasks run in.
#pragma once

#include "core/method.hpp"
#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"
#include "diagnostics/stability.hpp"
#include "diagnostics/stability_diagnostic.hpp"

#include <cstdint>
#include <functional>
#include <string_view>
#include <vector>

namespace dampsym {

struct StabilitySweepDiagnostic {
    static constexpr std::string_view name = "stability-sweep";
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = LinearOscillator<P>;
};
DAMPSYM_DIAGNOSTIC(StabilitySweepDiagnostic, 70);

struct SweepRow {
    std::int64_t first_emp = 0, first_formula = 0, first_pb = 0, first_pb_formula = 0;
    std::int64_t f_viol = 0, pb_viol = 0, violations_inside = 0;
    std::int64_t mismatch = 0, pb_mismatch = 0;
    double max_trace_err = 0.0; // |½trM − e^{−γh}cos(βh)| over the row (F Fig 3.4)
};
inline constexpr std::size_t sweep_rows_per_task = 8;

// The analysis of the method's one-step matrix on the oscillator (ω, γ) at step h (the typed part).
using OneStepAt = std::function<OneStepAnalysis(double omega, double gamma, double h)>;

// One γ row of the grid hs.
SweepRow sweep_row(const MethodInfo& info, double omega, double gamma,
                   const std::vector<double>& hs, const OneStepAt& one_step);

// The method's sweep from its rows.
json sweep_json(const MethodInfo& info, double omega, const std::vector<double>& gammas,
                const std::vector<double>& hs, const std::vector<SweepRow>& rows);

} // namespace dampsym
