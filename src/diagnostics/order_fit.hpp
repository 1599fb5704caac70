// Convergence order from a step ladder (conventions §5 "order", B Fig 3.2).
//
// Rule: (1) points whose error is not finite or not above `floor` (round-off or reference floor)
// are dropped; (2) among the remaining points, sorted by h, the asymptotic window is the longest
// contiguous run of >= 3 points whose neighbour-to-neighbour local orders agree with their mean to
// within max(0.1·|mean|, 0.05) and whose mean local order is at least 0.5 (a run that does not
// converge is a round-off or reference plateau, however long) — coarse pre-asymptotic points and
// plateau points break that agreement; ties go to the run with the smallest spread, then the finer
// one; (3) the order is the
// least-squares slope of log e against log h over the window, with R². Fewer than 3 usable points,
// or no consistent window, is a failed fit with a reason, never a guess.
#pragma once

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
    std::string reason; // why the fit failed, when !ok
    double slope = 0.0, intercept = 0.0, r2 = 0.0;
    std::vector<double> window_h;      // h values used, descending
    std::vector<double> local_orders;  // between neighbours of the usable points, descending h
    std::vector<DroppedPoint> dropped; // points not used, with the reason
};

OrderFit fit_order(std::vector<OrderPoint> points, double floor);

// Plain least-squares line y = a + b x: returns {b, a, r2}. Needs >= 2 points.
struct LineFit {
    double slope, intercept, r2;
};
LineFit least_squares(const std::vector<double>& x, const std::vector<double>& y);

} // namespace dampsym
