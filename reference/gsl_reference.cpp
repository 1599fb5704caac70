#include "reference/gsl_reference.hpp"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <memory>
#include <mutex>
#include <sstream>

namespace dampsym {

// GSL's default handler aborts; we check every status instead. Switched off once, process-wide.
void gsl_errors_off() {
    static std::once_flag once;
    std::call_once(once, [] { gsl_set_error_handler_off(); });
}

namespace {

const char* gsl_status_name(int s) {
    switch (s) {
    case GSL_FAILURE:
        return "GSL_FAILURE";
    case GSL_EINVAL:
        return "GSL_EINVAL";
    case GSL_EFAULT:
        return "GSL_EFAULT";
    case GSL_ENOMEM:
        return "GSL_ENOMEM";
    case GSL_EBADFUNC:
        return "GSL_EBADFUNC";
    case GSL_EMAXITER:
        return "GSL_EMAXITER";
    case GSL_ENOPROG:
        return "GSL_ENOPROG";
    default:
        return "GSL status";
    }
}

// Per-solve state handed to GSL as the system's params: the user's rhs, the evaluation count and
// the reason the rhs was rejected, if it was.
struct RhsContext {
    explicit RhsContext(const ReferenceRequest& r) : req(&r) {}
    const ReferenceRequest* req;
    std::int64_t evals = 0;
    std::string failure;
};

bool all_finite(const double* v, int n) {
    return std::all_of(v, v + n, [](double x) { return std::isfinite(x); });
}

// The C callback. Non-finite input or output, or an exception, is reported as GSL_EBADFUNC, which
// evolve_apply returns at once (no step-size halving down to nothing).
int gsl_rhs(double t, const double y[], double dydt[], void* params) {
    auto* ctx = static_cast<RhsContext*>(params);
    ++ctx->evals;
    const int n = ctx->req->dim;
    if (!all_finite(y, n)) {
        ctx->failure = "non-finite state passed to rhs";
        return GSL_EBADFUNC;
    }
    try {
        ctx->req->rhs(t, y, dydt);
    } catch (const std::exception& e) {
        ctx->failure = std::string("rhs threw: ") + e.what();
        return GSL_EBADFUNC;
    } catch (...) {
        ctx->failure = "rhs threw a non-standard exception";
        return GSL_EBADFUNC;
    }
    if (!all_finite(dydt, n)) {
        ctx->failure = "rhs returned a non-finite value";
        return GSL_EBADFUNC;
    }
    return GSL_SUCCESS;
}

// Empty string if the request is usable, else why not.
std::string validate(const ReferenceRequest& r) {
    if (r.dim <= 0) return "dim must be positive";
    if (r.y0.size() != r.dim)
        return "y0 has size " + std::to_string(r.y0.size()) + ", dim is " + std::to_string(r.dim);
    if (!r.rhs) return "rhs is empty";
    if (r.stepper != "rkf45" && r.stepper != "rk8pd") return "unknown stepper '" + r.stepper + "'";
    if (!std::isfinite(r.t0) || !r.y0.allFinite()) return "t0 and y0 must be finite";
    if (r.times.empty()) return "no output times";
    double prev = r.t0;
    for (std::size_t k = 0; k < r.times.size(); ++k) {
        if (!std::isfinite(r.times[k]) || r.times[k] < prev)
            return "output times must be finite, non-decreasing and >= t0 (index " +
                   std::to_string(k) + ")";
        prev = r.times[k];
    }
    if (!(r.epsabs >= 0.0) || !(r.epsrel >= 0.0) || r.epsabs + r.epsrel <= 0.0)
        return "epsabs, epsrel must be >= 0 and not both 0";
    if (r.nmax == 0) return "nmax must be positive";
    if (!(r.hmin >= 0.0) || !(r.hstart > 0.0) || r.hstart < r.hmin)
        return "need 0 <= hmin <= hstart";
    return {};
}

struct DriverDeleter {
    void operator()(gsl_odeiv2_driver* d) const { gsl_odeiv2_driver_free(d); }
};

// One GSL solve with the given stepper and tolerances; the request is already validated.
ReferenceSolution run(const ReferenceRequest& req, const std::string& stepper, double epsabs,
                      double epsrel) {
    ReferenceSolution out;
    out.stepper = stepper;
    out.epsabs = epsabs;
    out.epsrel = epsrel;

    RhsContext ctx(req);
    gsl_odeiv2_system sys{gsl_rhs, nullptr, static_cast<std::size_t>(req.dim), &ctx};
    const gsl_odeiv2_step_type* type =
        stepper == "rk8pd" ? gsl_odeiv2_step_rk8pd : gsl_odeiv2_step_rkf45;
    // y_new control: accept a step when |err_i| <= epsabs + epsrel |y_i| for every i.
    std::unique_ptr<gsl_odeiv2_driver, DriverDeleter> drv(
        gsl_odeiv2_driver_alloc_y_new(&sys, type, req.hstart, epsabs, epsrel));
    if (!drv) {
        out.error = "gsl_odeiv2_driver_alloc_y_new failed";
        return out;
    }
    if (int s = gsl_odeiv2_driver_set_hmin(drv.get(), req.hmin); s != GSL_SUCCESS) {
        out.error = std::string("gsl_odeiv2_driver_set_hmin: ") + gsl_status_name(s);
        return out;
    }
    gsl_odeiv2_driver_set_nmax(drv.get(), req.nmax);

    out.states.resize(req.dim, static_cast<Eigen::Index>(req.times.size()));
    Vec y = req.y0;
    double t = req.t0;
    for (std::size_t k = 0; k < req.times.size(); ++k) {
        const double t1 = req.times[k];
        if (t1 > t) { // t1 == t (t0 itself, or a repeated time): y is already the sample
            const int s = gsl_odeiv2_driver_apply(drv.get(), &t, t1, y.data());
            if (s != GSL_SUCCESS || t != t1 || !y.allFinite()) {
                std::ostringstream msg;
                msg.precision(17);
                msg << stepper << ": gsl_odeiv2_driver_apply returned "
                    << (s == GSL_SUCCESS ? "success with a bad state" : gsl_status_name(s)) << " ("
                    << s << ", " << gsl_strerror(s) << ") at t = " << t
                    << " while advancing to t = " << t1;
                if (s == GSL_EMAXITER) msg << " (more than nmax = " << req.nmax << " steps)";
                if (s == GSL_ENOPROG) msg << " (step size fell below hmin = " << req.hmin << ")";
                if (!ctx.failure.empty()) msg << ": " << ctx.failure;
                out.error = msg.str();
                out.rhs_evals = ctx.evals;
                return out;
            }
        }
        out.states.col(static_cast<Eigen::Index>(k)) = y;
    }
    out.rhs_evals = ctx.evals;
    out.ok = true;
    return out;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

} // namespace

ReferenceSolution solve_reference(const ReferenceRequest& req) {
    gsl_errors_off();
    const auto start = std::chrono::steady_clock::now();
    ReferenceSolution out;
    if (std::string why = validate(req); !why.empty()) {
        out.stepper = req.stepper;
        out.epsabs = req.epsabs;
        out.epsrel = req.epsrel;
        out.error = "bad reference request: " + why;
    } else {
        out = run(req, req.stepper, req.epsabs, req.epsrel);
    }
    out.wall_seconds = seconds_since(start);
    return out;
}

ReferenceSolution certified_reference(const ReferenceRequest& req) {
    const auto start = std::chrono::steady_clock::now();
    ReferenceSolution out = solve_reference(req);
    out.certifier = "rk8pd";
    out.cert_epsabs = std::min(1e-15, req.epsabs / 10);
    out.cert_epsrel = std::min(1e-14, req.epsrel / 10);
    if (out.ok) {
        const ReferenceSolution cert = run(req, out.certifier, out.cert_epsabs, out.cert_epsrel);
        if (!cert.ok) {
            out.ok = false;
            out.error = "certifying solve failed: " + cert.error;
        } else {
            out.error_estimate = (out.states - cert.states).cwiseAbs().maxCoeff();
        }
    }
    out.wall_seconds = seconds_since(start);
    return out;
}

} // namespace dampsym
