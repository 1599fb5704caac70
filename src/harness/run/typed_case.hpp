// The typed case runner: TypedCase<P> holds only what must know the problem type P: the run's
// observer (Recorder<P>), the exact or certified reference of P, and the typed hooks of the
// diagnostics (one-step matrix, Jacobian pass, local error, problem functions handed to the
// compiled-once metric producers). It never instantiates a kernel: the run's step loop and the
// steppers of the diagnostics' passes come from the (kernel, problem) pair's KernelOps<P>
// (kernel_ops.hpp), compiled once in the kernel shards. Everything else (run records, order fits,
// sweep bookkeeping, checks, report JSON, metric JSON) is compiled once in case_run.cpp,
// checks.cpp, measures.cpp and src/diagnostics/*_diagnostic.cpp. It is instantiated only in the
// generated shard translation units (src/harness/run/case_shard.cpp.in: every problem type whose
// index in ProblemList falls in shard K), so they compile in parallel; adding a problem or a
// kernel touches no runner file.
#pragma once

#include "core/integrate.hpp"
#include "core/problem_concepts.hpp"
#include "diagnostics/diagnostic_list.hpp"
#include "diagnostics/problem_check_json.hpp"
#include "diagnostics/recorder.hpp"
#include "harness/figures/series.hpp" // figures hook
#include "harness/problem_list.hpp"
#include "harness/run/case_run.hpp"
#include "harness/run/grid_stream.hpp" // the output grid streamed
#include "harness/run/kernel_ops.hpp"
#include "harness/run/limits.hpp"
#include "harness/run/view.hpp"

#include <cmath>
#include <optional>
#include <vector>

namespace dampsym::detail {

template <class P>
class TypedCase final : public CaseRun {
public:
    explicit TypedCase(const CaseSpec& spec)
        : CaseRun(spec), problem_(P::from_params(spec.params)) {}

    void prepare() override {
        plan(HasExactSolution<P>);
        if (figures_) series_.assign(runs_.size(), json()); // figures hook
        if (!needs_reference()) {
            reference_ = {{"kind", "none"}};
            return;
        }
        if constexpr (HasExactSolution<P>) {
            const auto np = static_cast<Eigen::Index>(ref_times_.size());
            Mat ref(problem_.dim(), np);
            Vec tmp(problem_.dim());
            const Vec z0 = problem_.initial_state(); // the state at t0 (core/problem.hpp)
            for (Eigen::Index i = 0; i < np; ++i) {
                problem_.exact(c_.t0, z0, ref_times_[static_cast<std::size_t>(i)], tmp);
                ref.col(i) = tmp;
            }
            set_exact_reference(std::move(ref));
        } else {
            auto sol = reference_cache().get(reference_key(c_, ref_times_), [&] {
                ReferenceRequest req = reference_request(problem_, c_, ref_times_);
                poison_reference(req, fault_for(c_.id, "(reference)")); // tests only (limits.hpp)
                stop_reference_with(req, guard_); // stops at the case's time budget
                return certified_reference(req);
            });
            set_numerical_reference(*sol);
        }
    }

    void add_tasks(std::vector<std::function<void()>>& tasks) override {
        for (std::size_t m = 0; m < c_.methods.size(); ++m) {
            for (std::size_t d = 0; d < c_.dts.size(); ++d)
                tasks.emplace_back([this, m, d] { run_one(m, d); });
            if constexpr (LinearOscillator<P>) {
                if (c_.wants(StabilitySweepDiagnostic::name))
                    sweep_tasks(m, tasks, one_step_at(method(m)));
                if (c_.wants(TraceTaylorDiagnostic::name))
                    tasks.emplace_back([this, m] {
                        method_metrics_[m][std::string(TraceTaylorDiagnostic::name)] =
                            trace_taylor_metrics(
                                method(m), problem_.omega, problem_.gamma,
                                [&](double h) { return half_trace_at(method(m), h); });
                    });
            }
        }
    }

    // The case's report with the derivative checks of the problem (problem_check.hpp): a
    // mismatch adds the failing check "problem Jacobian matches its force".
    json finish() override {
        json out = CaseRun::finish();
        out["problem_check"] = problem_check();
        const json failure = problem_check_failure(out["problem_check"]);
        if (!failure.is_null()) out["checks"].push_back(failure);
        return out;
    }

