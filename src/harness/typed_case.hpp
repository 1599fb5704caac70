// The typed case runner: one TypedCase<P> per problem type runs the methods of a case through
// their kernels and computes the requested diagnostics. It is instantiated only in the generated
// shard translation units (src/harness/case_shard.cpp.in: every problem type whose index in
// ProblemList falls in shard K), so that the heavy template code compiles in parallel; adding a
// problem or a kernel still touches no runner file.
#pragma once

#include "harness/case_job.hpp"

#include "core/integrate.hpp"
#include "diagnostics/capabilities.hpp"
#include "diagnostics/conformal_symplectic.hpp"
#include "diagnostics/maxima.hpp"
#include "diagnostics/order_fit.hpp"
#include "diagnostics/recorder.hpp"
#include "diagnostics/stability.hpp"
#include "harness/figure_series.hpp" // figures hook (issue 14)
#include "harness/registry.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

namespace dampsym::detail {

template <class P>
class TypedCase final : public CaseJob {
public:
    explicit TypedCase(const CaseSpec& spec) : c_(spec), problem_(P::from_params(spec.params)) {}

    void prepare() override {
        runs_.assign(c_.methods.size() * c_.dts.size(), json());
        method_metrics_.assign(c_.methods.size(), json::object());
        if (figures_) series_.assign(runs_.size(), json()); // figures hook (issue 14)
        points_ = output_points(c_);
        // A trajectory grid only for diagnostics that read it; a reference only for those that
        // compare with it (the energy diagnostic without "error" reports changes only).
        needs_grid_ = case_needs_grid(c_, points_);
        if (c_.wants("error") || c_.wants("poincare")) {
            ref_times_ = reference_times(c_, points_, needs_grid_);
            const auto np = static_cast<Eigen::Index>(ref_times_.size());
            if constexpr (P::has_exact) {
                ref_.resize(problem_.dim(), np);
                Vec tmp(problem_.dim());
                const Vec z0 = problem_.initial_state(); // the state at t0 (core/problem.hpp)
                for (std::int64_t i = 0; i < np; ++i) {
                    problem_.exact(c_.t0, z0, ref_times_[static_cast<std::size_t>(i)], tmp);
                    ref_.col(i) = tmp;
                }
                reference_ = {{"kind", "exact"}, {"error_estimate", 0.0}, {"points", np}};
            } else {
                numerical_reference();
            }
        } else {
            reference_ = {{"kind", "none"}};
        }
    }

    // Certified GSL reference (conventions §4) on the output grid, shared through the cache.
    void numerical_reference() {
        auto sol = reference_cache().get(reference_key(c_, ref_times_), [&] {
            ReferenceRequest req = reference_request(problem_, c_, ref_times_);
            poison_reference(req, fault_for(c_.id, "(reference)")); // tests only (limits.hpp)
            return certified_reference(req);
        });
        reference_ = {{"kind", "gsl-certified"},
                      {"ok", sol->ok},
                      {"stepper", sol->stepper},
                      {"epsrel", sol->epsrel},
                      {"epsabs", sol->epsabs},
                      {"certifier", sol->certifier},
                      {"certifier_epsrel", sol->cert_epsrel},
                      {"certifier_epsabs", sol->cert_epsabs},
                      {"error_estimate", sol->ok ? json(sol->error_estimate) : json(nullptr)},
                      {"rhs_evals", sol->rhs_evals},
                      {"points", ref_times_.size()}};
        if (!sol->ok) {
            reference_["error"] = sol->error;
            reference_ok_ = false;
            return;
        }
        ref_ = sol->states;
        ref_error_ = sol->error_estimate;
        reference_["final_time"] = ref_times_.back();
        reference_["final_state"] = state_json(ref_.col(ref_.cols() - 1));
    }

    void add_tasks(std::vector<std::function<void()>>& tasks) override {
        for (std::size_t m = 0; m < c_.methods.size(); ++m) {
            for (std::size_t d = 0; d < c_.dts.size(); ++d)
                tasks.emplace_back([this, m, d] { run_one(m, d); });
            if (c_.wants("stability-sweep")) sweep_tasks(m, tasks);
            if (c_.wants("trace-taylor")) tasks.emplace_back([this, m] { trace_taylor(m); });
        }
    }

    json finish() override;

    // Figures hook (issue 14): the series file of the case (docs/reports.md "Series files").
    json series() override {
        if (!figures_) return nullptr;
        json out = case_series_json(c_, runs_, series_);
        if constexpr (P::is_linear)
            if (c_.wants("stability-sweep") && c_.sweep)
                for (std::size_t m = 0; m < c_.methods.size(); ++m)
                    out["stability_map"][c_.methods[m]] = stability_map_series<P>(c_, method(m));
        return out;
    }

private:
    // Figures hook (issue 14): the series of the run whose record is `out` (a slot of runs_).
    template <class K>
    void capture_figure_series(const MethodInfo& info, double h, std::int64_t n,
                               const Recorder<P>& rec, const json& out) {
        const auto slot = static_cast<std::size_t>(&out - runs_.data());
        if (!figure_series_for_dt(c_, slot % c_.dts.size())) return;
        const Mat& g = rec.grid();
        std::vector<double> times;
        for (Eigen::Index i = 0; i < g.cols(); ++i) times.push_back(grid_time(i));
        const bool ref_on_grid = reference_ok_ && needs_grid_ && ref_.cols() == g.cols();
        series_[slot] = capture_run_series<K>(problem_, c_, info, h, n, g, times, ref_, ref_on_grid,
                                              rec.maxima());
    }
    std::vector<json> series_; // per run slot, only with --figures

    const MethodInfo& method(std::size_t m) const { return *find_method(c_.methods[m]); }
    json& run_slot(std::size_t m, std::size_t d) { return runs_[m * c_.dts.size() + d]; }

    void run_one(std::size_t m, std::size_t d) {
        const MethodInfo& info = method(m);
        json& out = run_slot(m, d);
        const double h = c_.dts[d];
        const std::int64_t n = c_.steps[d];
        out = {{"method", info.id}, {"dt", h}, {"steps_planned", n}};
        KernelMatch match = KernelMatch::applied;
        try {
            match = with_kernel<P>(info, [&]<class K>() { integrate_with<K>(info, h, n, out); });
        } catch (const std::exception& e) {
            // issue 17: a fault in this run is its status; the other runs and cases go on
            out = {{"method", info.id},        {"dt", h},           {"steps_planned", n},
                   {"status", "error"},        {"error", e.what()}, {"steps", 0},
                   {"metrics", json::object()}};
            return;
        }
        if (match != KernelMatch::applied) {
            out["status"] = "not-applicable";
            out["steps"] = 0;
            out["metrics"] = json::object();
        }
    }

