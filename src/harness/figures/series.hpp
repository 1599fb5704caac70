// What a run keeps for its figures with `dampsym run --figures` (the file format is in
// docs/reports.md, "Series files"). Called from one hook in TypedCase::integrate_with and one in
// TypedCase::series() (typed_case.hpp), and only when figures are on: without --figures nothing
// here runs, so the measured run, its bare-loop timing and every report number are untouched.
//
// Per-step series come from the measured run itself: the diagnostics' per-step parts in the
// Recorder (the same computation as the report's statistics, observer_part.hpp), the orbit
// samples of the figure observer (FigureStepObserver, beside the Recorder in one RunObserver) and
// the conformal-symplectic diagnostic's Jacobian pass (its E_n series). No extra pass is made;
// with --figures a run's wall time includes the series' bookkeeping (every other number is the
// same with or without), and the maximum of a decimated series equals the maximum the report
// states (verify/figures/test_figure_data.py checks this).
// Series on the output grid (state error, energy error and change, temperature, Poincaré points)
// are read from the measured run's grid and the case's reference, which the diagnostics used.
#pragma once

#include "core/integrate.hpp"
#include "diagnostics/attractor_diagnostic.hpp"
#include "diagnostics/capabilities.hpp"
#include "diagnostics/conformal_symplectic.hpp"
#include "diagnostics/dissipation_drift_diagnostic.hpp"
#include "diagnostics/energy_diagnostic.hpp"
#include "diagnostics/error_diagnostic.hpp"
#include "diagnostics/field_drift_diagnostic.hpp"
#include "diagnostics/maxima.hpp"
#include "diagnostics/pde_error_diagnostic.hpp"
#include "diagnostics/poincare_diagnostic.hpp"
#include "diagnostics/recorder.hpp"
#include "diagnostics/series.hpp"
#include "diagnostics/stability.hpp"
#include "diagnostics/temperature_diagnostic.hpp"
#include "harness/case/case.hpp"
#include "harness/case/figures_key.hpp"
#include "harness/figures/step_observer.hpp"
#include "harness/run/kernel_ops.hpp"
#include "reference/oscillator_exact.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <optional>
#include <string_view>
#include <vector>

