// Helpers shared by the unit tests: observed-order slope, max norm, verbose output switch, catalog
// lookup, and the damped pendulum
// with its certified GSL reference (the orders tests of test_method_families.cpp and
// test_exponential_rk.cpp measure against the same reference).
#pragma once

#include "core/any_stepper.hpp"
#include "core/method.hpp"
#include "harness/run/kernel_ops.hpp"
#include "problems/pendulum.hpp"
#include "reference/gsl_reference.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <initializer_list>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace dampsym::test {

// Least-squares slope of log e against log h (an observed order).
inline double log_log_slope(const std::vector<double>& h, const std::vector<double>& e) {
    const int n = static_cast<int>(h.size());
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (int i = 0; i < n; ++i) {
        const double x = std::log(h[i]), y = std::log(e[i]);
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
    }
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

inline double max_abs(const Vec& v) {
    return v.cwiseAbs().maxCoeff();
}

// DAMPSYM_TEST_VERBOSE set (and not "" or "0"): the tests print what they measure.
inline bool verbose() {
    static const bool v = [] {
        const char* e = std::getenv("DAMPSYM_TEST_VERBOSE");
        return e != nullptr && e[0] != '\0' && e[0] != '0';
    }();
    return v;
}

// The catalog row of `id`; the test fails if there is none.
inline const MethodInfo& method(std::string_view id) {
    const MethodInfo* m = find_method(id);
    if (m == nullptr) FAIL("method not in the catalog: " << std::string(id));
    return *m;
}

// The functions of the kernel that steps `info` on the registered problem type P, compiled in the
// library's kernel shards (harness/run/kernel_ops.hpp): the tests instantiate no kernel of their
// own. The test fails if no kernel applies.
template <class P>
const KernelOps<P>& kernel(const MethodInfo& info) {
    KernelMatch match = KernelMatch::unknown_kernel;
    const KernelOps<P>* ops = kernel_ops<P>(info, match);
    if (ops == nullptr) FAIL("no kernel steps " << std::string(info.id) << " on " << P::id);
    return *ops;
}

// A fresh stepper of `info` on `problem` (kernel<P>), with its counts in `counters`.
template <class P>
std::unique_ptr<AnyStepper> stepper(const P& problem, const MethodInfo& info, double h,
                                    Counters& counters) {
    return kernel<P>(info).stepper(problem, info, h, counters);
}

// A stepper of `info` on `problem` from the library, or null when no kernel applies; a test of
// particular kernels names them, and the registry's choice must be one of them (checked, not
// assumed).
template <class P>
std::unique_ptr<AnyStepper> stepper_among(const P& problem, const MethodInfo& info, double h,
                                          Counters& counters,
                                          std::initializer_list<std::string_view> kernels) {
    KernelMatch match = KernelMatch::unknown_kernel;
    const KernelOps<P>* ops = kernel_ops<P>(info, match);
    if (ops == nullptr) return nullptr;
    INFO(std::string(info.id) << " on " << P::id << " is stepped by "
                              << std::string(ops->kernel_id));
    REQUIRE(std::find(kernels.begin(), kernels.end(), ops->kernel_id) != kernels.end());
    return ops->stepper(problem, info, h, counters);
}

// n steps of size h from t = 0 (t_k = k h); false on a failed step (a null stepper too).
inline bool steps_from_zero(AnyStepper* k, double h, int n, Vec& z) {
    if (k == nullptr) return false;
    for (int i = 0; i < n; ++i)
        if (k->step(time_at(0.0, h, i), z) != StepStatus::ok) return false;
    return true;
}

// q'' + 2γq' + sin q = 0 from q0 = 1, p0 = 0.
inline Pendulum pendulum(double gamma = 0.1) {
    Pendulum p;
    p.gamma = gamma;
    p.q0 = 1.0;
    p.p0 = 0.0;
    return p;
}

// The pendulum's state at t_end by the certified GSL reference (rk8pd, epsrel 1e-14, epsabs
// 1e-15; docs/conventions.md §4). Requires the certification to succeed.
inline ReferenceSolution pendulum_reference(const Pendulum& prob, double t_end) {
    ReferenceRequest req;
    req.dim = 2;
    req.y0 = prob.initial_state();
    req.times = {t_end};
    req.stepper = "rk8pd";
    req.epsabs = 1e-15;
    req.epsrel = 1e-14;
    req.rhs = [prob](double t, const double* y, double* f) {
        const Vec z = Eigen::Map<const Vec>(y, 2);
        Vec out(2);
        prob.rhs(t, z, out);
        f[0] = out[0];
        f[1] = out[1];
    };
    ReferenceSolution ref = certified_reference(req);
    REQUIRE(ref.ok);
    return ref;
}

} // namespace dampsym::test