    template <class K>
    void integrate_with(const MethodInfo& info, double h, std::int64_t n, json& out) {
        Counters counters;
        K stepper(problem_, info, h, counters);
        Vec z = problem_.initial_state();
        const bool observe = needs_grid_ || c_.wants("invariants") ||
                             c_.wants("dissipation-drift") || c_.wants("momentum") ||
                             c_.wants("energy-balance");
        Recorder<P> rec(problem_, c_.t0, h);
        IntegrateOutcome res;
        // issue 17: the step loop in chunks with the case's time budget and stop requests tested
        // between them (src/harness/limits.hpp); a fault only where a test planted one
        const FaultPlan* fault = fault_for(c_.id, info.id);
        guard_.start();
        const auto start = Clock::now();
        if (observe) {
            if (needs_grid_) rec.record_grid(n / points_, points_ + 1);
            if (c_.wants("invariants")) rec.track_invariants();
            if (c_.wants("dissipation-drift")) rec.track_maxima();
            if (c_.wants("momentum")) rec.track_momentum(table_momentum_factor(info, h));
            if (c_.wants("energy-balance")) rec.track_energy_balance();
            rec.start(z);
            res = integrate_guarded(stepper, z, c_.t0, h, n, &rec, guard_, fault);
        } else {
            res = integrate_guarded(stepper, z, c_.t0, h, n, static_cast<NoObserver*>(nullptr),
                                    guard_, fault);
        }
        const double wall = seconds_since(start);
        out["observed"] = {{"bare_loop", !observe},
                           {"grid_points", needs_grid_ ? points_ + 1 : 0},
                           {"invariants", c_.wants("invariants")},
                           {"maxima", c_.wants("dissipation-drift")},
                           {"momentum", c_.wants("momentum")},
                           {"energy_balance", c_.wants("energy-balance")},
                           {"step_jacobians", c_.wants("conformal-symplectic")}};

        out["status"] = to_string(res.status);
        out["steps"] = res.steps_done;
        out["final_time"] = time_at(c_.t0, h, res.steps_done);
        out["final_state"] = state_json(z);
        if (res.status != RunStatus::ok) out["failed_at_step"] = res.failed_step;
        out["rhs_evals"] = counters.rhs_evals;
        out["jac_evals"] = counters.jac_evals;
        out["newton_iters"] = counters.newton_iters;
        out["max_newton_iters_per_step"] = counters.max_newton_iters_per_step;
        out["wall_seconds"] = wall;
        if (res.status == RunStatus::timeout || res.status == RunStatus::interrupted) {
            out["metrics"] = json::object(); // issue 17: stopped; no further pass over the steps
            return;
        }
        json metrics = json::object();
        const bool ok = res.status == RunStatus::ok;
        const double steps = static_cast<double>(std::max<std::int64_t>(res.steps_done, 1));
        if (c_.wants("cost")) {
            metrics["cost"] = {
                {"rhs_evals_per_step", static_cast<double>(counters.rhs_evals) / steps},
                {"jac_evals_per_step", static_cast<double>(counters.jac_evals) / steps},
                {"newton_iters_per_step", static_cast<double>(counters.newton_iters) / steps},
                {"max_newton_iters", counters.max_newton_iters_per_step},
                {"wall_seconds", wall}};
        }
        if (ok && reference_ok_ && c_.wants("error")) metrics["error"] = error_metrics(rec, z);
        if (ok && reference_ok_ && !c_.measures.empty())
            metrics["measure"] = measure_metrics(rec, z);
        if (ok && reference_ok_ && c_.wants("energy")) metrics["energy"] = energy_metrics(rec);
        if (ok && c_.wants("invariants")) metrics["invariants"] = invariant_metrics(rec);
        if (ok && c_.wants("dissipation-drift")) metrics["dissipation-drift"] = drift_metrics(rec);
        if (ok && c_.wants("momentum")) metrics["momentum"] = momentum_metrics(rec, info, h);
        if (ok && c_.wants("energy-balance")) {
            const EnergyBalanceStats& e = rec.energy_balance_stats();
            json eb = {{"max", e.max},
                       {"last", e.last},
                       {"mean", e.count ? e.sum / static_cast<double>(e.count) : 0.0},
                       {"max_rate", e.max_rate},
                       {"points", e.count}};
            // R relative to the largest |Ḣ|: undefined when Ḣ ≡ 0 (γ = 0 or p ≡ 0)
            if (scale_defined(e.max_rate))
                eb["max_rel"] = e.max / e.max_rate;
            else
                set_undefined(eb, "max_rel", "max |dH/dt| is 0: no rate to compare with");
            metrics["energy-balance"] = eb;
        }
        if (c_.wants("conformal-symplectic"))
            metrics["conformal-symplectic"] = conformal_symplectic_metrics<K>(info, h, n);
        if (ok && c_.wants("poincare")) metrics["poincare"] = poincare_metrics(rec);
        if (ok && c_.wants("temperature")) metrics["temperature"] = temperature_metrics(rec);
        if (c_.wants("stability")) {
            if constexpr (P::is_linear) metrics["stability"] = stability_metrics<K>(info, h);
        }
        if (c_.wants("local-error")) metrics["local-error"] = local_error_metrics<K>(info, h);
        out["metrics"] = metrics;
        // Figures hook (issue 14): only with --figures; a separate pass, the run above is
        // untouched.
        if (figures_ && ok) capture_figure_series<K>(info, h, n, rec, out);
        // Work-precision timing (ladder cases): the bare step loop only, never a failed run.
        if (ok && time_budget_ > 0.0 && c_.dts.size() >= 2)
            out["timing"] = time_bare_loop<K>(info, h, n);
    }

    // One warm-up, then the minimum of N repetitions of the bare step loop (no observer), N chosen
    // from the warm-up so that the repetitions total >= time_budget_ (at most 100000).
    template <class K>
    json time_bare_loop(const MethodInfo& info, double h, std::int64_t n) const {
        auto once = [&] {
            Counters counters;
            K stepper(problem_, info, h, counters);
            Vec z = problem_.initial_state();
            const auto start = Clock::now();
            integrate(stepper, z, c_.t0, h, n);
            return seconds_since(start);
        };
        const double warmup = once();
        const double est = std::max(warmup, 1e-9);
        const auto reps =
            static_cast<std::int64_t>(std::clamp(std::ceil(time_budget_ / est), 1.0, 100000.0));
        double best = std::numeric_limits<double>::infinity(), total = 0.0;
        std::int64_t r = 0;
        for (; (r < reps || total < time_budget_) && r < 100000; ++r) {
            const double t = once();
            best = std::min(best, t);
            total += t;
        }
        return {{"repetitions", r},
                {"wall_seconds_min", best},
                {"ns_per_step", 1e9 * best / static_cast<double>(std::max<std::int64_t>(n, 1))},
                {"repetitions_wall_seconds", total},
                {"warmup_wall_seconds", warmup}};
    }

    // One step from the initial state against the exact solution at t0 + h (B Fig 3.2's local
    // error, O(h^{p+1})); a separate stepper, so the run above is untouched.
    template <class K>
    json local_error_metrics(const MethodInfo& info, double h) const {
        json out = json::object();
        if constexpr (P::has_exact) {
            Counters scratch;
            K stepper(problem_, info, h, scratch);
            Vec z = problem_.initial_state();
            if (stepper.step(c_.t0, z) != StepStatus::ok) return {{"reason", "solve failed"}};
            Vec exact(z.size());
            problem_.exact(c_.t0, problem_.initial_state(), c_.t0 + h, exact);
            const double e = (z - exact).norm();
            out = {{"abs", e}};
            if (scale_defined(exact.norm()))
                out["rel"] = e / exact.norm();
            else
                set_undefined(out, "rel", "exact solution at t0 + h has norm 0");
        }
        return out;
    }

