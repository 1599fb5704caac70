// Oscillation maxima of q for the dissipation drift d(t) = ln(max q) + Γ(t) − Γ(t0) (F(4.4), whose
// runs start at t0 = 0; Γ counted from the start as everywhere else, bitwise F's at t0 = 0), for a
// separable problem with one degree of freedom. Between two consecutive samples (t_a, z_a),
// (t_b, z_b) where q' changes sign from + to −, q is interpolated by the quintic Hermite
// polynomial through q, q' and q'' at both ends (q' = f_q(z), q'' = ∂f_q/∂z · f(t, z): the vector
// field evaluated on the samples themselves, so method states and reference states are treated
// alike); the maximum is the largest value of the interpolant at the roots of its derivative
// where it changes from + to − (safeguarded Newton; at coarse steps the interpolant can have more
// than one such root in a step, see locate()). The interpolation error is O(Δt⁶), far below the
// methods' errors at the steps used.
#pragma once

#include "core/types.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>
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

    // Root of dH in [lo, hi] with dH(lo) > 0 >= dH(hi): Newton from s0 kept inside the bracket
    // (bisection when a Newton step leaves it or dH is not concave there).
    template <class D, class DD>
    static double bracketed_root(const D& dH, const DD& ddH, double lo, double hi, double s) {
        for (int it = 0; it < 60; ++it) {
            const double g = dH(s);
            if (g > 0.0)
                lo = s;
            else
                hi = s;
            const double dd = ddH(s);
            double next = dd < 0.0 ? s - g / dd : 0.5 * (lo + hi);
            if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
            if (std::abs(next - s) <= 1e-16) return next;
            s = next;
        }
        return s;
    }

    // Root of a function f monotone on [a, b] with a sign change there, by bisection to round-off.
    template <class F>
    static double bisect(const F& f, double a, double b) {
        const bool fa_pos = f(a) > 0.0;
        for (int it = 0; it < 200; ++it) {
            const double m = 0.5 * (a + b);
            if (m <= a || m >= b) break;
            if ((f(m) > 0.0) == fa_pos)
                a = m;
            else
                b = m;
        }
        return 0.5 * (a + b);
    }

    // Splits the sorted cuts {0, ..., 1} (f monotone between consecutive ones) at the roots of f;
    // returns the new number of cuts.
    template <class F>
    static int split_at_roots(const F& f, const double* cuts, int n, double* out) {
        int m = 0;
        out[m++] = cuts[0];
        for (int i = 0; i + 1 < n; ++i) {
            if ((f(cuts[i]) > 0.0) != (f(cuts[i + 1]) > 0.0))
                out[m++] = bisect(f, cuts[i], cuts[i + 1]);
            out[m++] = cuts[i + 1];
        }
        return m;
    }

    // The brackets [lo_k, hi_k] in [0, 1] where dH changes sign from + to − (each holding one local
    // maximum of the quintic H = Σ c_k s^k): the roots of H‴ = 60c₅s² + 24c₄s + 6c₃ (closed form)
    // split [0, 1] where H″ is monotone, the roots of H″ where H′ is monotone. Returns their
    // number.
    template <class D, class DD>
    static int local_maxima(const std::array<double, 6>& c, const D& dH, const DD& ddH,
                            std::array<double, 8>& lo, std::array<double, 8>& hi) {
        double cuts3[4], cuts2[8], cuts1[16];
        int n3 = 0;
        cuts3[n3++] = 0.0;
        const double qa = 60.0 * c[5], qb = 24.0 * c[4], qc = 6.0 * c[3];
        double r[2] = {0.0, 0.0};
        int nr = 0;
        if (qa != 0.0) {
            const double disc = qb * qb - 4.0 * qa * qc;
            if (disc > 0.0) {
                const double qq = -0.5 * (qb + std::copysign(std::sqrt(disc), qb));
                r[nr++] = qq / qa;
                if (qq != 0.0) r[nr++] = qc / qq;
            }
        } else if (qb != 0.0) {
            r[nr++] = -qc / qb;
        }
        if (nr == 2 && r[0] > r[1]) std::swap(r[0], r[1]);
        for (int i = 0; i < nr; ++i)
            if (r[i] > 0.0 && r[i] < 1.0) cuts3[n3++] = r[i];
        cuts3[n3++] = 1.0;
        const int n2 = split_at_roots(ddH, cuts3, n3, cuts2);
        const int n1 = split_at_roots(dH, cuts2, n2, cuts1);
        int n = 0;
        for (int i = 0; i + 1 < n1 && n < 8; ++i)
            if (dH(cuts1[i]) > 0.0 && !(dH(cuts1[i + 1]) > 0.0)) {
                lo[static_cast<std::size_t>(n)] = cuts1[i];
                hi[static_cast<std::size_t>(n)] = cuts1[i + 1];
                ++n;
            }
        return n;
    }

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
        // dH(0) = d0 > 0 >= dH(1) = d1. At coarse steps the interpolant can have several local
        // maxima in one step: the maximum is the largest. The roots of dH are isolated exactly
        // (local_maxima); with one + → − change (the usual case) the root is found on [0, 1]
        // from the secant estimate, otherwise in each bracket.
        std::array<double, 8> lo{}, hi{};
        const int n = local_maxima(c, dH, ddH, lo, hi);
        double s = bracketed_root(dH, ddH, 0.0, 1.0, d0 / (d0 - d1));
        if (n > 1) {
            double best = -std::numeric_limits<double>::infinity();
            for (std::size_t k = 0; k < static_cast<std::size_t>(n); ++k) {
                const double ga = dH(lo[k]), gb = dH(hi[k]);
                const double r =
                    bracketed_root(dH, ddH, lo[k], hi[k], lo[k] + (hi[k] - lo[k]) * ga / (ga - gb));
                if (H(r) > best) {
                    best = H(r);
                    s = r;
                }
            }
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
