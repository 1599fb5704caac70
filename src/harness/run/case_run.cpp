#include "harness/run/case_run.hpp"

#include "diagnostics/error_diagnostic.hpp"
#include "diagnostics/local_error_diagnostic.hpp"
#include "diagnostics/order_diagnostic.hpp"
#include "diagnostics/stability_sweep_diagnostic.hpp"
#include "harness/case/recorded_file.hpp"
#include "harness/problem_info.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dampsym::detail {

void CaseRun::plan(bool has_exact) {
    runs_.assign(c_.methods.size() * c_.dts.size(), json());
    method_metrics_.assign(c_.methods.size(), json::object());
    facts_.t0 = c_.t0;
    facts_.t_end = c_.t_end;
    facts_.points = output_points(c_);
    // A trajectory grid only for diagnostics that read it; a reference only for those that
    // compare with it (the energy diagnostic without "error" reports changes only).
    facts_.needs_grid = case_needs_grid(c_, facts_.points);
    grid_plan_ = grid_plan(c_, facts_.points, has_exact, figures_); // limits.hpp
    observes_ = facts_.needs_grid;
    for (const std::string& name : c_.diagnostics) {
        const DiagnosticInfo* d = find_diagnostic(name);
        if (!d) continue;
        needs_reference_ = needs_reference_ || d->needs.reference;
        if (d->needs.observer) observes_ = true;
    }
    // an exact reference evaluated on the fly is stored at t_end only
    if (needs_reference_)
        ref_times_ =
            reference_times(c_, facts_.points, facts_.needs_grid && grid_plan_.store_reference);
}

bool CaseRun::produces(std::string_view name, bool run_ok) const {
    if (!c_.wants(name)) return false;
    const DiagnosticInfo* d = find_diagnostic(name);
    return d && (!d->needs.ok_run || run_ok) && (!d->needs.reference_ok || facts_.reference_ok);
}

const MethodInfo& CaseRun::method(std::size_t m) const {
    return *find_method(c_.methods[m]);
}

void CaseRun::set_exact_reference(Mat states) {
    facts_.ref = std::move(states);
    // the times compared, whether stored or evaluated during the runs (exact_on_the_fly)
    reference_ = {{"kind", "exact"},
                  {"error_estimate", 0.0},
                  {"points", facts_.needs_grid ? facts_.points + 1 : std::int64_t{1}}};
}

// Certified GSL reference (conventions §4) on the output grid, shared through the cache.
void CaseRun::set_numerical_reference(const ReferenceSolution& sol) {
    reference_ = {{"kind", "gsl-certified"},
                  {"ok", sol.ok},
                  {"stepper", sol.stepper},
                  {"epsrel", sol.epsrel},
                  {"epsabs", sol.epsabs},
                  {"certifier", sol.certifier},
                  {"certifier_epsrel", sol.cert_epsrel},
                  {"certifier_epsabs", sol.cert_epsabs},
                  {"error_estimate", sol.ok ? json(sol.error_estimate) : json(nullptr)},
                  {"rhs_evals", sol.rhs_evals},
                  {"points", ref_times_.size()}};
    if (!sol.ok) {
        reference_["error"] = sol.error;
        facts_.reference_ok = false;
        return;
    }
    facts_.ref = sol.states;
    facts_.ref_error = sol.error_estimate;
    reference_["final_time"] = ref_times_.back();
    reference_["final_state"] = state_json(facts_.ref.col(facts_.ref.cols() - 1));
}

void CaseRun::record_run(json& out, const IntegrateOutcome& res, const Counters& counters,
                         const Vec& z, double wall, double h) const {
    json observed = {{"bare_loop", !observes_},
                     {"grid_points", facts_.needs_grid ? facts_.points + 1 : 0}};
    bool jacobians = false;
    for (const DiagnosticInfo& d : diagnostic_registry()) {
        if (d.needs.jacobian_pass && c_.wants(d.name)) jacobians = true;
        if (!d.observed_key.empty()) observed[d.observed_key] = c_.wants(d.name);
    }
    observed["step_jacobians"] = jacobians;
    out["observed"] = observed;
    out["status"] = to_string(res.status);
    out["steps"] = res.steps_done;
    out["final_time"] = time_at(c_.t0, h, res.steps_done);
    out["final_state"] = state_json(z);
    if (res.status != RunStatus::ok) out["failed_at_step"] = res.failed_step;
    if (res.status == RunStatus::solve_failed && counters.failed_solve_iterations > 0)
        out["solve_failure"] = solve_failure_json(counters); // limits.hpp
    out["rhs_evals"] = counters.rhs_evals;
    out["jac_evals"] = counters.jac_evals;
    out["newton_iters"] = counters.newton_iters;
    out["max_newton_iters_per_step"] = counters.max_newton_iters_per_step;
    out["wall_seconds"] = wall;
}

void CaseRun::mark_not_applicable(json& out) const {
    out["status"] = "not-applicable";
    out["steps"] = 0;
    out["metrics"] = json::object();
}

void CaseRun::mark_error(json& out, const std::string& what) const {
    json rec = {
        {"method", out["method"]}, {"dt", out["dt"]}, {"steps_planned", out["steps_planned"]}};
    rec["status"] = "error";
    rec["error"] = what;
    rec["steps"] = 0;
    rec["metrics"] = json::object();
    out = std::move(rec);
}

