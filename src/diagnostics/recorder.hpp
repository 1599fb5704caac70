// The observer attached to the step loop when a case asks for trajectory diagnostics. Each part is
// enabled only when requested: states on the output grid (error, energy), per-step conformal laws
// of the problem's invariants (invariants: I_{n+1} = e^{−2(Γ(t_{n+1})−Γ(t_n))} I_n, B Def. 2.3),
// and oscillation maxima of q for d(t) = ln(max U(t)) + Γ(t) (dissipation-drift, F(4.4)).
// Everything is streamed; nothing grows with the number of steps except the requested grid, and
// not even that when the grid's only readers reduce it on the fly (a GridSink:
// harness/run/grid_stream.hpp).
#pragma once

#include "core/types.hpp"
#include "diagnostics/capabilities.hpp"
#include "diagnostics/maxima.hpp"
#include "diagnostics/metric_json.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string_view>
#include <vector>

namespace dampsym {

// Law residuals are measured against a scale S(z) ≥ |I(z)| that does not vanish with the invariant
// (the problem declares it next to the invariant: invariant_scales; docs/conventions.md, "Law
// residuals and their scales"). A residual is undefined where its scale is not a normal positive
// number (scale_defined, metric_json.hpp: the state has underflowed to zero, or is not finite); one
// undefined point makes the run's metric undefined (reported with its reason, and a check on it
// fails with that reason).

struct InvariantStats {
    double max_step_res = 0.0;   // max_n |I_{n+1} − e^{−2ΔΓ} I_n| / S(z_n)
    double last_step_res = 0.0;  // the same at the last step
    double max_step_abs = 0.0;   // max_n |I_{n+1} − e^{−2ΔΓ} I_n|
    double scale_at_max = 0.0;   // S(z_n) at the step of max_step_res
    double scale_initial = 0.0;  // S(z_0)
    double max_global_res = 0.0; // max_n |I_n − e^{−2Γ(t_n)} I_0| / S(z_n)
    std::int64_t undefined_steps = 0, first_undefined_step = -1; // S(z_n) not a normal number
    // The invariant relative to its law's prediction, r_n = e^{2Γ(t_n)} I_n / I_0 − 1 (F's
    // conformal energy ratio). Evaluating I_n costs a round-off u_n = ε S(z_n) / |e^{−2Γ(t_n)} I_0|
    // in r_n, which is not small when I_0 is round-off on its scale or when the terms of an
    // indefinite invariant outgrow the law's value (over-damped H_γ: S(z_n) e^{2Γ} grows). r_n is
    // defined only where it is resolved: u_n ≤ 1e-8, or u_n ≤ 1e-2 |r_n| (a large deviation known
    // to two digits); one unresolved point makes the ratio metrics undefined.
    static constexpr double ratio_abs_resolution = 1e-8, ratio_rel_resolution = 1e-2;
    bool ratio_defined = true;
    std::int64_t first_unresolved_ratio = -1;
    double max_ratio_dev = 0.0; // max_n |e^{2Γ(t_n)} I_n / I_0 − 1|
    // Least-squares sums for the slopes against t of (I_n − e^{−2Γ(t_n)} I_0) / S(z_n) (g) and of
    // e^{2Γ(t_n)} I_n / I_0 − 1 (r).
    double sx = 0, sy = 0, sxx = 0, sxy = 0, count = 0;
    double rx = 0, ry = 0, rxx = 0, rxy = 0, rcount = 0;
    static double slope(double n, double x, double y, double xx, double xy) {
        const double den = n * xx - x * x;
        return den > 0.0 ? (n * xy - x * y) / den : 0.0;
    }
    double global_res_slope() const { return slope(count, sx, sy, sxx, sxy); }
    double ratio_dev_slope() const { return slope(rcount, rx, ry, rxx, rxy); }
    void undefined_at(std::int64_t n) {
        if (undefined_steps++ == 0) first_undefined_step = n;
    }
};

// Per-step conformal law of a vector quantity X (total linear or angular momentum):
// law: X_{n+1} = e^{−2ΔΓ} X_n (B Ex. 1.3); table: X_{n+1} = f X_n with the factor f the method
// declares (B Table 3.1), when it declares one. Residuals are ‖·‖₂ on the scale S(z_n) the problem
// declares (Σ‖p_i‖ and Σ‖q_i‖‖p_i‖: linear_momentum_scale, angular_momentum_scale). The measured
// factor X_{n+1}·X_n/‖X_n‖² is a ratio to ‖X_n‖ itself: it is defined only where
// ‖X_n‖ ≥ factor_floor · S(z_n) (below that its round-off, ≈ ε S/‖X_n‖, exceeds ~1e-8).
struct VectorLawStats {
    static constexpr double factor_floor = 1e-8;
    double max_law_res = 0.0, last_law_res = 0.0;
    double max_table_res = 0.0; // only with a table factor
    double max_law_abs = 0.0;   // max_n ‖X_{n+1} − e^{−2ΔΓ} X_n‖₂
    double first_factor = std::numeric_limits<double>::quiet_NaN(); // X_1·X_0/‖X_0‖²
    double max_factor_dev = 0.0; // max_n |X_{n+1}·X_n/‖X_n‖² − f| / f (f = table, else law)
    double initial_norm = 0.0;   // ‖X_0‖₂
    double scale_initial = 0.0;  // S(z_0)
    double scale_at_max = 0.0;   // S(z_n) at the step of max_law_res
    std::int64_t undefined_steps = 0, first_undefined_step = -1; // S(z_n) not a normal number
    std::int64_t factor_undefined_steps = 0, first_factor_undefined_step = -1;
};

// The momenta X(z_{n−1}), X(z_n) and the scale S(z_{n−1}) of the step being measured, stepped by
// the recorder (statistics) and the figure observer (series) alike: one copy of the law's
// factor e^{−2ΔΓ} over step n, of its residual and of the measured factor.
template <class P>
struct MomentumSteps {
    Vec lin_prev, lin_now, ang_prev, ang_now;
    double lin_scale_prev = 0.0, ang_scale_prev = 0.0;