    // Figures hook: the series file of the case (docs/reports.md "Series files").
    json series() override {
        if (!figures_) return nullptr;
        json out = case_series_json(c_, runs_, series_);
        if constexpr (LinearOscillator<P>)
            if (c_.wants(StabilitySweepDiagnostic::name) && c_.sweep)
                for (std::size_t m = 0; m < c_.methods.size(); ++m)
                    out["stability_map"][c_.methods[m]] =
                        stability_map_series(problem_, c_, method(m));
        return out;
    }

private:
    void run_one(std::size_t m, std::size_t d) {
        const MethodInfo& info = method(m);
        json& out = run_slot(m, d);
        const double h = c_.dts[d];
        const std::int64_t n = c_.steps[d];
        out = {{"method", info.id}, {"dt", h}, {"steps_planned", n}};
        try {
            KernelMatch match = KernelMatch::applied;
            const KernelOps<P>* ops = kernel_ops<P>(info, match);
            if (!ops) {
                mark_not_applicable(out);
                return;
            }
            integrate_with(*ops, info, h, n, out);
        } catch (const std::exception& e) {
            // a fault in this run is its status; the other runs and cases go on
            mark_error(out, e.what());
        }
    }

    // The step loop of the run's kernel (ops.run, compiled once per (kernel, problem) pair): bare
    // (no observer: no virtual call, no allocation per step) unless a diagnostic of the case or
    // its figures need the trajectory.
    void integrate_with(const KernelOps<P>& ops, const MethodInfo& info, double h, std::int64_t n,
                        json& out) {
        Counters counters;
        Vec z = problem_.initial_state();
        Recorder<P> rec(problem_, c_.t0, h);
        // Figures hook: only with --figures, the per-step series from the same pass
        // (the figure observer beside the recorder) and the E_n series from the
        // conformal-symplectic pass below; every report number is the same with or without.
        std::optional<FigureStepObserver<P>> fig = figure_observer(out, h, n);
        // the error and measures reduced on the fly when nothing else reads the grid
        std::optional<GridStream<P>> stream;
        if (streams_grid() && facts_.reference_ok)
            stream.emplace(problem_, c_, facts_, exact_on_the_fly(),
                           c_.wants(ErrorDiagnostic::name), !c_.measures.empty());
        // the step loop in chunks with the case's time budget and stop requests tested
        // between them (src/harness/run/limits.hpp); a fault only where a test planted one
        const FaultPlan* fault = fault_for(c_.id, info.id);
        guard_.start();
        FigureStepObserver<P>* steps = fig && fig->needed() ? &*fig : nullptr;
        RunObserver<P> obs{observes() ? &rec : nullptr, steps};
        if (observes())
            start_recorder(rec, info, h, n, z, stream ? &*stream : nullptr, fig.has_value());
        if (steps) steps->start(z);
        double wall = 0.0;
        const IntegrateOutcome res =
            ops.run(problem_, info, h, counters, z, c_.t0, n, observes() || steps ? &obs : nullptr,
                    guard_, fault, wall);
        record_run(out, res, counters, z, wall, h);
        if (res.status == RunStatus::timeout || res.status == RunStatus::interrupted) {
            out["metrics"] = json::object(); // stopped; no further pass over the steps
            return;
        }
        const bool ok = res.status == RunStatus::ok;
        std::optional<MinMaxDecimator> cs_series;
        const RunView<P> view{problem_,
                              facts_,
                              rec,
                              stores_grid() ? &rec.grid() : nullptr,
                              stream ? &*stream : nullptr,
                              info,
                              c_.t0,
                              h,
                              n,
                              z,
                              counters,
                              res.steps_done,
                              wall,
                              table_factor(info, h),
                              fig ? &cs_series : nullptr,
                              ops.stepper};
        json metrics = observed_metrics(view, ok);
        pass_metrics(metrics, view);
        out["metrics"] = metrics;
        if (fig && ok) capture_figure_series(*fig, cs_series, n, rec, out);
        // Work-precision timing (ladder cases): the bare step loop only, never a failed run.
        if (ok && time_budget_ > 0.0 && c_.dts.size() >= 2) {
            auto once = [&] {
                Counters scratch;
                Vec zt = problem_.initial_state();
                static const CaseGuard no_budget; // still stopped by SIGINT/SIGTERM
                double seconds = 0.0;
                ops.run(problem_, info, h, scratch, zt, c_.t0, n, nullptr, no_budget, nullptr,
                        seconds);
                return seconds;
            };
            out["timing"] = time_repeated(once, time_budget_, n);
        }
    }