    // Relative errors e_n / ‖z_ref(t_n)‖ are defined only where the reference's norm is a normal
    // number above 100× its certified error estimate (below that the reference cannot resolve a
    // relative error; a solution decayed to ~0 makes the ratio meaningless): one such point makes
    // final_rel / max_rel undefined (null, with the reason), never a huge or a zero ratio.
    json error_metrics(const Recorder<P>& rec, const Vec& z_final) const {
        double max_abs = 0.0, max_rel = 0.0, sum_abs = 0.0;
        Eigen::Index count = 0;
        const double ref_floor = 100.0 * ref_error_;
        std::string rel_undefined;
        auto rel_of = [&](double e, double ref_norm, double t) {
            if (ref_norm >= std::numeric_limits<double>::min() && ref_norm > ref_floor)
                return e / ref_norm;
            if (rel_undefined.empty())
                rel_undefined = "reference norm " + json(ref_norm).dump() +
                                " at t = " + json(t).dump() +
                                " is below max(DBL_MIN, 100 x its error estimate)";
            return 0.0;
        };
        if (needs_grid_) {
            const Mat& g = rec.grid();
            for (Eigen::Index i = 1; i < g.cols(); ++i) { // the initial point is exact
                const double e = (g.col(i) - ref_.col(i)).norm();
                max_abs = std::max(max_abs, e);
                max_rel = std::max(max_rel, rel_of(e, ref_.col(i).norm(), grid_time(i)));
                sum_abs += e;
                ++count;
            }
        }
        const Vec ref_final = ref_.col(ref_.cols() - 1);
        const double final_abs = (z_final - ref_final).norm();
        const std::string grid_undefined = rel_undefined;
        rel_undefined.clear();
        const double final_rel = rel_of(final_abs, ref_final.norm(), c_.t_end);
        const std::string final_undefined = rel_undefined;
        max_abs = std::max(max_abs, final_abs);
        max_rel = std::max(max_rel, final_rel);
        // mean over the output grid t_1..t_end: B Fig 3.1's "average absolute error"
        const double mean_abs = count ? sum_abs / static_cast<double>(count) : final_abs;
        json out = {{"final_abs", final_abs}, {"final_rel", final_rel},
                    {"max_abs", max_abs},     {"mean_abs", mean_abs},
                    {"max_rel", max_rel},     {"reference_error_estimate", ref_error_}};
        if (!final_undefined.empty()) set_undefined(out, "final_rel", final_undefined);
        if (!final_undefined.empty() || !grid_undefined.empty())
            set_undefined(out, "max_rel",
                          grid_undefined.empty() ? final_undefined : grid_undefined);
        return out;
    }

    // The case's "measures" (docs/case-keys.md): the error of the chosen components, or of
    // the energy, absolute or relative to the reference pointwise, reduced over the output grid
    // t_1..t_end (the initial point is exact) as the paper states it.
    json measure_metrics(const Recorder<P>& rec, const Vec& z_final) const {
        json out = json::object();
        for (const MeasureSpec& m : c_.measures) {
            auto pointwise = [&](const auto& u, const auto& ref) {
                double e = 0.0, scale = 1.0, floor = 1e-300;
                if (m.quantity == MeasureQuantity::energy_error) {
                    if constexpr (P::has_energy) {
                        const double exact = problem_.energy(ref);
                        e = std::abs(problem_.energy(u) - exact);
                        scale = std::abs(exact);
                        // The paper's |H − H_ref|/|H_ref| is kept, but where |H_ref| is within
                        // 100 ulps of its energy scale S_H (T + |V|) of zero, H_ref is round-off
                        // and the ratio is undefined (docs/conventions.md, "Law residuals and
                        // their scales").
                        floor = std::max(floor, 100.0 * std::numeric_limits<double>::epsilon() *
                                                    problem_.energy_scale(ref));
                    }
                } else {
                    e = (u.segment(m.first, m.count) - ref.segment(m.first, m.count)).norm();
                    scale = ref.segment(m.first, m.count).norm();
                    // as error.max_rel: the reference cannot resolve a relative error below
                    // 100 times its certified error estimate
                    floor = std::max(floor, 100.0 * ref_error_);
                }
                // relative to a reference that is not resolved: undefined (never a huge ratio)
                if (m.relative && !(scale > floor)) return std::numeric_limits<double>::quiet_NaN();
                return m.relative ? e / scale : e;
            };
            std::vector<double> t, v;
            if (needs_grid_ && m.over != MeasureStat::final_value) {
                const Mat& g = rec.grid();
                for (Eigen::Index i = 1; i < g.cols(); ++i) {
                    t.push_back(grid_time(i));
                    v.push_back(pointwise(Vec(g.col(i)), Vec(ref_.col(i))));
                }
            } else {
                t.push_back(c_.t_end);
                v.push_back(pointwise(z_final, Vec(ref_.col(ref_.cols() - 1))));
            }
            // One undefined point makes the whole statistic undefined (max_element and the
            // sums would otherwise skip or propagate it depending on its position).
            double x = std::any_of(v.begin(), v.end(), [](double e) { return std::isnan(e); })
                           ? std::numeric_limits<double>::quiet_NaN()
                           : 0.0;
            if (!std::isnan(x)) switch (m.over) {
                case MeasureStat::final_value:
                    x = v.back();
                    break;
                case MeasureStat::max:
                    x = *std::max_element(v.begin(), v.end());
                    break;
                case MeasureStat::mean:
                case MeasureStat::rms: {
                    double sum = 0.0;
                    for (double e : v) sum += m.over == MeasureStat::rms ? e * e : e;
                    x = sum / static_cast<double>(v.size());
                    if (m.over == MeasureStat::rms) x = std::sqrt(x);
                    break;
                }
                case MeasureStat::growth: {
                    // log–log slope of the running maximum against t − t0: ≈ 0 for a bounded
                    // error, 1 for linear growth (O(th)), 2 for quadratic growth (O(t²h)).
                    std::vector<double> lx, ly;
                    double running = 0.0;
                    for (std::size_t i = 0; i < v.size(); ++i) {
                        running = std::max(running, v[i]);
                        if (t[i] >= m.growth_from && running > 0.0) {
                            lx.push_back(std::log(t[i] - c_.t0));
                            ly.push_back(std::log(running));
                        }
                    }
                    if (lx.size() < 3) continue; // not produced: a check on it fails, naming it
                    x = least_squares(lx, ly).slope;
                    break;
                }
                }
            if (!std::isfinite(x)) {
                out[m.name] = nullptr;
                out["undefined"][m.name] =
                    m.quantity == MeasureQuantity::energy_error
                        ? "relative to a reference energy within round-off of 0 at some point"
                        : "relative to a reference of norm 0 at some point";
                continue;
            }
            out[m.name] = x;
        }
        return out;
    }

    // Energy changes H_n − H_0 on the scale S_H(z_0) and errors H_exact − H_n on S_H(z_ref(t_n)),
    // S_H the problem's energy_scale (T + |V|, or H for a definite energy; docs/conventions.md),
    // so that an energy crossing zero does not make a ratio blow up.
    json energy_metrics(const Recorder<P>& rec) const {
        if constexpr (P::has_energy) {
            const Mat& g = rec.grid();
            std::vector<double> t, err, res, change;
            const double e0 = problem_.energy(g.col(0));
            const double s0 = problem_.energy_scale(g.col(0));
            const bool with_ref = reference_ok_ && ref_.cols() == g.cols();
            std::vector<double> change_res;
            double max_err = 0.0, max_change = 0.0, max_change_res = 0.0;
            std::string err_undefined;
            for (Eigen::Index i = 0; i < g.cols(); ++i) {
                const double en = problem_.energy(g.col(i));
                t.push_back(grid_time(i));
                if (with_ref) {
                    const double exact = problem_.energy(ref_.col(i));
                    const double scale = problem_.energy_scale(ref_.col(i));
                    err.push_back(exact - en); // H_exact − H_approx (F Fig 4.3)
                    if (!scale_defined(scale) && err_undefined.empty())
                        err_undefined = "energy scale of the reference is " + json(scale).dump() +
                                        " at t = " + json(t.back()).dump();
                    res.push_back(scale_defined(scale) ? err.back() / scale : 0.0);
                    max_err = std::max(max_err, std::abs(err.back()));
                }
                change.push_back(en - e0);
                change_res.push_back(scale_defined(s0) ? (en - e0) / s0 : 0.0);
                max_change = std::max(max_change, std::abs(change.back()));
                max_change_res = std::max(max_change_res, std::abs(change_res.back()));
            }
            // Growth of |H_n − H_0| between the two halves of the run: ≈ 1 when the error is
            // bounded, ≈ 2 when it grows linearly (HLW Table 2.1).
            double first_half = 0.0, second_half = 0.0;
            const Eigen::Index mid = g.cols() / 2;
            for (Eigen::Index i = 0; i < g.cols(); ++i)
                (i <= mid ? first_half : second_half) =
                    std::max(i <= mid ? first_half : second_half,
                             std::abs(change[static_cast<std::size_t>(i)]));
            json out = {{"max_abs_change", max_change},
                        {"change_slope", least_squares(t, change).slope},
                        {"scale_initial", s0},
                        {"max_change_res", max_change_res},
                        {"change_res_slope", least_squares(t, change_res).slope}};
            if (first_half > 0.0)
                out["growth_ratio"] = second_half / first_half;
            else
                set_undefined(out, "growth_ratio", "|H_n - H_0| = 0 on the first half");
            if (!scale_defined(s0)) {
                const std::string why = "energy scale at t0 is " + json(s0).dump();
                set_undefined(out, "max_change_res", why);
                set_undefined(out, "change_res_slope", why);
            }
            if (with_ref) {
                out["max_abs_error"] = max_err;
                out["final_abs_error"] = std::abs(err.back());
                out["drift_slope"] = least_squares(t, err).slope;
                if (err_undefined.empty())
                    out["error_res_slope"] = least_squares(t, res).slope;
                else
                    set_undefined(out, "error_res_slope", err_undefined);
            }
            return out;
        } else {
            (void)rec;
            return json::object();
        }
    }

