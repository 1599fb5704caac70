// Convergence order from a step ladder (conventions §5 "order", B Fig 3.2).
//
// Rule (docs/conventions.md §5 "order"):
//  (1) points whose error is not finite or not above `floor` (round-off and reference accuracy)
//      are dropped, and so are points whose error is not small against the solution (at least
//      `large_fraction` of `solution_scale`, e.g. ‖z_ref(t_end)‖): such a step resolves nothing,
//      and its local order says nothing about the method;
//  (2) the window ENDS at the finest remaining step — the smallest step whose error is above the
//      floor is where the asymptotic behaviour lives, so the fit may never look away from it —
//      and extends to coarser steps as far as the neighbour-to-neighbour local orders agree with
//      their mean to within max(0.1·|mean|, 0.05), with a mean local order of at least 0.5;
//  (3) the order is the least-squares slope of log e against log h over the window, with R².
// When no window of >= 3 points ends at the finest step, the fit fails with a status naming what
// the finest steps do ("order drops at small h", "order rises at small h", "no convergence at the
// finest steps") and the local orders; fewer than 3 usable points is a failed fit too. A failed
// fit has no slope: every check on it fails with the status, never a guess.
#pragma once

#include <limits>
#include <string>
#include <vector>

namespace dampsym {

struct OrderPoint {
    double h;
    double error;
};

struct DroppedPoint {
    double h;
    double error;
    std::string reason;
};

struct OrderFit {
    bool ok = false;
    std::string status = "ok"; // "ok" or the short name of why the fit failed
    std::string reason;        // why the fit failed, with the local orders, when !ok
    double slope = 0.0, intercept = 0.0, r2 = 0.0;
    std::vector<double> window_h;      // h values used, descending
    std::vector<double> local_orders;  // between neighbours of the usable points, descending h
    std::vector<DroppedPoint> dropped; // points not used, with the reason
};

// Fraction of the solution's size at or above which an error is "not small against the solution".
inline constexpr double order_fit_large_fraction = 0.1;

// solution_scale: the size of the solution the errors are measured against (infinity: no such
// bound).
OrderFit fit_order(std::vector<OrderPoint> points, double floor,
                   double solution_scale = std::numeric_limits<double>::infinity());

// An order check `near` with tolerance `tol` on a fit (its JSON from order_fit_json): "" when the
// local order between the two finest usable steps agrees with the fitted slope to within tol, else
// why not — a fit whose finest steps disagree with its slope beyond the check's own tolerance
// fails every order check on it, whatever the slope (docs/conventions.md §5 order).
std::string finest_steps_disagree(double slope, double finest_local_order, double tol);

// Plain least-squares line y = a + b x: returns {b, a, r2}. Needs >= 2 points.
struct LineFit {
    double slope, intercept, r2;
};
LineFit least_squares(const std::vector<double>& x, const std::vector<double>& y);

} // namespace dampsym
