// Diagnostic "invariants": the per-step and global conformal laws I_{n+1} = e^{−2ΔΓ} I_n of the
// problem's invariants (B Def. 2.3), residuals on their declared scales (docs/conventions.md). The
// per-step hook is the Recorder's "invariants" part (diagnostics/recorder.hpp).
#pragma once

#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"
#include "diagnostics/recorder.hpp"

#include <string_view>
#include <vector>

namespace dampsym {

struct InvariantsDiagnostic {
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = true; // a check on it needs invariants (case.cpp)
};

// names / scale_defs: the problem's invariant_names and invariant_scale_defs; initial: I_k(z_0).
json invariant_metrics(const std::vector<InvariantStats>& stats,
                       const std::vector<std::string_view>& names,
                       const std::vector<std::string_view>& scale_defs,
                       const std::vector<double>& initial);

} // namespace dampsym
