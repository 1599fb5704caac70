#include "diagnostics/precession_diagnostic.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace dampsym {

DiagnosticInfo PrecessionDiagnostic::info() {
    return {.name = std::string(name),
            .what = "turning of the orbit's perihelion (Laplace-Runge-Lenz vector), HLW Fig 2.1",
            .requirement = "a Laplace-Runge-Lenz vector (Kepler's problem)",
            .needs = {.grid = true, .reference = true, .ok_run = true},
            .metrics = {"initial_angle", "total", "rate", "max_grid_step", "min_eccentricity",
                        "reference_total", "total_minus_reference"}};
}

namespace {

// Below this osculating eccentricity the perihelion direction is not defined (a circular orbit).
constexpr double kMinEccentricity = 1e-6;

struct Turning {
    double initial = 0.0, total = 0.0, max_step = 0.0, min_ecc = 0.0;
};

// φ_i = atan2(A₂, A₁) along the grid, unwrapped: each grid step adds the remainder of
// φ_i − φ_{i−1} modulo 2π in [−π, π].
Turning turning(const Mat& g, const RungeLenzFunction& runge_lenz) {
    Turning t;
    double prev = 0.0;
    t.min_ecc = std::numeric_limits<double>::infinity();
    for (Eigen::Index i = 0; i < g.cols(); ++i) {
        const auto a = runge_lenz(g.col(i));
        const double phi = std::atan2(a[1], a[0]);
        t.min_ecc = std::min(t.min_ecc, std::hypot(a[0], a[1]));
        if (i == 0) {
            t.initial = phi;
        } else {
            const double d = std::remainder(phi - prev, 2.0 * M_PI);
            t.total += d;
            t.max_step = std::max(t.max_step, std::abs(d));
        }
        prev = phi;
    }
    return t;
}

} // namespace

json precession_metrics(const CaseFacts& c, const Mat& g, const RungeLenzFunction& runge_lenz) {
    if (!runge_lenz) return {{"reason", "problem declares no Laplace-Runge-Lenz vector"}};
    if (g.cols() < 2) return {{"reason", "needs an output grid of at least two points"}};
    const Turning t = turning(g, runge_lenz);
    const double span = c.t_end - c.t0;
    json out = {{"initial_angle", t.initial},
                {"max_grid_step", t.max_step},
                {"min_eccentricity", t.min_ecc}};
    // The unwrapping needs the angle to move by less than π between grid points; near a
    // circular orbit the direction is undefined.
    if (!(t.min_ecc >= kMinEccentricity) || !(t.max_step < 0.5 * M_PI)) {
        const std::string why =
            !(t.min_ecc >= kMinEccentricity)
                ? "orbit nearly circular (eccentricity below 1e-6): no perihelion direction"
                : "the perihelion turns by pi/2 or more between output points: refine output_dt";
        set_undefined(out, "total", why);
        set_undefined(out, "rate", why);
        return out;
    }
    out["total"] = t.total;
    out["rate"] = t.total / span;
    if (c.reference_ok && c.ref.cols() == g.cols()) {
        const Turning r = turning(c.ref, runge_lenz);
        out["reference_total"] = r.total;
        out["total_minus_reference"] = t.total - r.total;
    }
    return out;
}

} // namespace dampsym
