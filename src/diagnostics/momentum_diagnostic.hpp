// Diagnostic "momentum": the per-step laws of the total linear momentum Σp_i and the angular
// momentum Σq_i×p_i, X_{n+1} = e^{−2ΔΓ} X_n (B Ex. 1.3), and the factor the method declares
// (B Table 3.1). The per-step hook is the Recorder's "momentum" part (diagnostics/recorder.hpp).
#pragma once

#include "diagnostics/capabilities.hpp"
#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"
#include "diagnostics/recorder.hpp"

#include <string_view>

namespace dampsym {

struct MomentumDiagnostic {
    static constexpr std::string_view name = "momentum";
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = HasMomentum<P>;
    // Its metrics of one run from the run's view (harness/run/view.hpp: the problem, the case's
    // facts, the recorder and grid, the method, h, the final state, the counters).
    template <class V>
    static json produce(const V& run);
};

// B Table 3.1 factor of Σp per step the method declares (claims, core/method.hpp) at a constant
// damping step gh = γh; NaN if it declares none or the damping is not constant.
double table_momentum_factor(unsigned claims, bool constant_gamma, double gh);

// linear_law: whether Σp has a law (Kepler's fixed centre breaks it); law_factor e^{−2ΔΓ}.
json momentum_metrics(const VectorLawStats& linear, const VectorLawStats& angular, bool linear_law,
                      double table_factor, double law_factor);

template <class P>
constexpr bool has_linear_momentum_law() {
    if constexpr (requires { P::linear_momentum_law; })
        return P::linear_momentum_law;
    else
        return true;
}

template <class V>
json MomentumDiagnostic::produce(const V& run) {
    using P = typename V::Problem;
    return momentum_metrics(run.rec.linear_momentum_stats(), run.rec.angular_momentum_stats(),
                            has_linear_momentum_law<P>(), run.table_factor,
                            std::exp(-2.0 * run.problem.dGamma(run.t0, run.h)));
}

} // namespace dampsym