    // Figures hook: the figure observer of the run whose record is `out` (a slot of
    // runs_), or none (no --figures, or a run of a ladder that keeps no series). It observes the
    // steps only if it has per-step series to keep (needed()).
    std::optional<FigureStepObserver<P>> figure_observer(const json& out, double h,
                                                         std::int64_t n) const {
        std::optional<FigureStepObserver<P>> fig;
        if (!figures_ || !figure_series_for_dt(c_, run_index(out) % c_.dts.size())) return fig;
        const Eigen::Index cols = stores_grid() ? facts_.points + 1 : 0; // the run's stored grid
        fig.emplace(problem_, c_, h, n, figure_orbit_from_steps(problem_, c_, cols, n));
        return fig;
    }

    std::size_t run_index(const json& out) const {
        return static_cast<std::size_t>(&out - runs_.data());
    }

    // Figures hook: the series of the run whose record is `out`.
    void capture_figure_series(FigureStepObserver<P>& fig, std::optional<MinMaxDecimator>& cs,
                               std::int64_t n, Recorder<P>& rec, const json& out) {
        const Mat& g = rec.grid();
        std::vector<double> times;
        for (Eigen::Index i = 0; i < g.cols(); ++i) times.push_back(facts_.grid_time(i));
        const bool ref_on_grid =
            facts_.reference_ok && facts_.needs_grid && facts_.ref.cols() == g.cols();
        json steps = fig.needed() ? fig.to_json() : json::object();
        rec.series(steps); // the per-step parts' series (PartContext::series_steps)
        if (cs) {
            steps[std::string(ConformalSymplecticDiagnostic::name) + ".rel"] = cs->to_json();
            // the form measured (the figure's axis label): J⁻¹, or the problem's structure matrix D
            if constexpr (has_structure_matrix<P>())
                steps[std::string(ConformalSymplecticDiagnostic::name) + ".rel"]["form"] =
                    "structure-matrix";
        }
        series_[run_index(out)] =
            capture_run_series(problem_, c_, std::move(steps), g, times, facts_.ref, ref_on_grid,
                               figure_orbit_from_steps(problem_, c_, g.cols(), n));
    }

    // series: the run keeps figure series (its parts keep theirs from the same computation).
    void start_recorder(Recorder<P>& rec, const MethodInfo& info, double h, std::int64_t n,
                        const Vec& z, GridSink* stream, bool series) const {
        if (stores_grid()) rec.record_grid(n / facts_.points, facts_.points + 1);
        if (stream) rec.stream_grid(n / facts_.points, stream); // grid_stream.hpp
        const PartContext ctx{c_.t0, h, table_factor(info, h), series ? n : 0};
        for_each_type(DiagnosticList{}, [&]<class D>() {
            if (c_.wants(D::name)) rec.template enable<D>(ctx);
        });
        rec.start(z);
    }

    double table_factor(const MethodInfo& info, double h) const {
        return table_momentum_factor(info.claims, P::constant_gamma, problem_.dGamma(c_.t0, h));
    }

    // The metrics read from the observer and the final state: every diagnostic of the list that
    // produces run metrics and supports P (typed on P only, not on the kernel).
    json observed_metrics(const RunView<P>& run, bool ok) const {
        json m = json::object();
        for_each_type(DiagnosticList{}, [&]<class D>() {
            if constexpr (D::template supports<P> && requires { D::produce(run); })
                if (produces(D::name, ok)) m[std::string(D::name)] = D::produce(run);
        });
        if (ok && facts_.reference_ok && !c_.measures.empty()) {
            StateFunction energy, energy_scale;
            if constexpr (HasEnergy<P>) {
                energy = [this](const Vec& v) { return problem_.energy(v); };
                energy_scale = [this](const Vec& v) { return problem_.energy_scale(v); };
            }
            m["measure"] = run.stream ? run.stream->measure_metrics(run.z)
                                      : measure_metrics(c_, facts_, run.stored_grid, run.z, energy,
                                                        energy_scale);
        }
        return m;
    }

