// The observer attached to the step loop when a case asks for trajectory diagnostics. Each part is
// enabled only when requested: states on the output grid (error, energy), per-step conformal laws
// of the problem's invariants (invariants: I_{n+1} = e^{−2(Γ(t_{n+1})−Γ(t_n))} I_n, B Def. 2.3),
// and oscillation maxima of q for d(t) = ln(max U(t)) + Γ(t) (dissipation-drift, F(4.4)).
// Everything is streamed; nothing grows with the number of steps except the requested grid.
#pragma once

#include "core/types.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace dampsym {

struct InvariantStats {
    double max_step_rel = 0.0;   // max_n |I_{n+1} − e^{−2ΔΓ} I_n| / |I_n|
    double last_step_rel = 0.0;  // the same at the last step
    double max_global_rel = 0.0; // max_n |I_n − e^{−2Γ(t_n)} I_0| / |e^{−2Γ(t_n)} I_0|
    // Least-squares sums for the drift slope of I_n/(e^{−2Γ(t_n)} I_0) − 1 against t.
    double sx = 0, sy = 0, sxx = 0, sxy = 0, count = 0;
    double drift_slope() const {
        const double den = count * sxx - sx * sx;
        return den > 0.0 ? (count * sxy - sx * sy) / den : 0.0;
    }
};

struct Maximum {
    double t;
    double d; // ln(q_max) + Γ(t_max)
};

template <class P>
class Recorder {
public:
    static constexpr int max_invariants = 8;

    Recorder(const P& problem, double t0, double h) : p_(problem), t0_(t0), h_(h) {}

    void record_grid(std::int64_t stride, std::int64_t points) {
        stride_ = stride;
        grid_.resize(p_.dim(), points);
    }
    void track_invariants() { inv_on_ = true; }
    void track_maxima() { max_on_ = true; }

    void start(const Vec& z0) {
        if (stride_ > 0) grid_.col(0) = z0;
        if (inv_on_) {
            p_.invariants(t0_, z0, inv_prev_.data());
            inv0_ = inv_prev_;
            stats_.assign(P::invariant_names.size(), InvariantStats{});
        }
        if (max_on_) {
            q_prev2_ = std::numeric_limits<double>::quiet_NaN();
            q_prev1_ = z0[0];
        }
    }

    void operator()(std::int64_t n, double t, const Vec& z) {
        if (stride_ > 0 && n % stride_ == 0) grid_.col(n / stride_) = z;
        if (inv_on_) invariants_step(n, t, z);
        if (max_on_) maxima_step(n, z[0]);
    }

    const Mat& grid() const { return grid_; }
    const std::vector<InvariantStats>& invariant_stats() const { return stats_; }
    const std::vector<Maximum>& maxima() const { return maxima_; }

private:
    void invariants_step(std::int64_t n, double t, const Vec& z) {
        std::array<double, max_invariants> now{};
        p_.invariants(t, z, now.data());
        const double decay_step = std::exp(-2.0 * p_.dGamma(time_at(t0_, h_, n - 1), h_));
        const double two_gamma = 2.0 * (p_.Gamma(t) - p_.Gamma(t0_));
        for (std::size_t k = 0; k < stats_.size(); ++k) {
            InvariantStats& s = stats_[k];
            const double expected = decay_step * inv_prev_[k];
            const double rel =
                std::abs(now[k] - expected) / std::max(std::abs(inv_prev_[k]), 1e-300);
            s.max_step_rel = std::max(s.max_step_rel, rel);
            s.last_step_rel = rel;
            // ratio I_n / (e^{−2Γ} I_0) in log form so that long runs do not underflow
            double ratio = 0.0;
            if (now[k] != 0.0 && inv0_[k] != 0.0) {
                const double sign = (now[k] > 0) == (inv0_[k] > 0) ? 1.0 : -1.0;
                ratio = sign * std::exp(std::log(std::abs(now[k])) - std::log(std::abs(inv0_[k])) +
                                        two_gamma);
            }
            const double g = ratio - 1.0;
            s.max_global_rel = std::max(s.max_global_rel, std::abs(g));
            const double x = t - t0_;
            s.sx += x;
            s.sy += g;
            s.sxx += x * x;
            s.sxy += x * g;
            s.count += 1.0;
            inv_prev_[k] = now[k];
        }
    }

    void maxima_step(std::int64_t n, double q) {
        // q_prev1_ is a local maximum of the sequence: parabolic vertex through the three points.
        if (q_prev1_ > q_prev2_ && q_prev1_ >= q && q_prev1_ > 0.0) {
            const double y0 = q_prev2_, y1 = q_prev1_, y2 = q;
            const double curv = y0 - 2.0 * y1 + y2;
            double offset = 0.0, peak = y1;
            if (curv < 0.0) {
                offset = 0.5 * (y0 - y2) / curv; // in units of h, within [−½, ½]
                peak = y1 - 0.125 * (y0 - y2) * (y0 - y2) / curv;
            }
            const double tm = time_at(t0_, h_, n - 1) + offset * h_;
            maxima_.push_back({tm, std::log(peak) + p_.Gamma(tm)});
        }
        q_prev2_ = q_prev1_;
        q_prev1_ = q;
    }

    const P& p_;
    double t0_, h_;
    std::int64_t stride_ = 0;
    Mat grid_;
    bool inv_on_ = false, max_on_ = false;
    std::array<double, max_invariants> inv_prev_{}, inv0_{};
    std::vector<InvariantStats> stats_;
    double q_prev2_ = 0.0, q_prev1_ = 0.0;
    std::vector<Maximum> maxima_;
};

} // namespace dampsym