    // The invariants' law residuals on their declared scales (recorder.hpp, docs/conventions.md).
    json invariant_metrics(const Recorder<P>& rec) const {
        json inv = json::object();
        for (std::size_t k = 0; k < P::invariant_names.size(); ++k) {
            const InvariantStats& s = rec.invariant_stats()[k];
            json o = {{"scale", std::string(P::invariant_scale_defs[k])},
                      {"scale_initial", s.scale_initial},
                      {"max_step_res", s.max_step_res},
                      {"last_step_res", s.last_step_res},
                      {"max_step_abs", s.max_step_abs},
                      {"scale_at_max_step_res", s.scale_at_max},
                      {"max_global_res", s.max_global_res},
                      {"global_res_slope", s.global_res_slope()},
                      {"max_global_ratio_dev", s.max_ratio_dev},
                      {"ratio_dev_slope", s.ratio_dev_slope()},
                      {"undefined_points", s.undefined_steps}};
            if (!s.ratio_defined) {
                const std::string why =
                    "at step " + std::to_string(s.first_unresolved_ratio) +
                    " the round-off eps S(z_n) / |e^{-2 Gamma} I_0| of e^{2 Gamma} I_n / I_0 "
                    "exceeds max(1e-8, 1e-2 |ratio - 1|) (I_0 = " +
                    json(rec.initial_invariant(k)).dump() +
                    ", scale S(z_0) = " + json(s.scale_initial).dump() + "); read max_global_res";
                set_undefined(o, "max_global_ratio_dev", why);
                set_undefined(o, "ratio_dev_slope", why);
            }
            if (s.undefined_steps > 0) {
                const std::string why = "scale not a positive normal number (state ~0 or not "
                                        "finite) at step " +
                                        std::to_string(s.first_undefined_step) + " and " +
                                        std::to_string(s.undefined_steps - 1) + " more";
                for (const char* key :
                     {"max_step_res", "last_step_res", "max_global_res", "global_res_slope"})
                    set_undefined(o, key, why);
            }
            inv[std::string(P::invariant_names[k])] = o;
        }
        return inv;
    }

    // A metric with no defined value here: null, and its reason under "undefined" in the same
    // object; a check on it fails with that reason (finish()).
    static void set_undefined(json& o, const std::string& key, const std::string& reason) {
        o[key] = nullptr;
        o["undefined"][key] = reason;
    }

    // d(t) = ln(max q) + Γ(t) at the positive maxima; a maximum of q at or below 0 has no d(t)
    // (over-damped motion): then every d(t) metric is undefined, with the count as the reason.
    static json drift_of(const std::vector<Maximum>& mx, std::int64_t nonpositive) {
        json out = {{"maxima", mx.size()}, {"maxima_nonpositive", nonpositive}};
        if (nonpositive > 0) {
            const std::string why =
                std::to_string(nonpositive) + " maxima of q are <= 0, where ln(max q) is undefined";
            for (const char* key : {"slope", "range"}) set_undefined(out, key, why);
            return out;
        }
        if (mx.size() < 3) return out; // slope missing: a check on it fails with that reason
        std::vector<double> t, d;
        double lo = mx[0].d, hi = mx[0].d;
        for (const auto& m : mx) {
            t.push_back(m.t);
            d.push_back(m.d);
            lo = std::min(lo, m.d);
            hi = std::max(hi, m.d);
        }
        out["slope"] = least_squares(t, d).slope;
        out["range"] = hi - lo;
        out["first"] = {mx.front().t, mx.front().d};
        out["last"] = {mx.back().t, mx.back().d};
        return out;
    }

    // d(t) of the method; with a reference on the output grid also d(t) of the reference (same
    // maxima locator on the reference samples) and the differences, maximum by maximum.
    // E_n of conventions §5 from the exact step Jacobian, in a separate pass with its own stepper
    // and counters (the main run's cost and timing stay those of the bare step).
    template <class K>
    json conformal_symplectic_metrics(const MethodInfo& info, double h, std::int64_t n) const {
        Counters counters;
        K stepper(problem_, info, h, counters);
        Vec z = problem_.initial_state();
        const ConformalSymplecticStats st =
            conformal_symplectic_defect(stepper, problem_, z, c_.t0, h, n);
        if (!st.applicable()) return {{"reason", to_string(st.applicability)}};
        json out = {{"max_rel", st.max_rel},
                    {"last_rel", st.last_rel},
                    {"max_abs", st.max_abs},
                    {"last_abs", st.last_abs},
                    {"max_rel_step", st.max_rel_step},
                    {"steps_measured", st.steps_measured},
                    {"norm", ConformalSymplecticStats::norm},
                    {"status", to_string(st.status)}};
        if (st.status != RunStatus::ok) out["failed_at_step"] = st.failed_step;
        if (st.rel_undefined_steps > 0) {
            out["rel_undefined_steps"] = st.rel_undefined_steps;
            if (st.max_rel_step == 0)
                for (const char* key : {"max_rel", "last_rel"})
                    set_undefined(out, key,
                                  "e^{-2 dGamma} per step is below the double range "
                                  "(dGamma > ~354 per step) at every measured step");
        }
        return out;
    }

    json drift_metrics(const Recorder<P>& rec) const {
        const std::vector<Maximum> mx = rec.maxima();
        json out = drift_of(mx, rec.nonpositive_maxima());
        if constexpr (HasOneDofMaxima<P>) {
            if (reference_ok_ && ref_.cols() > 2 && ref_.cols() == points_ + 1) {
                MaximaFinder<P> finder(problem_, c_.t0);
                for (Eigen::Index i = 0; i < ref_.cols(); ++i)
                    finder.feed(grid_time(i), ref_.col(i));
                const auto& rm = finder.maxima();
                const json ref = drift_of(rm, finder.nonpositive());
                out["reference"] = ref;
                if (ref.contains("slope") && out.contains("slope") && ref["slope"].is_number() &&
                    out["slope"].is_number())
                    out["slope_minus_reference"] =
                        out["slope"].get<double>() - ref["slope"].get<double>();
                double max_diff = 0.0;
                const std::size_t k = std::min(mx.size(), rm.size());
                for (std::size_t i = 0; i < k; ++i)
                    max_diff = std::max(max_diff, std::abs(mx[i].d - rm[i].d));
                out["max_abs_diff_reference"] = max_diff;
                out["maxima_count_diff"] =
                    static_cast<std::int64_t>(mx.size()) - static_cast<std::int64_t>(rm.size());
            }
        }
        return out;
    }

    double grid_time(Eigen::Index i) const {
        if (i == points_) return c_.t_end;
        return c_.t0 + static_cast<double>(i) * (c_.t_end - c_.t0) / static_cast<double>(points_);
    }

