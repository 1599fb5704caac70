// What a run keeps for its figures with `dampsym run --figures` (issue 14; the file format is in
// docs/reports.md, "Series files"). Called from one hook in TypedCase::integrate_with and one in
// TypedCase::series() (typed_case.hpp), and only when figures are on: without --figures nothing
// here runs, so the measured run, its bare-loop timing and every report number are untouched.
//
// Per-step series come from a SEPARATE pass with its own stepper (like the conformal-symplectic
// diagnostic): the measured run keeps its observers and its wall time. They reproduce the formulas
// of diagnostics/recorder.hpp and conformal_symplectic.hpp exactly, so the maximum of a decimated
// series equals the maximum the report states (verify/figures/test_figure_data.py checks this).
// Series on the output grid (state error, energy error and change, temperature, Poincaré points)
// are read from the measured run's grid and the case's reference, which the diagnostics used.
#pragma once

#include "core/integrate.hpp"
#include "diagnostics/capabilities.hpp"
#include "diagnostics/conformal_symplectic.hpp"
#include "diagnostics/maxima.hpp"
#include "diagnostics/recorder.hpp"
#include "diagnostics/series.hpp"
#include "diagnostics/stability.hpp"
#include "harness/case.hpp"
#include "harness/registry.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <optional>
#include <string_view>
#include <vector>

namespace dampsym::detail {

// Problems whose figures include the orbit (state samples over time).
template <class P>
constexpr bool figure_wants_orbit() {
    constexpr std::string_view id = P::id;
    return id == "kepler" || id == "lotka-volterra" || id == "outer-solar-system" ||
           id == "pendulum" || id == "rigid-body" || id == "oscillator" || id == "hill";
}

// Whether run (d = index in the ladder) keeps step series: every run of a case with at most two
// step sizes; on a longer ladder (a convergence case) only the smallest step size.
inline bool figure_series_for_dt(const CaseSpec& c, std::size_t d) {
    if (c.dts.size() <= 2) return true;
    for (double h : c.dts)
        if (h < c.dts[d]) return false;
    return true;
}

template <class P>
class FigureStepObserver {
public:
    FigureStepObserver(const P& p, const CaseSpec& c, double h, std::int64_t n, bool orbit)
        : p_(p), t0_(c.t0), h_(h), n_(n), orbit_on_(orbit), orbit_(n + 1) {
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
                const int k = p_.space_dim() == 3 ? 3 : 1;
                lin_prev_.resize(p_.space_dim());
                lin_now_.resize(p_.space_dim());
                ang_prev_.resize(k);
                ang_now_.resize(k);
                p_.linear_momentum(z0, lin_prev_);
                p_.angular_momentum(z0, ang_prev_);
                lin_scale_prev_ = p_.linear_momentum_scale(z0);
                ang_scale_prev_ = p_.angular_momentum_scale(z0);
            }
        }
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
        if (!orbit_t_.empty())
            s["orbit"] = {{"t", orbit_t_}, {"states", orbit_z_}, {"stride", orbit_.stride()}};
        return s;
    }

