// The one convergence test of every Newton solve in the method kernels (cimp, implicit RK, IFRK,
// exponential RK, partitioned RK, general linear): the iteration has converged to round-off when
// the update is a few ulps of the iterate's scale, or when it stopped decreasing once it was
// already tiny (the round-off floor of the residual).
#pragma once

#include <limits>

namespace dampsym {

inline bool newton_converged(double step_norm, double scale, double previous_step_norm) {
    constexpr double eps = std::numeric_limits<double>::epsilon();
    return step_norm <= 4.0 * eps * scale ||
           (step_norm <= 1e-10 * scale && step_norm >= 0.5 * previous_step_norm);
}

} // namespace dampsym