    void start(const P& p, const Vec& z0) {
        const int k = p.space_dim() == 3 ? 3 : 1;
        lin_prev.resize(p.space_dim());
        lin_now.resize(p.space_dim());
        ang_prev.resize(k);
        ang_now.resize(k);
        p.linear_momentum(z0, lin_prev);
        p.angular_momentum(z0, ang_prev);
        lin_scale_prev = p.linear_momentum_scale(z0);
        ang_scale_prev = p.angular_momentum_scale(z0);
    }
    // The momenta at z_n, the end of step n (from t_{n−1} = t0 + (n−1)h); returns the law's factor
    // e^{−2ΔΓ} over that step (B Ex. 1.3).
    double measure(const P& p, double t0, double h, std::int64_t n, const Vec& z) {
        p.linear_momentum(z, lin_now);
        p.angular_momentum(z, ang_now);
        return std::exp(-2.0 * p.dGamma(time_at(t0, h, n - 1), h));
    }
    void shift(const P& p, const Vec& z) {
        lin_prev.swap(lin_now);
        ang_prev.swap(ang_now);
        lin_scale_prev = p.linear_momentum_scale(z);
        ang_scale_prev = p.angular_momentum_scale(z);
    }
};

// ‖X_n − f X_{n−1}‖₂, a law's residual before its scale.
inline double law_residual_abs(const Vec& now, const Vec& prev, double f) {
    return (now - f * prev).norm();
}

// The factor X_n·X_{n−1}/‖X_{n−1}‖² a step applied, where ‖X_{n−1}‖ is resolved on the scale
// (VectorLawStats::factor_floor) and the scale is defined; empty otherwise.
inline std::optional<double> measured_factor(const Vec& now, const Vec& prev, double scale) {
    const double norm2 = prev.squaredNorm();
    if (!(std::sqrt(norm2) >= VectorLawStats::factor_floor * scale) || !scale_defined(scale))
        return std::nullopt;
    return now.dot(prev) / norm2;
}

// Energy balance residual R(t_n) = |D_t H_n − Ḣ_n| with the 8th-order central difference D_t and
// the exact law Ḣ = −2γ(t) p·∇T(p) (B(3.4): for the pendulum Ḣ = −2γp²).
struct EnergyBalanceStats {
    double max = 0.0, last = 0.0, sum = 0.0, max_rate = 0.0;
    std::int64_t count = 0;
};

// A reader of the output grid that reduces it on the fly (harness/run/grid_stream.hpp): given each
// grid point i >= 1 (the state at step i × stride) as the run reaches it, instead of a stored grid.
class GridSink {
public:
    virtual void point(Eigen::Index i, const Vec& z) = 0;

protected:
    ~GridSink() = default;
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
    // Grid points i >= 1 to `sink` (not stored; the sink must outlive the run).
    void stream_grid(std::int64_t stride, GridSink* sink) {
        sink_stride_ = stride;
        sink_ = sink;
    }
    void track_invariants() { inv_on_ = true; }
    void track_maxima() { max_on_ = true; }
    // table_factor: the method's declared per-step factor of Σp (NaN if it declares none).
    void track_momentum(double table_factor) {
        mom_on_ = true;
        table_factor_ = table_factor;
    }
    void track_energy_balance() { eb_on_ = true; }
    // The part a diagnostic names as its observer_part (diagnostics/diagnostic.hpp): "invariants",
    // "maxima", "momentum" (with the method's table factor) or "energy-balance".
    void enable(std::string_view part, double table_factor) {
        if (part == "invariants") track_invariants();
        if (part == "maxima") track_maxima();
        if (part == "momentum") track_momentum(table_factor);
        if (part == "energy-balance") track_energy_balance();
    }