    // B Table 3.1 factor of Σp per step the method declares (constant γ only), NaN if none.
    double table_momentum_factor(const MethodInfo& info, double h) const {
        if (!P::constant_gamma) return std::numeric_limits<double>::quiet_NaN();
        const double gh = problem_.dGamma(c_.t0, h);
        if (info.claims & claim_linear_momentum_cayley)
            return std::exp(-gh) * (2.0 - gh) / (2.0 + gh);
        if (info.claims & claim_linear_momentum) return std::exp(-2.0 * gh);
        return std::numeric_limits<double>::quiet_NaN();
    }

    json momentum_metrics(const Recorder<P>& rec, const MethodInfo& info, double h) const {
        auto one = [](const VectorLawStats& s, bool with_table, const char* scale) {
            json o = {{"scale", scale},
                      {"scale_initial", s.scale_initial},
                      {"max_law_res", s.max_law_res},
                      {"last_law_res", s.last_law_res},
                      {"max_law_abs", s.max_law_abs},
                      {"scale_at_max_law_res", s.scale_at_max},
                      {"first_factor", s.first_factor},
                      {"max_factor_dev", s.max_factor_dev},
                      {"initial_norm", s.initial_norm},
                      {"undefined_points", s.undefined_steps},
                      {"factor_undefined_points", s.factor_undefined_steps}};
            if (with_table) o["max_table_res"] = s.max_table_res;
            if (s.undefined_steps > 0) {
                const std::string why = "scale not a positive normal number at step " +
                                        std::to_string(s.first_undefined_step);
                for (const char* key : {"max_law_res", "last_law_res", "max_table_res"})
                    if (o.contains(key)) set_undefined(o, key, why);
            }
            if (s.factor_undefined_steps > 0) {
                const std::string why =
                    "|X_n| < 1e-8 x scale at step " +
                    std::to_string(s.first_factor_undefined_step) + " (" +
                    std::to_string(s.factor_undefined_steps) +
                    " steps): the factor X_{n+1}.X_n/|X_n|^2 is round-off there";
                set_undefined(o, "max_factor_dev", why);
                if (s.first_factor_undefined_step == 0) set_undefined(o, "first_factor", why);
            }
            return o;
        };
        json ang = one(rec.angular_momentum_stats(), false, "sum_i |q_i| |p_i|");
        if constexpr (requires { P::linear_momentum_law; }) {
            // e.g. Kepler's fixed centre: Σp has no law, only the angular momentum is reported.
            if (!P::linear_momentum_law)
                return {{"angular", ang}, {"linear", {{"reason", "no linear momentum law"}}}};
        }
        const double table = table_momentum_factor(info, h);
        json lin = one(rec.linear_momentum_stats(), !std::isnan(table), "sum_i |p_i|");
        lin["law_factor"] = std::exp(-2.0 * problem_.dGamma(c_.t0, h));
        if (!std::isnan(table)) {
            lin["table_factor"] = table;
            lin["table_source"] = "B Table 3.1";
        }
        return {{"linear", lin}, {"angular", ang}};
    }

    // Poincaré section at t = t0 + kT, T the forcing period (B §3.2.2): the output grid must be
    // exactly the section times. The angle is compared on the circle. Pointwise distances to the
    // reference's section, and set distances (nearest reference point, symmetric Hausdorff) after
    // the first 10% of sections (transient), which stay meaningful where a chaotic orbit has
    // separated from the reference pointwise.
    json poincare_metrics(const Recorder<P>& rec) const {
        if constexpr (HasForcingPeriod<P>) {
            const double T = problem_.forcing_period();
            const double spacing = (c_.t_end - c_.t0) / static_cast<double>(points_);
            if (std::abs(spacing - T) > 1e-9 * T)
                return {{"reason", "output_dt must equal the forcing period " + std::to_string(T)}};
            if (!reference_ok_) return {{"reason", "reference failed"}};
            const Mat& g = rec.grid();
            auto dist = [](const Vec& a, const Vec& b) {
                double s = std::remainder(a[0] - b[0], 2.0 * M_PI);
                s *= s;
                for (Eigen::Index i = 1; i < a.size(); ++i) s += (a[i] - b[i]) * (a[i] - b[i]);
                return std::sqrt(s);
            };
            double pmax = 0.0;
            for (Eigen::Index k = 0; k < g.cols(); ++k)
                pmax = std::max(pmax, dist(g.col(k), ref_.col(k)));
            const Eigen::Index skip = g.cols() / 10;
            auto nearest = [&](const Mat& from, const Mat& to, double& mean) {
                double worst = 0.0, sum = 0.0;
                for (Eigen::Index i = skip; i < from.cols(); ++i) {
                    double best = std::numeric_limits<double>::infinity();
                    for (Eigen::Index j = skip; j < to.cols(); ++j)
                        best = std::min(best, dist(from.col(i), to.col(j)));
                    worst = std::max(worst, best);
                    sum += best;
                }
                mean = sum / static_cast<double>(std::max<Eigen::Index>(1, from.cols() - skip));
                return worst;
            };
            double mean_mr = 0.0, mean_rm = 0.0;
            const double h1 = nearest(g, ref_, mean_mr), h2 = nearest(ref_, g, mean_rm);
            return {{"sections", g.cols()},
                    {"transient_skipped", skip},
                    {"pointwise_max", pmax},
                    {"pointwise_final", dist(g.col(g.cols() - 1), ref_.col(ref_.cols() - 1))},
                    {"set_mean", 0.5 * (mean_mr + mean_rm)},
                    {"set_hausdorff", std::max(h1, h2)}};
        } else {
            (void)rec;
            return {{"reason", "problem has no periodic forcing"}};
        }
    }

    // HLW(3.8) temperature on the output grid: its fluctuation and, with a reference, its error.
    json temperature_metrics(const Recorder<P>& rec) const {
        if constexpr (HasTemperature<P>) {
            const Mat& g = rec.grid();
            const double T0 = problem_.temperature(g.col(0));
            double lo = T0, hi = T0, sum = 0.0, max_err = 0.0;
            const bool with_ref = reference_ok_ && ref_.cols() == g.cols();
            for (Eigen::Index i = 0; i < g.cols(); ++i) {
                const double T = problem_.temperature(g.col(i));
                lo = std::min(lo, T);
                hi = std::max(hi, T);
                sum += T;
                if (with_ref)
                    max_err = std::max(max_err, std::abs(T - problem_.temperature(ref_.col(i))));
            }
            json out = {{"initial", T0},
                        {"mean", sum / static_cast<double>(g.cols())},
                        {"min", lo},
                        {"max", hi},
                        {"max_abs_dev_initial", std::max(hi - T0, T0 - lo)}};
            if (with_ref) out["max_abs_error"] = max_err;
            return out;
        } else {
            (void)rec;
            return {{"reason", "problem declares no temperature"}};
        }
    }