namespace dampsym::detail {

// Whether run (d = index in the ladder) keeps step series: every run of a case with at most two
// step sizes; on a longer ladder (a convergence case) only the smallest step size.
inline bool figure_series_for_dt(const CaseSpec& c, std::size_t d) {
    if (c.dts.size() <= 2) return true;
    for (double h : c.dts)
        if (h < c.dts[d]) return false;
    return true;
}

// Whether case c keeps orbit samples for its figures (case_draws_orbit: its "figures" key, or the
// problem's default).
template <class P>
bool case_orbit(const CaseSpec& c) {
    return case_draws_orbit(c, figure_orbit_of<P>());
}

// Whether the orbit of a run's figures is sampled from its steps (the figure observer) rather
// than from its output grid of `cols` points: when the grid has fewer points than the step
// samples (orbit_samples), a grid of a few points per revolution would draw a polygon.
template <class P>
bool figure_orbit_from_steps(const P& problem, const CaseSpec& c, Eigen::Index cols,
                             std::int64_t n) {
    return case_orbit<P>(c) && cols - 1 < std::min<std::int64_t>(n, orbit_samples(problem.dim()));
}

// The pointwise values of the case's measures on the output grid, before their reduction over
// the grid (harness/run/measures.cpp): ‖U_n − u(t_n)‖ over the measure's components, or
// |H(U_n) − H(u(t_n))| for an energy-error measure, divided by ‖u(t_n)‖ (|H(u(t_n))|) when
// relative. B Fig 5.1 draws the absolute and relative error of u against t, HLW Fig 2.2 the
// energy and global errors. One series per distinct (quantity, components, norm):
// "measure-pointwise.<component or energy>.<abs|rel>".
template <class P>
void measure_pointwise_series(const P& problem, const CaseSpec& c, const Mat& grid,
                              const std::vector<double>& grid_t, const Mat& ref,
                              nlohmann::json& s) {
    for (const MeasureSpec& m : c.measures) {
        const bool energy = m.quantity == MeasureQuantity::energy_error;
        if (energy && !P::has_energy) continue;
        if (!energy && (m.count < 1 || m.first + m.count > grid.rows())) continue;
        const std::string key = "measure-pointwise." +
                                (energy ? std::string("energy") : m.component) +
                                (m.relative ? ".rel" : ".abs");
        if (s.contains(key)) continue;
        MinMaxDecimator d(grid.cols() - 1);
        for (Eigen::Index i = 1; i < grid.cols(); ++i) {
            double e = 0.0, scale = 0.0;
            if constexpr (P::has_energy) {
                if (energy) {
                    scale = std::abs(problem.energy(ref.col(i)));
                    e = std::abs(problem.energy(grid.col(i)) - problem.energy(ref.col(i)));
                }
            }
            if (!energy) {
                e = (grid.col(i).segment(m.first, m.count) - ref.col(i).segment(m.first, m.count))
                        .norm();
                scale = ref.col(i).segment(m.first, m.count).norm();
            }
            d.push(grid_t[static_cast<std::size_t>(i)],
                   m.relative ? (scale > 0.0 ? e / scale : std::nan("")) : e);
        }
        nlohmann::json j = d.to_json();
        j["component"] = energy ? std::string("H") : m.component;
        j["relative"] = m.relative;
        s[key] = std::move(j);
    }
}

// What a run's series are drawn from: the measured run's output grid, its times and the reference
// on the same grid (ref_on_grid false when the reference is not on it).
template <class P>
struct GridSeries {
    using Problem = P;
    const P& problem;
    const CaseSpec& c;
    const Mat& grid;
    const std::vector<double>& grid_t;
    const Mat& ref;
    bool ref_on_grid;
    Eigen::Index cols() const { return grid.cols(); }
    double t(Eigen::Index i) const { return grid_t[static_cast<std::size_t>(i)]; }
};

// The orbit and the reference orbit at (at most) kOrbitSamples grid points, unless the figure
// observer kept the orbit from the steps (orbit_steps).
template <class P>
void orbit_series(const GridSeries<P>& g, bool orbit_steps, nlohmann::json& s) {
    using json = nlohmann::json;
    auto grid_orbit = [&](const Mat& m) {
        StrideSampler pick(g.cols(), orbit_samples(m.rows()));
        json t = json::array(), st = json::array();
        for (Eigen::Index i = 0; i < g.cols(); ++i) {
            if (!pick.wants(i)) continue;
            t.push_back(g.t(i));
            std::vector<double> v(static_cast<std::size_t>(m.rows()));
            for (Eigen::Index r = 0; r < m.rows(); ++r)
                v[static_cast<std::size_t>(r)] = drawn_value(m(r, i)); // drawn, not compared
            st.push_back(v);
        }
        return json{{"t", t}, {"states", st}, {"stride", pick.stride()}};
    };
    if (!case_orbit<P>(g.c) || g.cols() <= 2) return;
    if (!orbit_steps) {
        s["orbit"] = grid_orbit(g.grid);
        if (g.ref_on_grid) s["orbit_reference"] = grid_orbit(g.ref);
    } else if (g.ref_on_grid && !s.contains("orbit_reference")) {
        s["orbit_reference"] = grid_orbit(g.ref); // no exact solution: the grid's reference
    }
}

// Everything one run keeps for its figures. steps: the series recorded per step (the parts'
// law series, the figure observer's orbit, the conformal-symplectic pass's E_n series);
// grid/ref: the measured run's output grid and the reference on the same grid (ref_on_grid false
// when the reference is not on it); orbit_steps: figure_orbit_from_steps for this grid. The
// series on the output grid are each diagnostic's own (its grid_series, with the formulas of its
// metrics), the measures' pointwise values and the orbit.
template <class P>
nlohmann::json capture_run_series(const P& problem, const CaseSpec& c, nlohmann::json steps,
                                  const Mat& grid, const std::vector<double>& grid_t,
                                  const Mat& ref, bool ref_on_grid, bool orbit_steps) {
    nlohmann::json s = steps.is_object() ? std::move(steps) : nlohmann::json::object();
    const GridSeries<P> g{problem, c, grid, grid_t, ref, ref_on_grid};
    if (g.cols() <= 1) return s;
    for_each_type(DiagnosticList{}, [&]<class D>() {
        if constexpr (requires { D::grid_series(g, s); })
            if (c.wants(D::name)) D::grid_series(g, s);
    });
    if (ref_on_grid) measure_pointwise_series(problem, c, grid, grid_t, ref, s);
    orbit_series(g, orbit_steps, s);
    return s;
}

// F Fig 3.4: |½ tr M(h) − e^{−γh} cos(βh)| of the method on the case's own oscillator at 25 step
// sizes from 2e-3 to 0.5 (geometric), the quantity whose h⁴ coefficient trace-taylor fits
// (diagnostics/stability_diagnostic.cpp); the figure draws it with the fitted c h⁴ line.
template <class P>
nlohmann::json half_trace_error_series(const P& problem, const MethodInfo& info) {
    std::vector<double> hs, err;
    for (int k = 0; k < 25; ++k) {
        const double h = 2e-3 * std::pow(250.0, k / 24.0);
        double half = std::numeric_limits<double>::quiet_NaN();
        KernelMatch match = KernelMatch::applied;
        if (const KernelOps<P>* ops = kernel_ops<P>(info, match))
            half =
                analyse_one_step(one_step_matrix(problem, info, h, ops->stepper), problem.gamma, h)
                    .half_trace;
        hs.push_back(h);
        err.push_back(std::abs(half - oscillator_damped_cs(problem.omega, problem.gamma, h).c));
    }
    return {{"omega", problem.omega}, {"gamma", problem.gamma}, {"h", hs}, {"error", err}};
}

// The (γ, h) stability map of one method on the oscillator for its figure: the case's sweep
// ranges on a grid `refine` times finer, each cell coded 0 = F's condition holds and M is
// power-bounded, 1 = F fails but M is power-bounded, 2 = F holds but M is not power-bounded,
// 3 = neither; and F's closed-form boundary (first h where F(3.12)/(3.17)/(3.22) fails, h
// resolved to 1/2000 of the range) at the map's γ rows, when the method has one.
// (A template on the linear problem type, so that only the shard holding it compiles it; the
// grid's problems are problem.with(ω, γ), as in the stability sweep.)
template <class P>
nlohmann::json stability_map_series(const P& problem, const CaseSpec& c, const MethodInfo& info,
                                    int refine = 4) {
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
    json rows = json::array(), equal_rows = json::array();
    for (double g : gs) {
        std::vector<int> row, equal;
        for (double h : hs) {
            const P osc = problem.with(sw.omega, g);
            OneStepAnalysis a;
            KernelMatch match = KernelMatch::applied;
            if (const KernelOps<P>* ops = kernel_ops<P>(info, match))
                a = analyse_one_step(one_step_matrix(osc, info, h, ops->stepper), g, h);
            row.push_back((a.F_condition ? 0 : 1) + (a.power_bounded ? 0 : 2));
            // F's strict condition |½trM| < e^{−γh} at equality (cimp at γ = ω): which side a
            // cell falls on is round-off, so the figure marks these cells as such
            equal.push_back(std::abs(std::abs(a.half_trace) - std::exp(-g * h)) <=
                                    64.0 * std::numeric_limits<double>::epsilon()
                                ? 1
                                : 0);
        }
        rows.push_back(row);
        equal_rows.push_back(equal);
    }
    json out = {
        {"omega", sw.omega}, {"gamma", gs}, {"h", hs}, {"code", rows}, {"F_equal", equal_rows}};
    out["half_trace_error"] = half_trace_error_series(problem, info);
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
        json s = i < series.size() && series[i].is_object() ? series[i] : json::object();
        // A reference orbit equal to an earlier run's (the reference on the case's output grid,
        // the same for every run) is written once: {"same_as_run": k} refers to run k's.
        if (s.contains("orbit_reference"))
            for (std::size_t k = 0; k < i; ++k)
                if (out_runs[k]["series"].contains("orbit_reference") &&
                    out_runs[k]["series"]["orbit_reference"] == s["orbit_reference"]) {
                    s["orbit_reference"] = {{"same_as_run", k}};
                    break;
                }
        out_runs.push_back({{"method", r.value("method", std::string())},
                            {"dt", r.value("dt", 0.0)},
                            {"status", r.value("status", std::string())},
                            {"series", std::move(s)}});
    }
    return {{"format", "dampsym-series-1"},
            {"case", c.id},
            {"problem", c.problem_id},
            {"t0", c.t0},
            {"t_end", c.t_end},
            {"runs", out_runs}};
}

} // namespace dampsym::detail