    void start(const Vec& z0) {
        if (stride_ > 0) grid_.col(0) = z0;
        if (inv_on_) {
            p_.invariants(t0_, z0, inv_prev_.data());
            p_.invariant_scales(t0_, z0, scale_prev_.data());
            inv0_ = inv_prev_;
            stats_.assign(P::invariant_names.size(), InvariantStats{});
            for (std::size_t k = 0; k < stats_.size(); ++k) {
                stats_[k].scale_initial = scale_prev_[k];
                if (!scale_defined(scale_prev_[k])) stats_[k].undefined_at(0);
                if (!ratio_resolved(scale_prev_[k], inv0_[k], 0.0, 0.0)) {
                    stats_[k].ratio_defined = false;
                    stats_[k].first_unresolved_ratio = 0;
                }
            }
        }
        if (max_on_) {
            if constexpr (HasOneDofMaxima<P>) {
                finder_.emplace(p_, t0_);
                finder_->feed(t0_, z0);
            }
        }
        if constexpr (HasMomentum<P>) {
            if (mom_on_) {
                mom_.start(p_, z0);
                lin_.initial_norm = mom_.lin_prev.norm();
                ang_.initial_norm = mom_.ang_prev.norm();
                lin_.scale_initial = mom_.lin_scale_prev;
                ang_.scale_initial = mom_.ang_scale_prev;
            }
        }
        if constexpr (HasEnergyBalance<P>) {
            if (eb_on_) {
                grad_t_.resize(p_.n());
                eb_push(0, t0_, z0);
            }
        }
    }

    void operator()(std::int64_t n, double t, const Vec& z) {
        if (stride_ > 0 && n % stride_ == 0) grid_.col(n / stride_) = z;
        if (sink_ && n % sink_stride_ == 0) sink_->point(n / sink_stride_, z);
        if (inv_on_) invariants_step(n, t, z);
        if constexpr (HasOneDofMaxima<P>)
            if (max_on_) finder_->feed(t, z);
        if constexpr (HasMomentum<P>)
            if (mom_on_) momentum_step(n, z);
        if constexpr (HasEnergyBalance<P>)
            if (eb_on_) eb_push(n, t, z);
    }

