// Diagnostic "momentum": the per-step laws of the total linear momentum Σp_i and the angular
// momentum Σq_i×p_i, X_{n+1} = e^{−2ΔΓ} X_n (B Ex. 1.3), and the factor the method declares
// (B Table 3.1). The per-step part is MomentumLaws (below).
#pragma once

#include "diagnostics/capabilities.hpp"
#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"
#include "diagnostics/observer_part.hpp"
#include "diagnostics/series.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string_view>

namespace dampsym {

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

// The momenta X(z_{n−1}), X(z_n) and the scale S(z_{n−1}) of the step being measured.
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

// The laws of the linear momentum (with the method's table factor) and of the angular momentum at
// every step; with a series, the linear and angular law residuals and the linear measured factor.
template <class P>
class MomentumLaws {
public:
    MomentumLaws(const P& p, const PartContext& ctx)
        : p_(p), t0_(ctx.t0), h_(ctx.h), table_factor_(ctx.table_factor) {
        if (ctx.series_steps > 0) {
            lin_res_.emplace(ctx.series_steps);
            lin_factor_.emplace(ctx.series_steps);
            ang_res_.emplace(ctx.series_steps);
        }
    }

    void start(const Vec& z0) {
        mom_.start(p_, z0);
        lin_.initial_norm = mom_.lin_prev.norm();
        ang_.initial_norm = mom_.ang_prev.norm();
        lin_.scale_initial = mom_.lin_scale_prev;
        ang_.scale_initial = mom_.ang_scale_prev;
    }

    void operator()(std::int64_t n, double t, const Vec& z) {
        const double law = mom_.measure(p_, t0_, h_, n, z);
        vector_law(lin_, n, mom_.lin_prev, mom_.lin_now, mom_.lin_scale_prev, law, table_factor_);
        vector_law(ang_, n, mom_.ang_prev, mom_.ang_now, mom_.ang_scale_prev, law,
                   std::numeric_limits<double>::quiet_NaN());
        if (lin_res_) push_series(t, law);
        mom_.shift(p_, z);
    }

    const VectorLawStats& linear() const { return lin_; }
    const VectorLawStats& angular() const { return ang_; }

    void series(nlohmann::json& s) {
        if (!lin_res_) return;
        s["momentum.linear.law_res"] = lin_res_->to_json();
        s["momentum.linear.factor"] = lin_factor_->to_json();
        s["momentum.angular.law_res"] = ang_res_->to_json();
    }

private:
    static void vector_law(VectorLawStats& s, std::int64_t n, const Vec& prev, const Vec& now,
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

    void push_series(double t, double law) {
        const double nan = std::numeric_limits<double>::quiet_NaN();
        const auto residual = [&](const Vec& now, const Vec& prev, double scale) {
            return scale_defined(scale) ? law_residual_abs(now, prev, law) / scale : nan;
        };
        lin_res_->push(t, residual(mom_.lin_now, mom_.lin_prev, mom_.lin_scale_prev));
        ang_res_->push(t, residual(mom_.ang_now, mom_.ang_prev, mom_.ang_scale_prev));
        lin_factor_->push(
            t, measured_factor(mom_.lin_now, mom_.lin_prev, mom_.lin_scale_prev).value_or(nan));
    }

    const P& p_;
    double t0_, h_, table_factor_;
    MomentumSteps<P> mom_;
    VectorLawStats lin_, ang_;
    std::optional<MinMaxDecimator> lin_res_, lin_factor_, ang_res_;
};

struct MomentumDiagnostic {
    static constexpr std::string_view name = "momentum";
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = HasMomentum<P>;
    template <class P>
    using Part = MomentumLaws<P>;
    // Its metrics of one run from the run's view (harness/run/view.hpp: the problem, the case's
    // facts, the recorder and grid, the method, h, the final state, the counters).
    template <class V>
    static json produce(const V& run);
};
DAMPSYM_DIAGNOSTIC(MomentumDiagnostic, 100);

// B Table 3.1 factor of Σp per step the method declares (claims, core/method.hpp) at a constant
// damping step gh = γh; NaN if it declares none or the damping is not constant.
double table_momentum_factor(unsigned claims, bool constant_gamma, double gh);

// linear_law: whether Σp has a law (Kepler's fixed centre breaks it); law_factor e^{−2ΔΓ}.
json momentum_metrics(const VectorLawStats& linear, const VectorLawStats& angular, bool linear_law,
                      double table_factor, double law_factor);

template <class P>
constexpr bool has_linear_momentum_law() {
    if constexpr (requires { P::linear_momentum_law; })
        return P::linear_momentum_law;
    else
        return true;
}

template <class V>
json MomentumDiagnostic::produce(const V& run) {
    using P = typename V::Problem;
    const MomentumLaws<P>& laws = run.rec.template part<MomentumDiagnostic>();
    return momentum_metrics(laws.linear(), laws.angular(), has_linear_momentum_law<P>(),
                            run.table_factor, std::exp(-2.0 * run.problem.dGamma(run.t0, run.h)));
}

} // namespace dampsym
