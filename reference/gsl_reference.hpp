// Numerical references on GSL odeiv2 (conventions §4).
//
// solve_reference() integrates y' = rhs(t, y) from t0 and samples the state at the requested
// output times by successive gsl_odeiv2_driver_apply calls, each advancing t exactly to the next
// output time (the step before an output time is shortened to land on it; there is no
// interpolation). certified_reference() does the same and then recomputes the solution with rk8pd
// at a tighter tolerance; the largest max-norm difference between the two over all output times is
// the reference's own error estimate.
//
// Failures never throw and never abort: a bad request, a GSL failure (GSL_EMAXITER, GSL_ENOPROG,
// GSL_FAILURE, ...), a non-finite or throwing rhs all come back as ok = false with a message.
// Both functions are thread-safe: every call owns its GSL objects; the only global is GSL's error
// handler, switched off once (std::call_once) on first use.
#pragma once

#include "core/types.hpp"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace dampsym {

struct ReferenceRequest {
    int dim = 0;
    double t0 = 0.0;
    Vec y0;
    std::vector<double> times; // output times: non-empty, non-decreasing, all >= t0 (t0 allowed)
    // dydt = f(t, y); both arrays have length dim. May be called concurrently from different
    // solves, so it must not share mutable state across threads. Exceptions are caught.
    std::function<void(double t, const double* y, double* dydt)> rhs;
    std::string stepper = "rkf45"; // "rkf45" (the seeds' choice) or "rk8pd"
    double epsabs = 1e-13;         // gsl_odeiv2_control_y_new: |err_i| <= epsabs + epsrel |y_i|
    double epsrel = 1e-12;
    std::size_t nmax = 50'000'000; // max steps per output interval (GSL counts per driver_apply)
    double hmin = 1e-14;           // a suggested step below this fails with GSL_ENOPROG
    double hstart = 1e-3;          // must satisfy hstart >= hmin
};

struct ReferenceSolution {
    bool ok = false;
    std::string error; // when !ok: what failed (GSL status name, t reached, stepper)
    Mat states;        // dim × times.size(); column k is y(times[k])
    // Certification only: max over output times of ‖y_main − y_cert‖_∞; NaN for an uncertified
    // solve.
    double error_estimate = std::numeric_limits<double>::quiet_NaN();
    std::string stepper; // what the main solve used
    double epsabs = 0.0;
    double epsrel = 0.0;
    std::string certifier; // empty for an uncertified solve
    double cert_epsabs = 0.0;
    double cert_epsrel = 0.0;
    std::int64_t rhs_evals = 0; // of the main solve
    double wall_seconds = 0.0;  // whole call, including the certifying solve
};

// One solve, no certification.
ReferenceSolution solve_reference(const ReferenceRequest& req);

// Switches GSL's aborting error handler off, once per process (every GSL status is checked).
void gsl_errors_off();

// solve_reference(req), then the same problem with rk8pd at epsrel = min(1e-14, req.epsrel/10),
// epsabs = min(1e-15, req.epsabs/10); states come from the main solve. ok = false if either solve
// fails.
ReferenceSolution certified_reference(const ReferenceRequest& req);

} // namespace dampsym