    const Mat& grid() const { return grid_; }
    const std::vector<InvariantStats>& invariant_stats() const { return stats_; }
    double initial_invariant(std::size_t k) const { return inv0_[k]; }
    std::vector<Maximum> maxima() const {
        return finder_ ? finder_->maxima() : std::vector<Maximum>{};
    }
    std::int64_t nonpositive_maxima() const { return finder_ ? finder_->nonpositive() : 0; }
    const VectorLawStats& linear_momentum_stats() const { return lin_; }
    const VectorLawStats& angular_momentum_stats() const { return ang_; }
    const EnergyBalanceStats& energy_balance_stats() const { return eb_; }

private:
    void vector_law(VectorLawStats& s, std::int64_t n, const Vec& prev, const Vec& now,
                    double scale, double law, double table) {
        if (!scale_defined(scale)) {
            if (s.undefined_steps++ == 0) s.first_undefined_step = n - 1;
        } else {
            const double abs = law_residual_abs(now, prev, law);
            const double res = abs / scale;
            if (res > s.max_law_res || n == 1) s.scale_at_max = scale;
            s.max_law_res = std::max(s.max_law_res, res);
            s.last_law_res = res;
            s.max_law_abs = std::max(s.max_law_abs, abs);
            if (!std::isnan(table))
                s.max_table_res =
                    std::max(s.max_table_res, law_residual_abs(now, prev, table) / scale);
        }
        const std::optional<double> measured = measured_factor(now, prev, scale);
        if (!measured) {
            if (s.factor_undefined_steps++ == 0) s.first_factor_undefined_step = n - 1;
            return;
        }
        const double factor = *measured;
        if (n == 1) s.first_factor = factor;
        const double f = std::isnan(table) ? law : table;
        s.max_factor_dev = std::max(s.max_factor_dev, std::abs(factor - f) / std::abs(f));
    }

    void momentum_step(std::int64_t n, const Vec& z) {
        if constexpr (HasMomentum<P>) {
            const double law = mom_.measure(p_, t0_, h_, n, z);
            vector_law(lin_, n, mom_.lin_prev, mom_.lin_now, mom_.lin_scale_prev, law,
                       table_factor_);
            vector_law(ang_, n, mom_.ang_prev, mom_.ang_now, mom_.ang_scale_prev, law,
                       std::numeric_limits<double>::quiet_NaN());
            mom_.shift(p_, z);
        }
    }

    // Sliding window of the last 9 energies; R at the window's centre once it is full.
    void eb_push(std::int64_t n, double t, const Vec& z) {
        if constexpr (HasEnergyBalance<P>) {
            const int nq = p_.n();
            const std::size_t slot = static_cast<std::size_t>(n % 9);
            eb_energy_[slot] = p_.energy(z);
            p_.grad_T(z.tail(nq), grad_t_);
            eb_rate_[slot] = -2.0 * p_.gamma_at(t) * z.tail(nq).dot(grad_t_);
            if (n < 8) return;
            static constexpr std::array<double, 4> c{4.0 / 5.0, -1.0 / 5.0, 4.0 / 105.0,
                                                     -1.0 / 280.0};
            const std::int64_t m = n - 4; // centre
            double d = 0.0;
            for (std::int64_t k = 4; k >= 1; --k)
                d += c[static_cast<std::size_t>(k - 1)] *
                     (eb_energy_[static_cast<std::size_t>((m + k) % 9)] -
                      eb_energy_[static_cast<std::size_t>((m - k) % 9)]);
            const double rate = eb_rate_[static_cast<std::size_t>(m % 9)];
            const double r = std::abs(d / h_ - rate);
            eb_.max = std::max(eb_.max, r);
            eb_.last = r;
            eb_.sum += r;
            eb_.max_rate = std::max(eb_.max_rate, std::abs(rate));
            ++eb_.count;
        }
    }

