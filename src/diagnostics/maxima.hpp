// Oscillation maxima of q for the dissipation drift d(t) = ln(max q) + Γ(t) − Γ(t0) (F(4.4), whose
// runs start at t0 = 0; Γ counted from the start as everywhere else, bitwise F's at t0 = 0), for a
// separable problem with one degree of freedom. Between two consecutive samples (t_a, z_a),
// (t_b, z_b) where q' changes sign from + to −, q is interpolated by the quintic Hermite
// polynomial through q, q' and q'' at both ends (q' = f_q(z), q'' = ∂f_q/∂z · f(t, z): the vector
// field evaluated on the samples themselves, so method states and reference states are treated
// alike); the maximum is the root of the interpolant's derivative (safeguarded Newton). The
// interpolation error is O(Δt⁶), far below the methods' errors at the steps used.
#pragma once

#include "core/types.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace dampsym {

struct Maximum {
    double t;
    double q; // max q
    double d; // ln(q_max) + Γ(t_max) − Γ(t0)
};

template <class P>
class MaximaFinder {
public:
    MaximaFinder(const P& problem, double t0)
        : p_(problem), gamma0_(problem.Gamma(t0)), f_(problem.dim()),
          J_(problem.dim(), problem.dim()) {}

    // Feed consecutive samples (any spacing, increasing t).
    void feed(double t, const Vec& z) {
        Sample s{t, z[0], 0.0, 0.0};
        p_.rhs(t, z, f_);
        p_.rhs_jacobian(t, z, J_);
        s.dq = f_[0];
        s.ddq = J_.row(0).dot(f_);
        if (have_prev_ && prev_.dq > 0.0 && s.dq <= 0.0) locate(prev_, s);
        prev_ = s;
        have_prev_ = true;
    }

    const std::vector<Maximum>& maxima() const { return maxima_; }
    // Maxima of q at or below 0 (not in maxima(): d(t) = ln(max q) + Γ is undefined there).
    std::int64_t nonpositive() const { return nonpositive_; }

private:
    struct Sample {
        double t, q, dq, ddq;
    };

    void locate(const Sample& a, const Sample& b) {
        const double h = b.t - a.t;
        const double y0 = a.q, y1 = b.q, d0 = a.dq * h, d1 = b.dq * h;
        const double a0 = a.ddq * h * h, a1 = b.ddq * h * h;
        // H(s) = Σ c_k s^k on s ∈ [0, 1] (quintic Hermite).
        const std::array<double, 6> c{
            y0,
            d0,
            0.5 * a0,
            -10.0 * y0 - 6.0 * d0 - 1.5 * a0 + 0.5 * a1 - 4.0 * d1 + 10.0 * y1,
            15.0 * y0 + 8.0 * d0 + 1.5 * a0 - a1 + 7.0 * d1 - 15.0 * y1,
            -6.0 * y0 - 3.0 * d0 - 0.5 * a0 + 0.5 * a1 - 3.0 * d1 + 6.0 * y1};
        auto H = [&](double s) {
            return ((((c[5] * s + c[4]) * s + c[3]) * s + c[2]) * s + c[1]) * s + c[0];
        };
        auto dH = [&](double s) {
            return (((5.0 * c[5] * s + 4.0 * c[4]) * s + 3.0 * c[3]) * s + 2.0 * c[2]) * s + c[1];
        };
        auto ddH = [&](double s) {
            return ((20.0 * c[5] * s + 12.0 * c[4]) * s + 6.0 * c[3]) * s + 2.0 * c[2];
        };
        // dH(0) = d0 > 0 >= dH(1) = d1: bracketed root, Newton kept inside the bracket.
        double lo = 0.0, hi = 1.0, s = d0 / (d0 - d1);
        for (int it = 0; it < 60; ++it) {
            const double g = dH(s);
            if (g > 0.0)
                lo = s;
            else
                hi = s;
            const double dd = ddH(s);
            double next = dd < 0.0 ? s - g / dd : 0.5 * (lo + hi);
            if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
            if (std::abs(next - s) <= 1e-16) {
                s = next;
                break;
            }
            s = next;
        }
        const double qmax = H(s);
        const double tm = a.t + s * h;
        if (qmax > 0.0)
            maxima_.push_back({tm, qmax, std::log(qmax) + (p_.Gamma(tm) - gamma0_)});
        else
            ++nonpositive_; // ln(max q) undefined: counted, reported by the d(t) metrics
    }

    const P& p_;
    double gamma0_; // Γ(t0)
    Vec f_;
    Mat J_;
    Sample prev_{};
    bool have_prev_ = false;
    std::vector<Maximum> maxima_;
    std::int64_t nonpositive_ = 0;
};

} // namespace dampsym