    template <class K>
    json stability_metrics(const MethodInfo& info, double h) const {
        const Mat M = one_step_matrix<K>(problem_, info, h);
        const double g = problem_.gamma_at(0.0);
        const OneStepAnalysis a = analyse_one_step(M, g, h);
        const double det_expected = std::exp(-2.0 * g * h);
        const double exact_half_trace = oscillator_damped_cs(problem_.omega, g, h).c;
        json out = {{"det", a.det},
                    {"det_expected", det_expected},
                    {"det_rel_err", std::abs(a.det - det_expected) / det_expected},
                    {"det_abs_err", std::abs(a.det - det_expected)},
                    {"half_trace", a.half_trace},
                    {"half_trace_exact", exact_half_trace},
                    {"half_trace_exact_err", std::abs(a.half_trace - exact_half_trace)},
                    {"eigenvalues",
                     {{a.eig[0].real(), a.eig[0].imag()}, {a.eig[1].real(), a.eig[1].imag()}}},
                    {"spectral_radius", a.spectral_radius},
                    {"F_condition", a.F_condition ? 1 : 0},
                    {"power_bounded", a.power_bounded ? 1 : 0},
                    {"matrix", {{M(0, 0), M(0, 1)}, {M(1, 0), M(1, 1)}}}};
        // e^{−2γh} underflows for γh > ~354: det M against it is then round-off over nothing.
        if (!(det_expected >= std::numeric_limits<double>::min()))
            set_undefined(out, "det_rel_err", "e^{-2 gamma h} underflows: compare det_abs_err");
        if (oscillator_formulas(info.id).half_trace) {
            const double f = oscillator_formulas(info.id).half_trace(problem_.omega, g, h);
            out["half_trace_formula"] = f;
            out["half_trace_formula_abs_err"] = std::abs(a.half_trace - f);
            // ½tr M passes through 0 (hω near the threshold): relative to |f| only where f is
            // resolved on the eigenvalues' scale e^{−γh}, else undefined (read the absolute error)
            const double radius = std::exp(-g * h);
            if (std::abs(f) > 1e-8 * radius && radius >= std::numeric_limits<double>::min())
                out["half_trace_formula_rel_err"] = std::abs(a.half_trace - f) / std::abs(f);
            else
                set_undefined(out, "half_trace_formula_rel_err",
                              "F's half trace is 0 on the scale e^{-gamma h}: compare "
                              "half_trace_formula_abs_err");
            out["formula_source"] = oscillator_formulas(info.id).source;
        }
        return out;
    }

    // (γ, h) sweep of F's condition and power-boundedness (conventions §5, F Figs 3.1–3.3). The
    // sweep of one method is split into independent tasks of sweep_rows_per_task γ rows; each
    // writes only its own pre-sized row slots and finish() assembles the rows in grid order
    // (sweep_json), so the report does not depend on --jobs or on the order in which tasks run.
    struct SweepRow {
        std::int64_t first_emp = 0, first_formula = 0, first_pb = 0, first_pb_formula = 0;
        std::int64_t f_viol = 0, pb_viol = 0, violations_inside = 0;
        std::int64_t mismatch = 0, pb_mismatch = 0;
        double max_trace_err = 0.0; // |½trM − e^{−γh}cos(βh)| over the row (F Fig 3.4)
    };
    static constexpr std::size_t sweep_rows_per_task = 8;

    // Analytic power-boundedness from the stability function R(z), for RK methods on the full
    // vector field (M = R(hA) on the linear oscillator).
    static bool has_power_formula(const MethodInfo& info) { return plain_tableau(info) != nullptr; }

    void sweep_tasks(std::size_t m, std::vector<std::function<void()>>& tasks) {
        if constexpr (P::is_linear) {
            if (sweep_rows_.size() != c_.methods.size()) { // first method: the shared grid
                sweep_gammas_ = c_.sweep->gamma.values();
                sweep_hs_ = c_.sweep->h.values();
                sweep_rows_.assign(c_.methods.size(), {});
            }
            const std::size_t n = sweep_gammas_.size();
            sweep_rows_[m].assign(n, SweepRow{});
            for (std::size_t r0 = 0; r0 < n; r0 += sweep_rows_per_task) {
                const std::size_t r1 = std::min(n, r0 + sweep_rows_per_task);
                tasks.emplace_back([this, m, r0, r1] {
                    for (std::size_t r = r0; r < r1; ++r) sweep_rows_[m][r] = sweep_row(m, r);
                });
            }
        } else {
            (void)m;
            (void)tasks;
        }
    }

    SweepRow sweep_row(std::size_t m, std::size_t r) const {
        const MethodInfo& info = method(m);
        const double omega = c_.sweep->omega, g = sweep_gammas_[r];
        const bool has_formula = oscillator_formulas(info.id).F_condition != nullptr;
        const bool has_pb_formula = has_power_formula(info);
        const auto nh = static_cast<std::int64_t>(sweep_hs_.size());
        SweepRow row;
        row.first_emp = row.first_formula = row.first_pb = row.first_pb_formula = nh;
        for (std::int64_t i = 0; i < nh; ++i) {
            const double h = sweep_hs_[static_cast<std::size_t>(i)];
            Oscillator osc;
            osc.omega = omega;
            osc.gamma = g;
            OneStepAnalysis a;
            with_kernel<Oscillator>(info, [&]<class K>() {
                a = analyse_one_step(one_step_matrix<K>(osc, info, h), g, h);
            });
            row.max_trace_err = std::max(
                row.max_trace_err, std::abs(a.half_trace - oscillator_damped_cs(omega, g, h).c));
            if (!a.F_condition) {
                row.first_emp = std::min(row.first_emp, i);
                ++row.f_viol;
                if (omega > g) ++row.violations_inside;
            }
            if (!a.power_bounded) {
                row.first_pb = std::min(row.first_pb, i);
                ++row.pb_viol;
            }
            if (has_formula) {
                const bool fc = oscillator_formulas(info.id).F_condition(omega, g, h);
                if (!fc) row.first_formula = std::min(row.first_formula, i);
                if (fc != a.F_condition) ++row.mismatch;
            }
            if (has_pb_formula) {
                const bool pb = rk_power_analysis(*plain_tableau(info), omega, g, h).power_bounded;
                if (!pb) row.first_pb_formula = std::min(row.first_pb_formula, i);
                if (pb != a.power_bounded) ++row.pb_mismatch;
            }
        }
        return row;
    }

    // The method's sweep from its rows (called by finish(), after every row task has run).
    json sweep_json(std::size_t m) const {
        const MethodInfo& info = method(m);
        const bool has_formula = oscillator_formulas(info.id).F_condition != nullptr;
        const bool has_pb_formula = has_power_formula(info);
        const auto nh = static_cast<std::int64_t>(sweep_hs_.size());
        auto h_at = [&](std::int64_t i) {
            return i < nh ? json(sweep_hs_[static_cast<std::size_t>(i)]) : json(nullptr);
        };
        json rows = json::array();
        std::int64_t mismatch_points = 0, violations_inside = 0, f_viol = 0, pb_viol = 0;
        std::int64_t pb_mismatch_points = 0, max_cells = 0, max_pb_cells = 0;
        for (std::size_t r = 0; r < sweep_rows_[m].size(); ++r) {
            const SweepRow& s = sweep_rows_[m][r];
            f_viol += s.f_viol;
            pb_viol += s.pb_viol;
            violations_inside += s.violations_inside;
            mismatch_points += s.mismatch;
            pb_mismatch_points += s.pb_mismatch;
            json row = {{"gamma", sweep_gammas_[r]},
                        {"h_F_empirical", h_at(s.first_emp)},
                        {"h_power_unbounded", h_at(s.first_pb)},
                        {"max_half_trace_err", s.max_trace_err}};
            if (has_formula) {
                row["h_F_formula"] = h_at(s.first_formula);
                max_cells = std::max(max_cells, std::abs(s.first_emp - s.first_formula));
            }
            if (has_pb_formula) {
                row["h_power_formula"] = h_at(s.first_pb_formula);
                max_pb_cells = std::max(max_pb_cells, std::abs(s.first_pb - s.first_pb_formula));
            }
            rows.push_back(row);
        }
        json out = {{"omega", c_.sweep->omega},
                    {"rows", rows},
                    {"F_violations", f_viol},
                    {"power_bounded_violations", pb_viol},
                    {"violations_omega_gt_gamma", violations_inside},
                    {"grid", {{"gamma", sweep_gammas_.size()}, {"h", sweep_hs_.size()}}}};
        if (!rows.empty()) {
            // the smallest γ of the grid (γ = 0 in the stress maps): where the classical
            // absolute-stability limits (hω < 2, √3, 2√2) can be compared with the grid
            const json& r0 = rows[0];
            out["first_row"] = {{"gamma", r0["gamma"]},
                                {"h_F_empirical", r0["h_F_empirical"]},
                                {"h_power_unbounded", r0["h_power_unbounded"]}};
        }
        if (has_formula) {
            out["max_boundary_mismatch_cells"] = max_cells;
            out["mismatch_points"] = mismatch_points;
            out["formula_source"] = oscillator_formulas(info.id).source;
        }
        if (has_pb_formula) {
            out["max_power_boundary_mismatch_cells"] = max_pb_cells;
            out["power_mismatch_points"] = pb_mismatch_points;
            out["power_formula_source"] = "stability function R(z) of the tableau at h*lambda";
        }
        return out;
    }

