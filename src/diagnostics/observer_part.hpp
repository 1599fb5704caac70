// A diagnostic's per-step part: what it measures at every step of the loop (a conformal law's
// residual, the oscillation maxima, the energy balance). A diagnostic with such a part declares
// it as a member template `Part<P>` next to its producer (src/diagnostics/<name>_diagnostic.hpp);
// the Recorder (recorder.hpp) holds one optional part per such diagnostic of the list and the
// typed case enables those its case names. With --figures the same part also keeps its per-step
// series (one computation for the report and the figure).
#pragma once

#include "core/types.hpp"

#include <nlohmann/json.hpp>

#include <concepts>
#include <cstdint>
#include <limits>

namespace dampsym {

struct PartContext {
    double t0 = 0.0, h = 0.0;
    // B Table 3.1's per-step factor of Σp the method declares (NaN: none).
    double table_factor = std::numeric_limits<double>::quiet_NaN();
    // > 0: keep the per-step series too, decimated for a run of this many steps (series.hpp).
    std::int64_t series_steps = 0;
};

// start(z0) at t0; (n, t, z) after step n (t = t0 + n h); series(s) adds its per-step series
// under its own keys.
template <class T>
concept ObserverPart = requires(T& part, const Vec& z, std::int64_t n, double t,
                                nlohmann::json& s) {
    part.start(z);
    part(n, t, z);
    part.series(s); // once, after the run (it flushes its decimators)
};

// Whether diagnostic D has a per-step part for problem type P.
template <class D, class P>
constexpr bool has_observer_part() {
    if constexpr (requires { typename D::template Part<P>; })
        return D::template supports<P>;
    else
        return false;
}

} // namespace dampsym
