// What a run keeps for its figures with `dampsym run --figures` (issue 14; the file format is in
// docs/reports.md, "Series files"). Called from one hook in TypedCase::integrate_with and one in
// TypedCase::series() (typed_case.hpp), and only when figures are on: without --figures nothing
// here runs, so the measured run, its bare-loop timing and every report number are untouched.
//
// Per-step series come from the measured run itself: its figure observer (FigureStepObserver,
// beside the Recorder in one RunObserver) and the conformal-symplectic diagnostic's Jacobian pass
// (its E_n series). No extra pass is made; with --figures a run's wall time includes the series'
// bookkeeping (every other number is the same with or without). The observer reproduces the
// formulas of diagnostics/recorder.hpp exactly, so the maximum of a decimated series equals the
// maximum the report states (verify/figures/test_figure_data.py checks this).
// Series on the output grid (state error, energy error and change, temperature, Poincaré points)
// are read from the measured run's grid and the case's reference, which the diagnostics used.
#pragma once

#include "core/integrate.hpp"
#include "diagnostics/attractor_diagnostic.hpp"
#include "diagnostics/capabilities.hpp"
#include "diagnostics/conformal_symplectic.hpp"
#include "diagnostics/field_drift_diagnostic.hpp"
#include "diagnostics/maxima.hpp"
#include "diagnostics/pde_error_diagnostic.hpp"
#include "diagnostics/recorder.hpp"
#include "diagnostics/series.hpp"
#include "diagnostics/stability.hpp"
#include "harness/case.hpp"
#include "harness/case_figures.hpp"
#include "harness/figure_step_observer.hpp"
#include "harness/registry.hpp"
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
// the grid (harness/measures.cpp): ‖U_n − u(t_n)‖ over the measure's components, or
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