    // The run record's own fields as metrics "run.<field>" (any status: a check may expect a
    // divergence, or an exact step or evaluation count; conventions §7 report fields).
    static json run_record_metrics(const json& run) {
        json r = json::object();
        for (const char* k :
             {"steps", "steps_planned", "rhs_evals", "jac_evals", "newton_iters", "final_time"})
            if (run.contains(k)) r[k] = run[k];
        const std::string status = run.value("status", std::string());
        r["ok"] = status == "ok" ? 1 : 0;
        r["diverged"] = status == "diverged" ? 1 : 0;
        r["failed_at_step"] = run.value("failed_at_step", std::int64_t{0});
        return {{"run", r}};
    }

    // The reason set_undefined() recorded for metric "a.b.key" (under "a.b".undefined.key), or "".
    static std::string undefined_reason(const json& metrics, const std::string& metric) {
        const auto dot = metric.rfind('.');
        const json* parent = lookup(metrics, metric.substr(0, dot));
        if (!parent || !parent->is_object() || !parent->contains("undefined")) return {};
        const json& u = (*parent)["undefined"];
        const std::string key = metric.substr(dot + 1);
        return u.contains(key) && u[key].is_string() ? u[key].get<std::string>() : std::string();
    }

    // A check that combines runs (docs/case-keys.md): the ratio metric(A) / metric(B) or the
    // spread max/min over several methods at each step size, or (across_dt) the log–log slope of
    // those values, or of one method's metric, against dt over the ladder. One check entry; its
    // "inputs" list every metric value it used.
    json comparison_check(const CheckSpec& cs, const std::string& mid,
                          std::optional<double> only_dt) const {
        const std::vector<std::string> members =
            cs.form == CheckForm::per_method ? std::vector<std::string>{mid} : cs.methods;
        std::string label;
        const char* sep = cs.form == CheckForm::ratio ? " / " : ", ";
        for (const auto& m : members) label += (label.empty() ? "" : sep) + m;
        if (cs.form == CheckForm::spread) label = "spread(" + label + ")";
        json ck = {{"name", cs.name},
                   {"metric", cs.metric},
                   {"method", label},
                   {"op", op_name(cs.op)},
                   {"expected", cs.value},
                   {"negative_control", cs.negative_control},
                   {"form", cs.form == CheckForm::ratio    ? "ratio"
                            : cs.form == CheckForm::spread ? "spread"
                                                           : "per-method"},
                   {"methods", members}};
        if (cs.op == CheckOp::near) ck["tolerance"] = cs.tol;
        if (cs.use_abs) ck["abs"] = true;
        if (cs.refutes) ck["refutes"] = true;
        if (!cs.note.empty()) ck["note"] = cs.note;
        if (cs.across_dt_slope) ck["across_dt"] = "loglog-slope";
        if (only_dt) ck["dt"] = *only_dt;
        json inputs = json::array();
        std::vector<double> hs, values;
        std::string missing;
        for (std::size_t d = 0; d < c_.dts.size(); ++d) {
            if (only_dt && *only_dt != c_.dts[d]) continue;
            json row = {{"dt", c_.dts[d]}};
            std::vector<double> xs;
            for (const auto& m : members) {
                const auto mi = static_cast<std::size_t>(
                    std::find(c_.methods.begin(), c_.methods.end(), m) - c_.methods.begin());
                const json& r = runs_[mi * c_.dts.size() + d];
                const json* v = r.contains("metrics") ? lookup(r["metrics"], cs.metric) : nullptr;
                if (r.value("status", std::string()) != "ok" || !v || !v->is_number()) {
                    if (missing.empty())
                        missing = m + " at dt = " + json(c_.dts[d]).dump() + ": " +
                                  (r.value("status", std::string()) != "ok"
                                       ? "run " + r.value("status", std::string("missing"))
                                       : "metric not produced");
                    row[m] = nullptr;
                    continue;
                }
                xs.push_back(v->get<double>());
                row[m] = xs.back();
            }
            if (xs.size() == members.size()) {
                double x = xs[0];
                if (cs.form == CheckForm::ratio) {
                    x = xs[0] / xs[1];
                } else if (cs.form == CheckForm::spread) {
                    x = *std::max_element(xs.begin(), xs.end()) /
                        *std::min_element(xs.begin(), xs.end());
                }
                row["value"] = x;
                hs.push_back(c_.dts[d]);
                values.push_back(x);
            }
            inputs.push_back(row);
        }
        ck["inputs"] = inputs;
        auto fail_with = [&](const std::string& why) {
            ck["passed"] = false;
            ck["value"] = nullptr;
            ck["message"] = why;
            return ck;
        };
        if (!missing.empty()) return fail_with(missing);
        double x = 0.0;
        if (cs.across_dt_slope) {
            std::vector<double> lx, ly;
            for (std::size_t i = 0; i < hs.size(); ++i) {
                if (!(values[i] > 0.0) || !std::isfinite(values[i]))
                    return fail_with("log-log slope needs positive values");
                lx.push_back(std::log(hs[i]));
                ly.push_back(std::log(values[i]));
            }
            x = least_squares(lx, ly).slope;
        } else {
            x = values.front(); // one step size (only_dt)
        }
        ck["value"] = x;
        ck["passed"] = std::isfinite(x) && check_passes(cs, x);
        return ck;
    }

    std::vector<double> sweep_gammas_, sweep_hs_;
    std::vector<std::vector<SweepRow>> sweep_rows_; // [method][γ row], pre-sized in sweep_tasks

    // Leading coefficient of ½trM − e^{−γh}cos(βh) = c h⁴ + O(h⁵), by Richardson extrapolation of
    // the measured (½trM − exact)/h⁴ at h = 0.02 and 0.01 (conventions §5).
    void trace_taylor(std::size_t m) {
        const MethodInfo& info = method(m);
        json& out = method_metrics_[m]["trace-taylor"];
        if constexpr (P::is_linear) {
            const double w = problem_.omega, g = problem_.gamma;
            auto coeff = [&](double h) {
                double c = std::numeric_limits<double>::quiet_NaN();
                with_kernel<P>(info, [&]<class K>() {
                    const OneStepAnalysis a =
                        analyse_one_step(one_step_matrix<K>(problem_, info, h), g, h);
                    c = (a.half_trace - oscillator_damped_cs(w, g, h).c) / (h * h * h * h);
                });
                return c;
            };
            const double c = std::abs(2.0 * coeff(0.01) - coeff(0.02));
            out = {{"h4_coeff", c}};
            if (oscillator_formulas(info.id).h4_coefficient) {
                const double e = std::abs(oscillator_formulas(info.id).h4_coefficient(w, g));
                out["h4_coeff_expected"] = e;
                out["h4_coeff_abs_err"] = std::abs(c - e);
                // the expected coefficient vanishes (cimp at ω = γ): no relative error
                const double scale = (w * w + g * g) * (w * w + g * g);
                if (e > 1e-12 * scale)
                    out["h4_coeff_rel_err"] = std::abs(c - e) / e;
                else
                    set_undefined(out, "h4_coeff_rel_err",
                                  "expected h^4 coefficient is 0: compare h4_coeff_abs_err");
            }
        }
    }