    // The problem's Jacobians against its functions (problem_check.hpp) at the initial state and
    // at the reference's middle and last states, or, without a reference, at the final state of
    // the first run that finished. The same states whether the reference is stored on the grid
    // (--figures stores it) or evaluated on the fly: the middle one is then evaluated here as the
    // stored grid would hold it, so that report.json does not move with --figures.
    json problem_check() const {
        ProblemCheck pc;
        pc.parts = problem_check_parts<P>();
        std::int64_t states = 0;
        auto at = [&](double t, const Vec& z) {
            if (!z.allFinite() || z.size() != problem_.dim()) return;
            check_problem_at(problem_, t, z, static_cast<std::uint64_t>(states), pc);
            ++states;
        };
        at(c_.t0, problem_.initial_state());
        const Eigen::Index cols = facts_.ref.cols();
        if (cols > 0 && static_cast<std::size_t>(cols) == ref_times_.size()) {
            if (cols >= 3) {
                at(ref_times_[(cols - 1) / 2], facts_.ref.col((cols - 1) / 2));
            } else if constexpr (HasExactSolution<P>) {
                if (exact_on_the_fly() && facts_.points >= 2) {
                    const double t = facts_.grid_time(facts_.points / 2); // = ref_times_ stored
                    Vec z(problem_.dim());
                    problem_.exact(c_.t0, problem_.initial_state(), t, z);
                    at(t, z);
                }
            }
            at(ref_times_.back(), facts_.ref.col(cols - 1));
            return problem_check_json(pc, states);
        }
        for (const json& r : runs_) {
            if (r.value("status", std::string()) != "ok" || !r.contains("final_time") ||
                !r.contains("final_state") || !r["final_state"].is_array())
                continue;
            const json& a = r["final_state"];
            Vec z(static_cast<Eigen::Index>(a.size()));
            for (std::size_t i = 0; i < a.size(); ++i)
                z[static_cast<Eigen::Index>(i)] = a[i].is_number()
                                                      ? a[i].get<double>()
                                                      : std::numeric_limits<double>::quiet_NaN();
            at(r["final_time"].get<double>(), z);
            break;
        }
        return problem_check_json(pc, states);
    }

    // The metrics of the diagnostics' separate passes with fresh steppers of the run's kernel
    // (RunView::stepper; the run above is untouched): every diagnostic with a pass that supports
    // P, whatever the run's status.
    void pass_metrics(json& m, const RunView<P>& run) const {
        for_each_type(DiagnosticList{}, [&]<class D>() {
            if constexpr (D::template supports<P> && requires { D::produce_pass(run); })
                if (produces(D::name, true)) m[std::string(D::name)] = D::produce_pass(run);
        });
    }

    // ½ tr M of the method on this oscillator at step h (trace-taylor), NaN if no kernel applies.
    double half_trace_at(const MethodInfo& info, double h) const {
        KernelMatch match = KernelMatch::applied;
        const KernelOps<P>* ops = kernel_ops<P>(info, match);
        if (!ops) return std::numeric_limits<double>::quiet_NaN();
        return analyse_one_step(one_step_matrix(problem_, info, h, ops->stepper), problem_.gamma, h)
            .half_trace;
    }

    // The one-step analysis of the method on the same oscillator at (ω, γ, h) (stability-sweep).
    OneStepAt one_step_at(const MethodInfo& info) const {
        return [this, &info](double omega, double g, double h) {
            OneStepAnalysis a;
            KernelMatch match = KernelMatch::applied;
            const KernelOps<P>* ops = kernel_ops<P>(info, match);
            if (!ops) return a;
            const P osc = problem_.with(omega, g);
            return analyse_one_step(one_step_matrix(osc, info, h, ops->stepper), g, h);
        };
    }

    P problem_;
    std::vector<json> series_; // figures hook: per run slot, only with --figures
};

// The case job for c if its problem type is in shard K of N (index in ProblemList mod N == K),
// else null. Explicitly instantiated once per shard in the generated case_shard_K.cpp.
template <int K, int N>
std::unique_ptr<CaseJob> make_case_shard(const CaseSpec& c) {
    std::unique_ptr<CaseJob> job;
    // Only the problems of this shard are instantiated here (the index test is compile-time:
    // a runtime test would instantiate every problem's runner in every shard).
    for_each_type_indexed(ProblemList{}, [&]<std::size_t I, class P>() {
        if constexpr (static_cast<int>(I) % N == K) {
            if (!job && P::id == c.problem_id) job = std::make_unique<TypedCase<P>>(c);
        }
    });
    return job;
}

} // namespace dampsym::detail
