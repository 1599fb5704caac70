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
    static constexpr std::string_view name = "invariants";
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = true; // a check on it needs invariants (case.cpp)
    // Its metrics of one run from the run's view (harness/run/view.hpp: the problem, the case's
    // facts, the recorder and grid, the method, h, the final state, the counters).
    template <class V>
    static json produce(const V& run);
};

// names / scale_defs: the problem's invariant_names and invariant_scale_defs; initial: I_k(z_0).
json invariant_metrics(const std::vector<InvariantStats>& stats,
                       const std::vector<std::string_view>& names,
                       const std::vector<std::string_view>& scale_defs,
                       const std::vector<double>& initial);

template <class V>
json InvariantsDiagnostic::produce(const V& run) {
    using P = typename V::Problem;
    std::vector<double> initial;
    for (std::size_t k = 0; k < P::invariant_names.size(); ++k)
        initial.push_back(run.rec.initial_invariant(k));
    return invariant_metrics(
        run.rec.invariant_stats(), {P::invariant_names.begin(), P::invariant_names.end()},
        {P::invariant_scale_defs.begin(), P::invariant_scale_defs.end()}, initial);
}

} // namespace dampsym