    void invariants_step(std::int64_t n, double t, const Vec& z) {
        std::array<double, max_invariants> now{}, scale_now{};
        p_.invariants(t, z, now.data());
        p_.invariant_scales(t, z, scale_now.data());
        const double dG = p_.dGamma(time_at(t0_, h_, n - 1), h_);
        const double G = p_.Gamma(t) - p_.Gamma(t0_);
        for (std::size_t k = 0; k < stats_.size(); ++k) {
            InvariantStats& s = stats_[k];
            // rate factor f_k (1 for all but a few PDE invariants; f = 1 gives the same bits)
            const double f = invariant_rate_factor<P>(k);
            const double decay_step = std::exp(-2.0 * f * dG);
            const double two_gamma = 2.0 * f * G;
            // step law on the scale of the earlier state
            const double abs = std::abs(now[k] - decay_step * inv_prev_[k]);
            const double res = abs / scale_prev_[k];
            if (!scale_defined(scale_prev_[k]) || !std::isfinite(res)) {
                s.undefined_at(n - 1);
            } else {
                if (res > s.max_step_res || n == 1) s.scale_at_max = scale_prev_[k];
                s.max_step_res = std::max(s.max_step_res, res);
                s.last_step_res = res;
                s.max_step_abs = std::max(s.max_step_abs, abs);
            }
            // global law (I_n − e^{−2Γ} I_0) / S(z_n); e^{−2Γ} I_0 / S(z_n) in log form so that
            // long runs do not underflow
            if (!scale_defined(scale_now[k]) || !std::isfinite(now[k])) {
                s.undefined_at(n);
            } else {
                double expected = 0.0;
                if (inv0_[k] != 0.0)
                    expected = std::copysign(
                        std::exp(std::log(std::abs(inv0_[k])) - two_gamma - std::log(scale_now[k])),
                        inv0_[k]);
                const double g = now[k] / scale_now[k] - expected;
                s.max_global_res = std::max(s.max_global_res, std::abs(g));
                const double x = t - t0_;
                s.sx += x;
                s.sy += g;
                s.sxx += x * x;
                s.sxy += x * g;
                s.count += 1.0;
            }
            // ratio I_n / (e^{−2Γ} I_0) in log form so that long runs do not underflow
            if (s.ratio_defined) {
                double ratio = 0.0;
                if (now[k] != 0.0) {
                    const double sign = (now[k] > 0) == (inv0_[k] > 0) ? 1.0 : -1.0;
                    ratio = sign * std::exp(std::log(std::abs(now[k])) -
                                            std::log(std::abs(inv0_[k])) + two_gamma);
                }
                const double r = ratio - 1.0;
                if (!std::isfinite(r) || !ratio_resolved(scale_now[k], inv0_[k], two_gamma, r)) {
                    s.ratio_defined = false;
                    s.first_unresolved_ratio = n;
                }
                s.max_ratio_dev = std::max(s.max_ratio_dev, std::abs(r));
                const double x = t - t0_;
                s.rx += x;
                s.ry += r;
                s.rxx += x * x;
                s.rxy += x * r;
                s.rcount += 1.0;
            }
            inv_prev_[k] = now[k];
            scale_prev_[k] = scale_now[k];
        }
    }

    // Whether r = e^{2Γ} I / I_0 − 1 is resolved at a state of scale S (InvariantStats), with
    // log u = log ε + log S − log|I_0| + 2Γ (no overflow for long runs).
    static bool ratio_resolved(double scale, double i0, double two_gamma, double r) {
        if (!scale_defined(scale) || i0 == 0.0) return false;
        const double log_u = std::log(std::numeric_limits<double>::epsilon()) + std::log(scale) -
                             std::log(std::abs(i0)) + two_gamma;
        return log_u <= std::log(InvariantStats::ratio_abs_resolution) ||
               log_u <= std::log(InvariantStats::ratio_rel_resolution * std::abs(r));
    }

    const P& p_;
    double t0_, h_;
    std::int64_t stride_ = 0;
    Mat grid_;
    std::int64_t sink_stride_ = 0;
    GridSink* sink_ = nullptr;
    bool inv_on_ = false, max_on_ = false, mom_on_ = false, eb_on_ = false;
    std::array<double, max_invariants> inv_prev_{}, inv0_{}, scale_prev_{};
    std::vector<InvariantStats> stats_;
    std::optional<MaximaFinder<P>> finder_;
    double table_factor_ = std::numeric_limits<double>::quiet_NaN();
    MomentumSteps<P> mom_;
    VectorLawStats lin_, ang_;
    std::array<double, 9> eb_energy_{}, eb_rate_{};
    Vec grad_t_;
    EnergyBalanceStats eb_;
};

} // namespace dampsym