    const CaseSpec& c_;
    P problem_;
    bool needs_grid_ = false;
    std::int64_t points_ = 1;
    std::vector<double> ref_times_;
    Mat ref_;
    json reference_;
    bool reference_ok_ = true;
    double ref_error_ = 0.0; // the reference's certified error estimate (0 for exact references)
    std::vector<json> runs_;
    std::vector<json> method_metrics_;
};

template <class P>
json TypedCase<P>::finish() {
    // Stability sweeps (method level) from their row tasks, in grid order.
    if (c_.wants("stability-sweep") && sweep_rows_.size() == c_.methods.size())
        for (std::size_t m = 0; m < c_.methods.size(); ++m)
            method_metrics_[m]["stability-sweep"] = sweep_json(m);
    // Order fits (method level): "order" from the global error of each run of the ladder,
    // "local-order" from the one-step error (B Fig 3.2; the exact solution, no reference error).
    for (const char* diag : {"order", "local-order"}) {
        if (!c_.wants(diag)) continue;
        const bool global = std::string(diag) == "order";
        // Round-off floor, and conventions §4: no fit uses an error within 100× the reference's
        // estimate.
        const double roundoff =
            1000.0 * std::numeric_limits<double>::epsilon() *
            (reference_ok_ && global ? std::max(1.0, ref_.col(ref_.cols() - 1).norm()) : 1.0);
        const double ref_error = global ? ref_error_ : 0.0;
        const double floor = std::max(roundoff, 100.0 * ref_error);
        for (std::size_t m = 0; m < c_.methods.size(); ++m) {
            std::vector<OrderPoint> pts;
            for (std::size_t d = 0; d < c_.dts.size(); ++d) {
                const json& r = run_slot(m, d);
                const json* e =
                    lookup(r["metrics"], global ? "error.final_abs" : "local-error.abs");
                pts.push_back({c_.dts[d], e && e->is_number()
                                              ? e->get<double>()
                                              : std::numeric_limits<double>::quiet_NaN()});
            }
            const OrderFit fit = fit_order(pts, floor);
            json o = {{"ok", fit.ok},
                      {"window_dt", fit.window_h},
                      {"local_orders", fit.local_orders},
                      {"floor", floor},
                      {"floor_source", 100.0 * ref_error > roundoff
                                           ? "100x reference error estimate"
                                           : "round-off"}};
            if (fit.ok) {
                o["slope"] = fit.slope;
                o["r2"] = fit.r2;
                o["points"] = fit.window_h.size();
            } else {
                o["reason"] = fit.reason;
            }
            json dropped = json::array();
            for (const auto& dp : fit.dropped)
                dropped.push_back({{"dt", dp.h}, {"error", dp.error}, {"reason", dp.reason}});
            o["dropped"] = dropped;
            method_metrics_[m][diag] = o;
        }
    }

    json checks = json::array();
    for (const CheckSpec& cs : c_.checks) {
        const std::string diag = cs.metric.substr(0, cs.metric.find('.'));
        const bool method_level = diagnostic_is_method_level(diag);
        for (const std::string& mid : cs.methods) {
            const auto mi = static_cast<std::size_t>(
                std::find(c_.methods.begin(), c_.methods.end(), mid) - c_.methods.begin());
            auto evaluate = [&](const json& metrics, const json* run) {
                json ck = {{"name", cs.name},      {"metric", cs.metric},
                           {"method", mid},        {"op", op_name(cs.op)},
                           {"expected", cs.value}, {"negative_control", cs.negative_control}};
                if (cs.op == CheckOp::near) ck["tolerance"] = cs.tol;
                if (cs.use_abs) ck["abs"] = true;
                if (cs.refutes) ck["refutes"] = true;
                if (!cs.note.empty()) ck["note"] = cs.note;
                if (run) ck["dt"] = (*run)["dt"];
                // "run.*" reads the run record itself; "stability.*" describes the one-step
                // matrix M, not the trajectory: both are evaluated whatever the run's status.
                const json run_view = diag == "run" && run ? run_record_metrics(*run) : json();
                const json* v = lookup(diag == "run" ? run_view : metrics, cs.metric);
                if (run && (*run)["status"] != "ok" && diag != "run" && diag != "stability") {
                    ck["passed"] = false;
                    ck["value"] = nullptr;
                    ck["message"] =
                        "run " + (*run)["status"].get<std::string>() +
                        ((*run).contains("failed_at_step")
                             ? " at step " +
                                   std::to_string((*run)["failed_at_step"].get<std::int64_t>())
                             : std::string());
                } else if ((!v || !v->is_number()) && !reference_ok_ &&
                           (diag == "error" || diag == "energy" || diag == "order")) {
                    ck["passed"] = false;
                    ck["value"] = nullptr;
                    ck["message"] = "reference failed: " + reference_.value("error", std::string());
                } else if (v && v->is_null() && !undefined_reason(metrics, cs.metric).empty()) {
                    // defined nowhere here (recorder.hpp, docs/conventions.md): fails, whatever
                    // the check's direction (a negative control too), with the reason
                    ck["passed"] = false;
                    ck["value"] = nullptr;
                    ck["message"] = "metric undefined: " + undefined_reason(metrics, cs.metric);
                } else if (!v || !v->is_number()) {
                    ck["passed"] = false;
                    ck["value"] = nullptr;
                    ck["message"] =
                        "metric not produced" +
                        (method_level && metrics.contains(diag) && metrics[diag].contains("reason")
                             ? ": " + metrics[diag]["reason"].get<std::string>()
                             : std::string());
                } else {
                    const double x = v->get<double>();
                    ck["value"] = x;
                    ck["passed"] = check_passes(cs, x);
                }
                checks.push_back(ck);
            };
            if (cs.form != CheckForm::per_method || cs.across_dt_slope) {
                if (&mid != &cs.methods.front() && cs.form != CheckForm::per_method) continue;
                if (cs.across_dt_slope) {
                    checks.push_back(comparison_check(cs, mid, std::nullopt));
                } else {
                    for (double h : c_.dts)
                        if (!cs.dt || *cs.dt == h) checks.push_back(comparison_check(cs, mid, h));
                }
            } else if (method_level) {
                evaluate(method_metrics_[mi], nullptr);
            } else {
                for (std::size_t d = 0; d < c_.dts.size(); ++d) {
                    if (cs.dt && *cs.dt != c_.dts[d]) continue;
                    const json& r = run_slot(mi, d);
                    evaluate(r["metrics"], &r);
                }
            }
        }
    }

    json runs = json::array();
    for (const auto& r : runs_) runs.push_back(r);
    json mm = json::object();
    for (std::size_t m = 0; m < c_.methods.size(); ++m)
        if (!method_metrics_[m].empty()) mm[c_.methods[m]] = method_metrics_[m];
    json params = json::object();
    for (const auto& [k, v] : c_.params.scalars) params[k] = v;
    for (const auto& [k, v] : c_.params.arrays) params[k] = v;
    json out = {{"id", c_.id},
                {"title", c_.title},
                {"source", c_.source},
                {"file", c_.file},
                {"problem", {{"id", c_.problem_id}, {"params", params}}},
                {"methods", c_.methods},
                {"t0", c_.t0},
                {"t_end", c_.t_end},
                {"dt_ladder", c_.dts},
                {"diagnostics", c_.diagnostics},
                {"overrides", c_.overrides},
                {"reference", reference_},
                {"runs", runs},
                {"method_metrics", mm},
                {"checks", checks}};
    if (!c_.no_checks_because.empty()) out["no_checks_because"] = c_.no_checks_because;
    if (!c_.measures.empty()) out["measures"] = c_.raw["measures"];
    return out;
}

// The case job for c if its problem type is in shard K of N (index in ProblemList mod N == K),
// else null. Explicitly instantiated once per shard in the generated case_shard_K.cpp.
template <int K, int N>
std::unique_ptr<CaseJob> make_case_shard(const CaseSpec& c) {
    std::unique_ptr<CaseJob> job;
    int index = 0;
    for_each_type(ProblemList{}, [&]<class P>() {
        if (index++ % N == K && !job && P::id == c.problem_id)
            job = std::make_unique<TypedCase<P>>(c);
    });
    return job;
}

} // namespace dampsym::detail