void CaseRun::sweep_tasks(std::size_t m, std::vector<std::function<void()>>& tasks,
                          OneStepAt one_step) {
    if (sweep_rows_.size() != c_.methods.size()) { // first method: the shared grid
        sweep_gammas_ = c_.sweep->gamma.values();
        sweep_hs_ = c_.sweep->h.values();
        sweep_rows_.assign(c_.methods.size(), {});
    }
    const std::size_t n = sweep_gammas_.size();
    sweep_rows_[m].assign(n, SweepRow{});
    auto shared = std::make_shared<OneStepAt>(std::move(one_step));
    for (std::size_t r0 = 0; r0 < n; r0 += sweep_rows_per_task) {
        const std::size_t r1 = std::min(n, r0 + sweep_rows_per_task);
        tasks.emplace_back([this, m, r0, r1, shared] {
            for (std::size_t r = r0; r < r1; ++r)
                sweep_rows_[m][r] =
                    sweep_row(method(m), c_.sweep->omega, sweep_gammas_[r], sweep_hs_, *shared);
        });
    }
}

// The size of the solution the global errors are measured against (order_fit.hpp): ‖z_ref(t_end)‖
// when the reference resolves it (above 100× its error estimate), else no bound. The one-step
// errors of local-order are not bounded this way (their steps are at most a step of the ladder).
double CaseRun::solution_scale(bool global) const {
    const double none = std::numeric_limits<double>::infinity();
    if (!global || !facts_.reference_ok || facts_.ref.cols() == 0) return none;
    const double n = facts_.ref.col(facts_.ref.cols() - 1).norm();
    return std::isfinite(n) && n > 100.0 * facts_.ref_error ? n : none;
}

// Order fits (method level): "order" from the global error of each run of the ladder,
// "local-order" from the one-step error (B Fig 3.2; the exact solution, no reference error).
void CaseRun::order_fits() {
    for (const std::string_view diag_name : {OrderDiagnostic::name, LocalOrderDiagnostic::name}) {
        const std::string diag(diag_name);
        if (!c_.wants(diag)) continue;
        const bool global = diag_name == OrderDiagnostic::name;
        // the error each fit reads: at t_end (global), or after one step (local)
        const std::string error_metric = global ? std::string(ErrorDiagnostic::name) + ".final_abs"
                                                : std::string(LocalErrorDiagnostic::name) + ".abs";
        // Round-off floor, and conventions §4: no fit uses an error within 100× the reference's
        // estimate.
        const double roundoff = 1000.0 * std::numeric_limits<double>::epsilon() *
                                (facts_.reference_ok && global
                                     ? std::max(1.0, facts_.ref.col(facts_.ref.cols() - 1).norm())
                                     : 1.0);
        const double ref_error = global ? facts_.ref_error : 0.0;
        const double scale = solution_scale(global);
        for (std::size_t m = 0; m < c_.methods.size(); ++m) {
            std::vector<OrderPoint> pts;
            for (std::size_t d = 0; d < c_.dts.size(); ++d) {
                const json& r = run_slot(m, d);
                const json* e = lookup(r["metrics"], error_metric);
                pts.push_back({c_.dts[d], e && e->is_number()
                                              ? e->get<double>()
                                              : std::numeric_limits<double>::quiet_NaN()});
            }
            method_metrics_[m][diag] = order_fit_json(pts, roundoff, ref_error, scale);
        }
    }
}

json CaseRun::finish() {
    // Stability sweeps (method level) from their row tasks, in grid order.
    const std::string sweep(StabilitySweepDiagnostic::name);
    if (c_.wants(sweep) && sweep_rows_.size() == c_.methods.size())
        for (std::size_t m = 0; m < c_.methods.size(); ++m)
            method_metrics_[m][sweep] =
                sweep_json(method(m), c_.sweep->omega, sweep_gammas_, sweep_hs_, sweep_rows_[m]);
    order_fits();
    return case_json(evaluate_checks(c_, runs_, method_metrics_, reference_, facts_.reference_ok));
}

json CaseRun::case_json(json checks) const {
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
                {"file", recorded_case_file(c_.file)},
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
    if (!c_.checks_not_run.empty()) out["checks_not_run"] = not_run_checks(c_);
    if (!c_.no_checks_because.empty()) out["no_checks_because"] = c_.no_checks_because;
    if (!c_.measures.empty()) out["measures"] = c_.raw["measures"];
    if (c_.raw.contains("figures")) out["figures"] = c_.raw["figures"]; // read by plot.py
    return out;
}

json time_repeated(const std::function<double()>& once, double budget, std::int64_t n) {
    const double warmup = once();
    const double est = std::max(warmup, 1e-9);
    const auto reps = static_cast<std::int64_t>(std::clamp(std::ceil(budget / est), 1.0, 100000.0));
    double best = std::numeric_limits<double>::infinity(), total = 0.0;
    std::int64_t r = 0;
    for (; (r < reps || total < budget) && r < 100000; ++r) {
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

} // namespace dampsym::detail
