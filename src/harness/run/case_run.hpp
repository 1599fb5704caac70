// The compiled-once part of a case in progress (case_run.cpp, checks.cpp): the run records, the
// reference, the per-method metrics, the order fits, the stability-sweep bookkeeping, the check
// evaluation and the case's report JSON. TypedCase<P> (typed_case.hpp) derives from it and adds
// only what must know the problem type: the step loop with its observer, the exact/reference
// evaluation and the typed diagnostic hooks.
#pragma once

#include "core/integrate.hpp"
#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"
#include "diagnostics/stability_sweep_diagnostic.hpp"
#include "harness/run/case_job.hpp"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace dampsym::detail {

class CaseRun : public CaseJob {
public:
    explicit CaseRun(const CaseSpec& spec) : c_(spec) {}
    json finish() override;

protected:
    // The output grid and what the case's diagnostics need of it (from the registry); has_exact:
    // the problem's reference is its exact solution (what is stored, grid_plan).
    void plan(bool has_exact);
    // limits.hpp grid_plan: the runs store the output grid / feed it on the fly to the
    // error and measure reductions (harness/run/grid_stream.hpp); the exact reference is evaluated
    // at each grid time during the runs instead of stored.
    bool stores_grid() const { return grid_plan_.store_grid; }
    bool streams_grid() const { return grid_plan_.grid && !grid_plan_.store_grid; }
    bool exact_on_the_fly() const { return grid_plan_.grid && !grid_plan_.store_reference; }
    bool needs_reference() const { return needs_reference_; }
    // Whether the step loop carries an observer (a grid or a diagnostic's per-step hook).
    bool observes() const { return observes_; }
    // The Recorder parts the case's diagnostics enable (diagnostics/recorder.hpp).
    // Whether run-level diagnostic `name` produces metrics for a run with this status.
    bool produces(std::string_view name, bool run_ok) const;

    const MethodInfo& method(std::size_t m) const;
    json& run_slot(std::size_t m, std::size_t d) { return runs_[m * c_.dts.size() + d]; }

    void set_exact_reference(Mat states);
    void set_numerical_reference(const ReferenceSolution& sol);

    // The run record of one integration (status, counts, final state, what was observed).
    void record_run(json& out, const IntegrateOutcome& res, const Counters& counters, const Vec& z,
                    double wall, double h) const;
    void mark_not_applicable(json& out) const;
    // the record of a run whose kernel threw (its status; the other runs go on).
    void mark_error(json& out, const std::string& what) const;

    // Stability sweep (method level): the row tasks of method m; one_step is its typed analysis.
    void sweep_tasks(std::size_t m, std::vector<std::function<void()>>& tasks, OneStepAt one_step);

    const CaseSpec& c_;
    CaseFacts facts_;
    std::vector<double> ref_times_;
    json reference_;
    std::vector<json> runs_;
    std::vector<json> method_metrics_;

private:
    void order_fits();
    double solution_scale(bool global) const;
    json case_json(json checks) const;

    bool needs_reference_ = false, observes_ = false;
    GridPlan grid_plan_;
    std::vector<double> sweep_gammas_, sweep_hs_;
    std::vector<std::vector<SweepRow>> sweep_rows_; // [method][γ row], pre-sized in sweep_tasks
};

// Repeats `once` (one bare step loop, returning its wall seconds): one warm-up, then the minimum of
// N repetitions, N chosen from the warm-up so that the repetitions total >= budget (at most 1e5).
json time_repeated(const std::function<double()>& once, double budget, std::int64_t steps);

// The checks of the case from its runs and method metrics (checks.cpp).
json evaluate_checks(const CaseSpec& c, const std::vector<json>& runs,
                     const std::vector<json>& method_metrics, const json& reference,
                     bool reference_ok);
// The checks the selection left without one of their methods (CaseSpec::checks_not_run), each with
// its reason: report.json's "checks_not_run" (checks.cpp).
json not_run_checks(const CaseSpec& c);

// The case's "measures" (docs/case-keys.md) of one run (measures.cpp); energy and energy_scale:
// the problem's energy and its scale S_H, empty when it has none.
json measure_metrics(const CaseSpec& c, const CaseFacts& f, const Mat* grid, const Vec& z_final,
                     const std::function<double(const Vec&)>& energy,
                     const std::function<double(const Vec&)>& energy_scale);

// The case's measures as running reductions over the output grid t_1..t_end (measures.cpp): fed
// one grid point at a time, on the fly during the run (harness/run/grid_stream.hpp: no
// trajectory stored) or from a stored grid (measure_metrics), with bitwise the same results.
class MeasureAccumulator {
public:
    MeasureAccumulator(const CaseSpec& c, const CaseFacts& f,
                       std::function<double(const Vec&)> energy,
                       std::function<double(const Vec&)> energy_scale);
    // Grid point i >= 1 at time t: the run's state and the reference's.
    void add(const Vec& z, const Vec& ref, double t);
    // The metrics; the final state and the reference at t_end serve "final" (and every measure
    // when no grid point was added).
    json finish(const Vec& z_final, const Vec& ref_final) const;

private:
    struct Stat {
        bool undefined = false;
        double max = 0.0, sum = 0.0;
        std::int64_t count = 0;
        std::vector<double> t, v; // growth only
    };
    double pointwise(const MeasureSpec& m, const Vec& u, const Vec& ref) const;
    const CaseSpec& c_;
    const CaseFacts& f_;
    std::function<double(const Vec&)> energy_, energy_scale_;
    std::vector<Stat> stats_;
    bool fed_ = false;
};

} // namespace dampsym::detail
