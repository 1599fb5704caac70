// The per-step series of a run's figures (harness/figures/series.hpp): invariant,
// momentum-law and energy-balance residual series and the orbit samples, with the formulas of
// diagnostics/recorder.hpp. Observes the measured run beside its Recorder (RunObserver), only
// with `dampsym run --figures`.
#pragma once

#include "core/integrate.hpp"
#include "core/problem_concepts.hpp"
#include "diagnostics/capabilities.hpp"
#include "diagnostics/metric_json.hpp"
#include "diagnostics/recorder.hpp"
#include "diagnostics/series.hpp"
#include "harness/case/case.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace dampsym::detail {

// Problems whose figures can draw the orbit (state samples over time) declare
// `static constexpr OrbitFigure figure_orbit` (core/problem.hpp; the others' states are too large
// or not drawn). Whether a case draws it is case_draws_orbit (harness/case/figures_key.hpp).
template <class P>
constexpr OrbitFigure figure_orbit_of() {
    if constexpr (requires { P::figure_orbit; })
        return P::figure_orbit;
    else
        return OrbitFigure::none;
}
template <class P>
constexpr bool figure_wants_orbit() {
    return figure_orbit_of<P>() != OrbitFigure::none;
}

template <class P>
class FigureStepObserver {
public:
    FigureStepObserver(const P& p, const CaseSpec& c, double h, std::int64_t n, bool orbit)
        : p_(p), t0_(c.t0), h_(h), n_(n), orbit_on_(orbit), orbit_(n + 1, orbit_samples(p.dim())) {
        inv_on_ = c.wants("invariants") && !P::invariant_names.empty();
        mom_on_ = c.wants("momentum");
        for (std::size_t k = 0; inv_on_ && k < P::invariant_names.size(); ++k) {
            inv_res_.emplace_back(n);
            inv_ratio_.emplace_back(n);
        }
        if (mom_on_) {
            lin_res_.emplace(n);
            lin_factor_.emplace(n);
            ang_res_.emplace(n);
        }
        if constexpr (HasEnergyBalance<P>) {
            if (c.wants("energy-balance")) eb_.emplace(n);
        }
    }
    bool needed() const { return inv_on_ || mom_on_ || orbit_on_ || eb_.has_value(); }

    void start(const Vec& z0) {
        if (inv_on_) {
            p_.invariants(t0_, z0, inv_prev_.data());
            p_.invariant_scales(t0_, z0, scale_prev_.data());
            inv0_ = inv_prev_;
        }
        if constexpr (HasMomentum<P>) {
            if (mom_on_) {
                mom_.start(p_, z0);
            }
        }
        z0_ = z0;
        sample(0, t0_, z0);
        if (eb_) eb_push(0, t0_, z0);
    }

    void operator()(std::int64_t n, double t, const Vec& z) {
        if (eb_) eb_push(n, t, z);
        if (inv_on_) invariants_step(n, t, z);
        if constexpr (HasMomentum<P>)
            if (mom_on_) momentum_step(n, t, z);
        sample(n, t, z);
    }

    nlohmann::json to_json() {
        using json = nlohmann::json;
        json s = json::object();
        for (std::size_t k = 0; k < inv_res_.size(); ++k) {
            const std::string name(P::invariant_names[k]);
            s["invariants." + name + ".step_res"] = inv_res_[k].to_json();
            s["invariants." + name + ".ratio_dev"] = inv_ratio_[k].to_json();
        }
        if (mom_on_ && lin_res_) {
            s["momentum.linear.law_res"] = lin_res_->to_json();
            s["momentum.linear.factor"] = lin_factor_->to_json();
            s["momentum.angular.law_res"] = ang_res_->to_json();
        }
        if (eb_) s["energy-balance.residual"] = eb_->to_json();
        if (!orbit_t_.empty()) {
            s["orbit"] = {{"t", orbit_t_}, {"states", orbit_z_}, {"stride", orbit_.stride()}};
            if (!orbit_ref_.empty())
                s["orbit_reference"] = {{"t", orbit_t_},
                                        {"states", orbit_ref_},
                                        {"stride", orbit_.stride()},
                                        {"exact", true}};
        }
        return s;
    }

private:
    void sample(std::int64_t n, double t, const Vec& z) {
        if constexpr (figure_wants_orbit<P>()) {
            if (!orbit_on_ || !orbit_.wants(n)) return;
            orbit_t_.push_back(t);
            orbit_z_.push_back(drawn(z));
            // the exact solution at the same times (a smooth reference orbit: the output grid's
            // reference may have few points per revolution)
            if constexpr (HasExactSolution<P>) {
                if (ref_.size() != z0_.size()) ref_.resize(z0_.size());
                p_.exact(t0_, z0_, t, ref_);
                orbit_ref_.push_back(drawn(ref_));
            }
        } else {
            (void)n, (void)t, (void)z;
        }
    }

    // A state as the figure draws it (drawn_value: 7 significant digits).
    static std::vector<double> drawn(const Vec& z) {
        std::vector<double> v(static_cast<std::size_t>(z.size()));
        for (Eigen::Index i = 0; i < z.size(); ++i)
            v[static_cast<std::size_t>(i)] = drawn_value(z[i]);
        return v;
    }

