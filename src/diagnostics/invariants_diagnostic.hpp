// Diagnostic "invariants": the per-step and global conformal laws I_{n+1} = e^{−2ΔΓ} I_n of the
// problem's invariants (B Def. 2.3), residuals on their declared scales (docs/conventions.md). The
// per-step part is InvariantLaws (below): the residuals and ratios of every step, their maxima and
// least-squares slopes for the report and, with --figures, their series.
#pragma once

#include "core/problem.hpp"
#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"
#include "diagnostics/observer_part.hpp"
#include "diagnostics/series.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
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
    // Whether r = e^{2Γ} I / I_0 − 1 is resolved at a state of scale S, with
    // log u = log ε + log S − log|I_0| + 2Γ (no overflow for long runs).
    static bool ratio_resolved(double scale, double i0, double two_gamma, double r) {
        if (!scale_defined(scale) || i0 == 0.0) return false;
        const double log_u = std::log(std::numeric_limits<double>::epsilon()) + std::log(scale) -
                             std::log(std::abs(i0)) + two_gamma;
        return log_u <= std::log(ratio_abs_resolution) ||
               log_u <= std::log(ratio_rel_resolution * std::abs(r));
    }
};

// The per-step laws of the problem's invariants, I_{n+1} = e^{−2f_kΔΓ} I_n (step) and
// I_n = e^{−2f_kΓ(t_n)} I_0 (global), f_k the invariant's rate factor (1 but for a few PDE
// invariants, core/problem.hpp); with a series, the step residual and the ratio deviation of
// every step.
template <class P>
class InvariantLaws {
public:
    static constexpr std::size_t max_invariants = 8;
    InvariantLaws(const P& p, const PartContext& ctx) : p_(p), t0_(ctx.t0), h_(ctx.h) {
        stats_.assign(P::invariant_names.size(), InvariantStats{});
        for (std::size_t k = 0; ctx.series_steps > 0 && k < stats_.size(); ++k) {
            res_series_.emplace_back(ctx.series_steps);
            ratio_series_.emplace_back(ctx.series_steps);
        }
    }

    void start(const Vec& z0) {
        p_.invariants(t0_, z0, prev_.data());
        p_.invariant_scales(t0_, z0, scale_prev_.data());
        inv0_ = prev_;
        for (std::size_t k = 0; k < stats_.size(); ++k) {
            stats_[k].scale_initial = scale_prev_[k];
            if (!scale_defined(scale_prev_[k])) stats_[k].undefined_at(0);
            if (!InvariantStats::ratio_resolved(scale_prev_[k], inv0_[k], 0.0, 0.0)) {
                stats_[k].ratio_defined = false;
                stats_[k].first_unresolved_ratio = 0;
            }
        }
    }

    void operator()(std::int64_t n, double t, const Vec& z) {
        std::array<double, max_invariants> now{}, scale_now{};
        p_.invariants(t, z, now.data());
        p_.invariant_scales(t, z, scale_now.data());
        const double dG = p_.dGamma(time_at(t0_, h_, n - 1), h_);
        const double G = p_.Gamma(t) - p_.Gamma(t0_);
        for (std::size_t k = 0; k < stats_.size(); ++k) {
            const double f = invariant_rate_factor<P>(k);
            step_law(k, n, t, now[k], std::exp(-2.0 * f * dG));
            global_law(k, n, t, now[k], scale_now[k], 2.0 * f * G);
            prev_[k] = now[k];
            scale_prev_[k] = scale_now[k];
        }
    }

    const std::vector<InvariantStats>& stats() const { return stats_; }
    double initial(std::size_t k) const { return inv0_[k]; }

    void series(nlohmann::json& s) {
        for (std::size_t k = 0; k < res_series_.size(); ++k) {
            const std::string name(P::invariant_names[k]);
            s["invariants." + name + ".step_res"] = res_series_[k].to_json();
            s["invariants." + name + ".ratio_dev"] = ratio_series_[k].to_json();
        }
    }

private:
    // |I_{n+1} − e^{−2ΔΓ} I_n| on the scale of the earlier state
    void step_law(std::size_t k, std::int64_t n, double t, double now, double decay_step) {
        InvariantStats& s = stats_[k];
        const double abs = std::abs(now - decay_step * prev_[k]);
        const double res = abs / scale_prev_[k];
        if (!res_series_.empty())
            res_series_[k].push(
                t, scale_defined(scale_prev_[k]) ? res : std::numeric_limits<double>::quiet_NaN());
        if (!scale_defined(scale_prev_[k]) || !std::isfinite(res)) {
            s.undefined_at(n - 1);
            return;
        }
        if (res > s.max_step_res || n == 1) s.scale_at_max = scale_prev_[k];
        s.max_step_res = std::max(s.max_step_res, res);
        s.last_step_res = res;
        s.max_step_abs = std::max(s.max_step_abs, abs);
    }

