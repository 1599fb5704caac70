// Diagnostic "precession": how the orbit's ellipse turns about its focus (HLW I.2, Fig 2.1: with a
// large step "the numerical solution lies close to an ellipse which turns slowly around its focus,
// clockwise for the symplectic Euler method and anticlockwise for the implicit midpoint rule").
// The direction of the perihelion is that of the Laplace–Runge–Lenz vector A (the problem's
// runge_lenz(z)); its angle φ = atan2(A₂, A₁) is followed on the output grid and unwrapped
// (docs/conventions.md §5 "precession").
#pragma once

#include "core/types.hpp"
#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"

#include <array>
#include <functional>
#include <string_view>

namespace dampsym {

// What a problem declares to support it: the Laplace–Runge–Lenz vector of a planar Kepler orbit
// (its direction is the perihelion's, its length the eccentricity).
template <class P>
concept HasRungeLenz = requires(const P& p, const Vec& z) {
    { p.runge_lenz(z) } -> std::convertible_to<std::array<double, 2>>;
};

struct PrecessionDiagnostic {
    static constexpr std::string_view name = "precession";
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = HasRungeLenz<P>;
    // Its metrics of one run from the run's view (harness/run/view.hpp: the problem, the case's
    // facts, the recorder and grid, the method, h, the final state, the counters).
    template <class V>
    static json produce(const V& run);
};
DAMPSYM_DIAGNOSTIC(PrecessionDiagnostic, 170);

// The Laplace–Runge–Lenz vector of a state (its length is the osculating eccentricity).
using RungeLenzFunction = std::function<std::array<double, 2>(const Vec&)>;

// From the output grid (and the reference on the same grid, when there is one).
json precession_metrics(const CaseFacts& c, const Mat& grid, const RungeLenzFunction& runge_lenz);

template <class V>
json PrecessionDiagnostic::produce(const V& run) {
    const auto& p = run.problem;
    return precession_metrics(run.facts, run.grid(),
                              [&p](const Vec& v) { return p.runge_lenz(v); });
}

} // namespace dampsym
