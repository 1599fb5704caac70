// Diagnostic "precession": how the orbit's ellipse turns about its focus (HLW I.2, Fig 2.1: with a
// large step "the numerical solution lies close to an ellipse which turns slowly around its focus,
// clockwise for the symplectic Euler method and anticlockwise for the implicit midpoint rule").
// The direction of the perihelion is that of the Laplace–Runge–Lenz vector A (the problem's
// runge_lenz(z)); its angle φ = atan2(A₂, A₁) is followed on the output grid and unwrapped
// (docs/conventions.md §5 "precession").
#pragma once

#include "diagnostics/capabilities.hpp"
#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"

#include <array>
#include <functional>

namespace dampsym {

struct PrecessionDiagnostic {
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = HasRungeLenz<P>;
};

// The Laplace–Runge–Lenz vector of a state (its length is the osculating eccentricity).
using RungeLenzFunction = std::function<std::array<double, 2>(const Vec&)>;

// From the output grid (and the reference on the same grid, when there is one).
json precession_metrics(const CaseFacts& c, const Mat& grid, const RungeLenzFunction& runge_lenz);

} // namespace dampsym