    // (I_n − e^{−2Γ} I_0) / S(z_n) and e^{2Γ} I_n / I_0 − 1, both in log form so that long runs do
    // not underflow
    void global_law(std::size_t k, std::int64_t n, double t, double now, double scale_now,
                    double two_gamma) {
        InvariantStats& s = stats_[k];
        const double x = t - t0_;
        if (!scale_defined(scale_now) || !std::isfinite(now)) {
            s.undefined_at(n);
        } else {
            double expected = 0.0;
            if (inv0_[k] != 0.0)
                expected = std::copysign(
                    std::exp(std::log(std::abs(inv0_[k])) - two_gamma - std::log(scale_now)),
                    inv0_[k]);
            const double g = now / scale_now - expected;
            s.max_global_res = std::max(s.max_global_res, std::abs(g));
            s.sx += x, s.sy += g, s.sxx += x * x, s.sxy += x * g, s.count += 1.0;
        }
        if (!s.ratio_defined && ratio_series_.empty()) return;
        double ratio = 0.0;
        if (now != 0.0) {
            const double sign = (now > 0) == (inv0_[k] > 0) ? 1.0 : -1.0;
            ratio =
                sign * std::exp(std::log(std::abs(now)) - std::log(std::abs(inv0_[k])) + two_gamma);
        }
        const double r = ratio - 1.0;
        const bool was_defined = s.ratio_defined;
        if (was_defined && (!std::isfinite(r) ||
                            !InvariantStats::ratio_resolved(scale_now, inv0_[k], two_gamma, r))) {
            s.ratio_defined = false;
            s.first_unresolved_ratio = n;
        }
        // The series ends where the metric's ratio does: from the first point whose round-off
        // e^{2Γ} ε S(z_n) / |I_0| is not resolved (I_0 = 0, a state at rest or an indefinite H_γ
        // through 0, from the start) it is skipped as non-finite. After it the ratio is the
        // run's round-off times e^{2Γ}: a strongly damped oscillator (γ = 50) drew ±1e300.
        if (!ratio_series_.empty())
            ratio_series_[k].push(t,
                                  s.ratio_defined ? r : std::numeric_limits<double>::quiet_NaN());
        if (!was_defined) return;
        s.max_ratio_dev = std::max(s.max_ratio_dev, std::abs(r));
        s.rx += x, s.ry += r, s.rxx += x * x, s.rxy += x * r, s.rcount += 1.0;
    }

    const P& p_;
    double t0_, h_;
    std::array<double, max_invariants> prev_{}, inv0_{}, scale_prev_{};
    std::vector<InvariantStats> stats_;
    std::vector<MinMaxDecimator> res_series_, ratio_series_;
};

struct InvariantsDiagnostic {
    static constexpr std::string_view name = "invariants";
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = true; // a check on it needs invariants (case.cpp)
    template <class P>
    using Part = InvariantLaws<P>;
    // Its metrics of one run from the run's view (harness/run/view.hpp: the problem, the case's
    // facts, the recorder and grid, the method, h, the final state, the counters).
    template <class V>
    static json produce(const V& run);
};
DAMPSYM_DIAGNOSTIC(InvariantsDiagnostic, 30);

// names / scale_defs: the problem's invariant_names and invariant_scale_defs; initial: I_k(z_0).
json invariant_metrics(const std::vector<InvariantStats>& stats,
                       const std::vector<std::string_view>& names,
                       const std::vector<std::string_view>& scale_defs,
                       const std::vector<double>& initial);

template <class V>
json InvariantsDiagnostic::produce(const V& run) {
    using P = typename V::Problem;
    const InvariantLaws<P>& laws = run.rec.template part<InvariantsDiagnostic>();
    std::vector<double> initial;
    for (std::size_t k = 0; k < P::invariant_names.size(); ++k) initial.push_back(laws.initial(k));
    return invariant_metrics(laws.stats(), {P::invariant_names.begin(), P::invariant_names.end()},
                             {P::invariant_scale_defs.begin(), P::invariant_scale_defs.end()},
                             initial);
}

} // namespace dampsym