    // The formulas of Recorder::eb_push (recorder.hpp): R = |D_t H − Ḣ| at the window centre.
    void eb_push(std::int64_t n, double t, const Vec& z) {
        if constexpr (HasEnergyBalance<P>) {
            const int nq = p_.n();
            if (grad_t_.size() != nq) grad_t_.resize(nq);
            const std::size_t slot = static_cast<std::size_t>(n % 9);
            eb_energy_[slot] = p_.energy(z);
            p_.grad_T(z.tail(nq), grad_t_);
            eb_rate_[slot] = -2.0 * p_.gamma_at(t) * z.tail(nq).dot(grad_t_);
            if (n < 8) return;
            static constexpr std::array<double, 4> c{4.0 / 5.0, -1.0 / 5.0, 4.0 / 105.0,
                                                     -1.0 / 280.0};
            const std::int64_t m = n - 4;
            double d = 0.0;
            for (std::int64_t k = 4; k >= 1; --k)
                d += c[static_cast<std::size_t>(k - 1)] *
                     (eb_energy_[static_cast<std::size_t>((m + k) % 9)] -
                      eb_energy_[static_cast<std::size_t>((m - k) % 9)]);
            eb_->push(time_at(t0_, h_, m),
                      std::abs(d / h_ - eb_rate_[static_cast<std::size_t>(m % 9)]));
        } else {
            (void)n, (void)t, (void)z;
        }
    }

    // The formulas of Recorder::invariants_step (recorder.hpp).
    void invariants_step(std::int64_t n, double t, const Vec& z) {
        std::array<double, 8> now{}, scale_now{};
        p_.invariants(t, z, now.data());
        p_.invariant_scales(t, z, scale_now.data());
        const double dG = p_.dGamma(time_at(t0_, h_, n - 1), h_);
        const double G = p_.Gamma(t) - p_.Gamma(t0_);
        for (std::size_t k = 0; k < inv_res_.size(); ++k) {
            const double f = invariant_rate_factor<P>(k);
            const double decay_step = std::exp(-2.0 * f * dG);
            const double two_gamma = 2.0 * f * G;
            const double abs = std::abs(now[k] - decay_step * inv_prev_[k]);
            const double res = abs / scale_prev_[k];
            inv_res_[k].push(
                t, scale_defined(scale_prev_[k]) ? res : std::numeric_limits<double>::quiet_NaN());
            double ratio = 0.0;
            if (now[k] != 0.0) {
                const double sign = (now[k] > 0) == (inv0_[k] > 0) ? 1.0 : -1.0;
                ratio = sign * std::exp(std::log(std::abs(now[k])) - std::log(std::abs(inv0_[k])) +
                                        two_gamma);
            }
            inv_ratio_[k].push(t, ratio - 1.0);
            inv_prev_[k] = now[k];
            scale_prev_[k] = scale_now[k];
        }
    }

    // The formulas of Recorder::vector_law / momentum_step (recorder.hpp).
    void momentum_step(std::int64_t n, double t, const Vec& z) {
        if constexpr (HasMomentum<P>) {
            const double law = mom_.measure(p_, t0_, h_, n, z);
            const double nan = std::numeric_limits<double>::quiet_NaN();
            const auto residual = [&](const Vec& now, const Vec& prev, double scale) {
                return scale_defined(scale) ? law_residual_abs(now, prev, law) / scale : nan;
            };
            lin_res_->push(t, residual(mom_.lin_now, mom_.lin_prev, mom_.lin_scale_prev));
            ang_res_->push(t, residual(mom_.ang_now, mom_.ang_prev, mom_.ang_scale_prev));
            lin_factor_->push(
                t, measured_factor(mom_.lin_now, mom_.lin_prev, mom_.lin_scale_prev).value_or(nan));
            mom_.shift(p_, z);
        } else {
            (void)n, (void)t, (void)z;
        }
    }

    const P& p_;
    double t0_, h_;
    std::int64_t n_;
    bool inv_on_ = false, mom_on_ = false, orbit_on_ = false;
    std::array<double, 8> inv_prev_{}, inv0_{}, scale_prev_{};
    std::vector<MinMaxDecimator> inv_res_, inv_ratio_;
    std::optional<MinMaxDecimator> lin_res_, lin_factor_, ang_res_;
    MomentumSteps<P> mom_;
    std::optional<MinMaxDecimator> eb_;
    std::array<double, 9> eb_energy_{}, eb_rate_{};
    Vec grad_t_;
    StrideSampler orbit_;
    std::vector<double> orbit_t_;
    std::vector<std::vector<double>> orbit_z_, orbit_ref_;
    Vec z0_, ref_;
};

// The observer of a measured run that observes its steps: the Recorder of its diagnostics and,
// with --figures, the figure series, each only if present. One observer type per problem, so
// each kernel's observed step loop is instantiated once, with or without figures.
template <class P>
struct RunObserver {
    Recorder<P>* recorder;
    FigureStepObserver<P>* figures;
    void operator()(std::int64_t n, double t, const Vec& z) {
        if (recorder) (*recorder)(n, t, z);
        if (figures) (*figures)(n, t, z);
    }
};

} // namespace dampsym::detail