private:
    void sample(std::int64_t n, double t, const Vec& z) {
        if constexpr (figure_wants_orbit<P>()) {
            if (!orbit_on_ || !orbit_.wants(n)) return;
            orbit_t_.push_back(t);
            std::vector<double> v(static_cast<std::size_t>(z.size()));
            for (Eigen::Index i = 0; i < z.size(); ++i) v[static_cast<std::size_t>(i)] = z[i];
            orbit_z_.push_back(std::move(v));
        } else {
            (void)n, (void)t, (void)z;
        }
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
        const double decay_step = std::exp(-2.0 * p_.dGamma(time_at(t0_, h_, n - 1), h_));
        const double two_gamma = 2.0 * (p_.Gamma(t) - p_.Gamma(t0_));
        for (std::size_t k = 0; k < inv_res_.size(); ++k) {
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
            const double law = std::exp(-2.0 * p_.dGamma(time_at(t0_, h_, n - 1), h_));
            p_.linear_momentum(z, lin_now_);
            p_.angular_momentum(z, ang_now_);
            const double nan = std::numeric_limits<double>::quiet_NaN();
            lin_res_->push(t, scale_defined(lin_scale_prev_)
                                  ? (lin_now_ - law * lin_prev_).norm() / lin_scale_prev_
                                  : nan);
            ang_res_->push(t, scale_defined(ang_scale_prev_)
                                  ? (ang_now_ - law * ang_prev_).norm() / ang_scale_prev_
                                  : nan);
            const double norm2 = lin_prev_.squaredNorm();
            const bool factor_defined =
                std::sqrt(norm2) >= VectorLawStats::factor_floor * lin_scale_prev_ &&
                scale_defined(lin_scale_prev_);
            lin_factor_->push(t, factor_defined ? lin_now_.dot(lin_prev_) / norm2 : nan);
            lin_prev_.swap(lin_now_);
            ang_prev_.swap(ang_now_);
            lin_scale_prev_ = p_.linear_momentum_scale(z);
            ang_scale_prev_ = p_.angular_momentum_scale(z);
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
    Vec lin_prev_, lin_now_, ang_prev_, ang_now_;
    double lin_scale_prev_ = 0.0, ang_scale_prev_ = 0.0;
    std::optional<MinMaxDecimator> eb_;
    std::array<double, 9> eb_energy_{}, eb_rate_{};
    Vec grad_t_;
    StrideSampler orbit_;
    std::vector<double> orbit_t_;
    std::vector<std::vector<double>> orbit_z_;
};

// E_n / (e^{−2ΔΓ_n} √d) per step: the loop of conformal_symplectic_defect
// (conformal_symplectic.hpp) with a decimated series instead of its maxima.
template <class K, class P>
nlohmann::json conformal_symplectic_series(const P& problem, const MethodInfo& info,
                                           const CaseSpec& c, double h, std::int64_t n) {
    if constexpr (!is_canonical_problem<P>() || !kernel_has_step_jacobian<K>()) {
        (void)problem, (void)info, (void)c, (void)h, (void)n;
        return nullptr;
    } else {
        Counters counters;
        K stepper(problem, info, h, counters);
        Vec z = problem.initial_state();
        const int d = problem.dim();
        const Mat Jinv = canonical_J_inverse(d);
        const double jinv_norm = std::sqrt(static_cast<double>(d));
        Mat Psi(d, d), JPsi(d, d), W(d, d);
        MinMaxDecimator rel(n);
        for (std::int64_t k = 0; k < n; ++k) {
            const double tk = time_at(c.t0, h, k);
            if (stepper.step_jacobian(tk, z, Psi) != StepStatus::ok) break;
            const double cdec = std::exp(-2.0 * problem.dGamma(tk, h));
            JPsi.noalias() = Jinv * Psi;
            W.noalias() = Psi.transpose() * JPsi;
            W -= cdec * Jinv;
            const double e_rel = W.norm() / (cdec * jinv_norm);
            if (state_diverged(z) || !std::isfinite(e_rel)) break;
            rel.push(time_at(c.t0, h, k + 1), e_rel);
        }
        return rel.to_json();
    }
}

// Everything one run keeps for its figures. grid/ref: the measured run's output grid and the
// reference on the same grid (ref_on_grid false when the reference is not on it).
template <class K, class P>
nlohmann::json capture_run_series(const P& problem, const CaseSpec& c, const MethodInfo& info,
                                  double h, std::int64_t n, const Mat& grid,
                                  const std::vector<double>& grid_t, const Mat& ref,
                                  bool ref_on_grid, const std::vector<Maximum>& maxima) {
    using json = nlohmann::json;
    json s = json::object();
    // the separate per-step pass (the orbit from it only when there is no output grid)
    const Eigen::Index cols = grid.cols();
    const bool orbit_steps = figure_wants_orbit<P>() && cols <= 2;
    FigureStepObserver<P> obs(problem, c, h, n, orbit_steps);
    if (obs.needed()) {
        Counters counters;
        K stepper(problem, info, h, counters);
        Vec z = problem.initial_state();
        obs.start(z);
        integrate(stepper, z, c.t0, h, n, &obs);
        s = obs.to_json();
    }
    if (c.wants("conformal-symplectic")) {
        json cs = conformal_symplectic_series<K>(problem, info, c, h, n);
        if (!cs.is_null()) s["conformal-symplectic.rel"] = cs;
    }
    // series on the output grid (the formulas of TypedCase's error/energy/temperature metrics)
    if (cols > 1) {
        if (ref_on_grid && c.wants("error")) {
            MinMaxDecimator e(cols - 1);
            for (Eigen::Index i = 1; i < cols; ++i)
                e.push(grid_t[static_cast<std::size_t>(i)], (grid.col(i) - ref.col(i)).norm());
            s["error.abs"] = e.to_json();
        }
        if constexpr (P::has_energy) {
            if (c.wants("energy")) {
                const double e0 = problem.energy(grid.col(0));
                const double s0 = problem.energy_scale(grid.col(0));
                MinMaxDecimator change(cols), err(cols), raw(cols);
                for (Eigen::Index i = 0; i < cols; ++i) {
                    const double t = grid_t[static_cast<std::size_t>(i)];
                    const double en = problem.energy(grid.col(i));
                    raw.push(t, en);
                    change.push(t, scale_defined(s0) ? (en - e0) / s0 : 0.0);
                    if (ref_on_grid) err.push(t, problem.energy(ref.col(i)) - en);
                }
                s["energy.value"] = raw.to_json();
                s["energy.change_res"] = change.to_json();
                if (ref_on_grid) s["energy.error"] = err.to_json();
            }
        }
        if constexpr (HasTemperature<P>) {
            if (c.wants("temperature")) {
                MinMaxDecimator temp(cols);
                for (Eigen::Index i = 0; i < cols; ++i)
                    temp.push(grid_t[static_cast<std::size_t>(i)],
                              problem.temperature(grid.col(i)));
                s["temperature"] = temp.to_json();
            }
        }
        if (c.wants("poincare")) {
            auto section = [](const Mat& g) {
                json q = json::array(), p = json::array();
                for (Eigen::Index i = 0; i < g.cols(); ++i) {
                    q.push_back(std::remainder(g(0, i), 2.0 * M_PI));
                    p.push_back(g(1, i));
                }
                return json{{"q", q}, {"p", p}};
            };
            s["poincare"] = section(grid);
            if (ref_on_grid) s["poincare_reference"] = section(ref);
        }
        // the orbit and the reference orbit at (at most) kOrbitSamples grid points
        auto grid_orbit = [&](const Mat& g) {
            StrideSampler pick(cols);
            json t = json::array(), st = json::array();
            for (Eigen::Index i = 0; i < cols; ++i) {
                if (!pick.wants(i)) continue;
                t.push_back(grid_t[static_cast<std::size_t>(i)]);
                std::vector<double> v(static_cast<std::size_t>(g.rows()));
                for (Eigen::Index r = 0; r < g.rows(); ++r)
                    v[static_cast<std::size_t>(r)] = g(r, i);
                st.push_back(v);
            }
            return json{{"t", t}, {"states", st}, {"stride", pick.stride()}};
        };
        if (figure_wants_orbit<P>() && cols > 2) {
            s["orbit"] = grid_orbit(grid);
            if (ref_on_grid) s["orbit_reference"] = grid_orbit(ref);
        }
    }
    auto maxima_json = [](const std::vector<Maximum>& mx) {
        MinMaxDecimator d(static_cast<std::int64_t>(mx.size()));
        for (const auto& m : mx) d.push(m.t, m.d);
        return d.to_json();
    };
    if (c.wants("dissipation-drift")) {
        s["dissipation-drift.d"] = maxima_json(maxima);
        if constexpr (HasOneDofMaxima<P>) {
            // the reference's d(t) by the same locator on the reference samples (drift_metrics)
            if (ref_on_grid && cols > 2) {
                MaximaFinder<P> finder(problem, c.t0);
                for (Eigen::Index i = 0; i < cols; ++i)
                    finder.feed(grid_t[static_cast<std::size_t>(i)], ref.col(i));
                s["dissipation-drift.d_reference"] = maxima_json(finder.maxima());
            }
        }
    }
    return s;
}

// The (γ, h) stability map of one method on the oscillator for its figure: the case's sweep
// ranges on a grid `refine` times finer, each cell coded 0 = F's condition holds and M is
// power-bounded, 1 = F fails but M is power-bounded, 2 = F holds but M is not power-bounded,
// 3 = neither; and F's closed-form boundary (first h where F(3.12)/(3.17)/(3.22) fails, h
// resolved to 1/2000 of the range) at the map's γ rows, when the method has one.
// (A template on the linear problem type, so that only the shard holding it compiles it.)
template <class P>
nlohmann::json stability_map_series(const CaseSpec& c, const MethodInfo& info, int refine = 4) {
    using json = nlohmann::json;
    const auto& sw = *c.sweep;
    const std::vector<double> g0 = sw.gamma.values(), h0 = sw.h.values();
    auto fine = [&](const std::vector<double>& v) {
        std::vector<double> out;
        if (v.size() < 2) return v;
        for (std::size_t i = 0; i + 1 < v.size(); ++i)
            for (int k = 0; k < refine; ++k) out.push_back(v[i] + (v[i + 1] - v[i]) * k / refine);
        out.push_back(v.back());
        return out;
    };
    const std::vector<double> gs = fine(g0), hs = fine(h0);
    json rows = json::array();
    for (double g : gs) {
        std::vector<int> row;
        for (double h : hs) {
            P osc;
            osc.omega = sw.omega;
            osc.gamma = g;
            OneStepAnalysis a;
            with_kernel<P>(info, [&]<class K>() {
                a = analyse_one_step(one_step_matrix<K>(osc, info, h), g, h);
            });
            row.push_back((a.F_condition ? 0 : 1) + (a.power_bounded ? 0 : 2));
        }
        rows.push_back(row);
    }
    json out = {{"omega", sw.omega}, {"gamma", gs}, {"h", hs}, {"code", rows}};
    if (oscillator_formulas(info.id).F_condition) {
        json bg = json::array(), bh = json::array();
        const double hlo = h0.front(), hhi = h0.back();
        for (double g : gs) {
            double first = std::numeric_limits<double>::quiet_NaN();
            for (int j = 0; j <= 2000; ++j) {
                const double h = hlo + (hhi - hlo) * j / 2000.0;
                if (!oscillator_formulas(info.id).F_condition(sw.omega, g, h)) {
                    first = h;
                    break;
                }
            }
            bg.push_back(g);
            bh.push_back(std::isnan(first) ? json(nullptr) : json(first));
        }
        out["F_formula_boundary"] = {
            {"gamma", bg}, {"h", bh}, {"source", oscillator_formulas(info.id).source}};
    }
    return out;
}

// The series file of a case: one entry per run (method, dt, status, its series; empty for runs
// that keep none: figure_series_for_dt).
inline nlohmann::json case_series_json(const CaseSpec& c, const std::vector<nlohmann::json>& runs,
                                       const std::vector<nlohmann::json>& series) {
    using json = nlohmann::json;
    json out_runs = json::array();
    for (std::size_t i = 0; i < runs.size(); ++i) {
        const json& r = runs[i];
        out_runs.push_back(
            {{"method", r.value("method", std::string())},
             {"dt", r.value("dt", 0.0)},
             {"status", r.value("status", std::string())},
             {"series", i < series.size() && series[i].is_object() ? series[i] : json::object()}});
    }
    return {{"format", "dampsym-series-1"},
            {"case", c.id},
            {"problem", c.problem_id},
            {"t0", c.t0},
            {"t_end", c.t_end},
            {"runs", out_runs}};
}

} // namespace dampsym::detail