// Everything one run keeps for its figures. steps: the series the measured run's figure observer
// (FigureStepObserver, with the conformal-symplectic pass's E_n series) recorded per step;
// grid/ref: the measured run's output grid and the reference on the same grid (ref_on_grid false
// when the reference is not on it); orbit_steps: figure_orbit_from_steps for this grid.
template <class P>
nlohmann::json capture_run_series(const P& problem, const CaseSpec& c, nlohmann::json steps,
                                  const Mat& grid, const std::vector<double>& grid_t,
                                  const Mat& ref, bool ref_on_grid,
                                  const std::vector<Maximum>& maxima, bool orbit_steps) {
    using json = nlohmann::json;
    json s = steps.is_object() ? std::move(steps) : json::object();
    const Eigen::Index cols = grid.cols();
    // series on the output grid (the formulas of TypedCase's error/energy/temperature metrics)
    if (cols > 1) {
        if (ref_on_grid && c.wants("error")) {
            MinMaxDecimator e(cols - 1);
            for (Eigen::Index i = 1; i < cols; ++i)
                e.push(grid_t[static_cast<std::size_t>(i)], (grid.col(i) - ref.col(i)).norm());
            s["error.abs"] = e.to_json();
        }
        if (ref_on_grid && c.wants("error"))
            measure_pointwise_series(problem, c, grid, grid_t, ref, s);
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
        if constexpr (HasPdeSolution<P>) {
            // B Fig 5.4: the field and the PDE's solution at the output times (at most 9; full
            // precision: figures.data recomputes pde-error.max_abs from them)
            if (c.wants("pde-error")) {
                StrideSampler pick(cols, 9);
                json ts = json::array(), us = json::array(), ps = json::array(), xs = json::array();
                Vec v;
                for (Eigen::Index i = 0; i < cols; ++i) {
                    if (!pick.wants(i)) continue;
                    const double t = grid_t[static_cast<std::size_t>(i)];
                    if (!problem.pde_solution(c.t0, t, v) || v.size() > grid.rows()) break;
                    ts.push_back(t);
                    us.push_back(
                        std::vector<double>(grid.col(i).data(), grid.col(i).data() + v.size()));
                    ps.push_back(std::vector<double>(v.data(), v.data() + v.size()));
                }
                if constexpr (requires { problem.grid.x(0); })
                    for (int n = 0; n < problem.dim(); ++n) xs.push_back(problem.grid.x(n));
                s["snapshots"] = {{"t", ts}, {"u", us}, {"pde", ps}, {"x", xs}};
            }
        }
        if constexpr (HasField<P>) {
            // d(t) = ln max_x u + Γ(t) − Γ(t0) of field_drift_metrics, B (5.6); up to the first
            // output time where max_x u <= 0 (where the metric is undefined)
            if (c.wants("field-drift") && cols > 2) {
                const int n = problem.field_size();
                const double gamma0 = problem.Gamma(c.t0);
                MinMaxDecimator d(cols - 1);
                for (Eigen::Index i = 1; i < cols && n >= 1 && n <= grid.rows(); ++i) {
                    const double m = grid.col(i).head(n).maxCoeff();
                    if (!(m > 0.0)) break;
                    const double t = grid_t[static_cast<std::size_t>(i)];
                    d.push(t, std::log(m) + (problem.Gamma(t) - gamma0));
                }
                s["field-drift.d"] = d.to_json();
            }
        }
        if constexpr (HasProbe<P>) {
            // B Fig 5.10's amplitude: the attractor diagnostic's probe on the output grid (the
            // whole run: the transient too; the statistics are of its second half)
            if (c.wants("attractor") && cols > 1) {
                MinMaxDecimator d(cols - 1);
                for (Eigen::Index i = 1; i < cols; ++i)
                    d.push(grid_t[static_cast<std::size_t>(i)], problem.probe(grid.col(i)));
                json j = d.to_json();
                j["probe"] = std::string(P::probe_name);
                s["attractor.probe"] = j;
            }
        }
        if constexpr (HasProbePlane<P>) {
            // B Fig 5.10's right panels: the probe as a point of its plane at (at most
            // kPortraitPoints) output times, the whole run
            if (c.wants("attractor") && cols > 1) {
                StrideSampler pick(cols - 1, kPortraitPoints);
                json t = json::array(), pts = json::array();
                for (Eigen::Index i = 1; i < cols; ++i) {
                    if (!pick.wants(i - 1)) continue;
                    const auto xy = problem.probe_plane(grid.col(i));
                    t.push_back(grid_t[static_cast<std::size_t>(i)]);
                    pts.push_back({drawn_value(xy[0]), drawn_value(xy[1])});
                }
                s["attractor.plane"] = {
                    {"t", t},
                    {"points", pts},
                    {"names",
                     {std::string(P::probe_plane_names[0]), std::string(P::probe_plane_names[1])}},
                    {"stride", pick.stride()}};
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
            StrideSampler pick(cols, orbit_samples(g.rows()));
            json t = json::array(), st = json::array();
            for (Eigen::Index i = 0; i < cols; ++i) {
                if (!pick.wants(i)) continue;
                t.push_back(grid_t[static_cast<std::size_t>(i)]);
                std::vector<double> v(static_cast<std::size_t>(g.rows()));
                for (Eigen::Index r = 0; r < g.rows(); ++r)
                    v[static_cast<std::size_t>(r)] = drawn_value(g(r, i)); // drawn, not compared
                st.push_back(v);
            }
            return json{{"t", t}, {"states", st}, {"stride", pick.stride()}};
        };
        const bool orbit = case_orbit<P>(c);
        if (orbit && !orbit_steps && cols > 2) {
            s["orbit"] = grid_orbit(grid);
            if (ref_on_grid) s["orbit_reference"] = grid_orbit(ref);
        } else if (orbit && ref_on_grid && cols > 2 && !s.contains("orbit_reference")) {
            s["orbit_reference"] = grid_orbit(ref); // no exact solution: the grid's reference
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

// F Fig 3.4: |½ tr M(h) − e^{−γh} cos(βh)| of the method on the case's own oscillator at 25 step
// sizes from 2e-3 to 0.5 (geometric), the quantity whose h⁴ coefficient trace-taylor fits
// (diagnostics/stability_diagnostic.cpp); the figure draws it with the fitted c h⁴ line.
template <class P>
nlohmann::json half_trace_error_series(const P& problem, const MethodInfo& info) {
    std::vector<double> hs, err;
    for (int k = 0; k < 25; ++k) {
        const double h = 2e-3 * std::pow(250.0, k / 24.0);
        double half = std::numeric_limits<double>::quiet_NaN();
        with_kernel<P>(info, [&]<class K>() {
            half =
                analyse_one_step(one_step_matrix<K>(problem, info, h), problem.gamma, h).half_trace;
        });
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
            with_kernel<P>(info, [&]<class K>() {
                a = analyse_one_step(one_step_matrix<K>(osc, info, h), g, h);
            });
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
