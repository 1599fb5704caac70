// The overhead of the harness around a long run. The case bench/cases/overhead-final-error.json is
// an oscillator with its exact solution, one method (csv1), one dt, 10^6 steps, diagnostics
// ["error"] and output_dt = t_end, so that the error is asked for at the final time only (no
// trajectory grid, no observer). Benchmarks:
//   overhead/oscillator/run_cases-final-error   run_cases({case}, jobs 1): the public API, with
//                                               case preparation, the run, checks and report JSON
//   overhead/oscillator/bare-integrate          the same kernel and steps through integrate() alone
//   overhead/oscillator/run_cases-error-grid    the same case without output_dt: "error" alone then
//                                               records the default output grid (up to 20000
//                                               points) with the per-step observer (for context)
//   overhead/pendulum/run_cases-csv1            harness/pendulum/csv1's run (same pendulum, h,
//   steps)
//                                               as a case with "diagnostics": [] through run_cases:
//                                               the step loop as compiled in the case shard.
//                                               Besides ns_per_step (the whole call) it reports
//                                               loop_ns_per_step, the minimum over iterations of
//                                               the runner's own wall_seconds around integrate()
//                                               (for context: the shard's codegen vs this file's)
#include "bench/bench_common.hpp"

#include "core/integrate.hpp"
#include "harness/case/case.hpp"
#include "harness/registry.hpp"
#include "harness/run/runner.hpp"

#include <algorithm>
#include <memory>
#include <string>

namespace dampsym::bench {
namespace {

const char* const kCaseFile = DAMPSYM_BENCH_DIR "/cases/overhead-final-error.json";

std::shared_ptr<const CaseSpec> load_overhead_case(bool with_grid) {
    auto c = std::make_shared<CaseSpec>(load_case(kCaseFile, {}));
    if (with_grid) c->output_dt.reset();
    return c;
}

void run_cases_bench(benchmark::State& state, bool with_grid) {
    std::shared_ptr<const CaseSpec> c;
    try {
        c = load_overhead_case(with_grid);
    } catch (const std::exception& e) {
        state.SkipWithError(e.what());
        return;
    }
    const std::int64_t n = c->steps.at(0);
    RunOptions opts;
    opts.jobs = 1;
    nlohmann::json report;
    std::int64_t evals = 0;
    for (auto _ : state) {
        report = run_cases({*c}, opts);
        benchmark::DoNotOptimize(report);
        const auto& run = report["cases"][0]["runs"][0];
        if (run.value("status", std::string()) != "ok" ||
            report["summary"]["checks_failed"].get<int>() != 0) {
            state.SkipWithError("the overhead case did not run cleanly");
            return;
        }
        evals += run["rhs_evals"].get<std::int64_t>();
    }
    set_step_counters(state, n, evals);
    const auto& ref = report["cases"][0]["reference"];
    state.counters["reference_points"] = ref.value("points", 0.0);
    state.counters["final_abs_error"] =
        report["cases"][0]["runs"][0]["metrics"]["error"]["final_abs"].get<double>();
    state.SetLabel(ref.value("kind", std::string()) + " reference at " +
                   std::to_string(ref.value("points", 0)) + " point(s)");
}

void bare_integrate_bench(benchmark::State& state) {
    std::shared_ptr<const CaseSpec> c;
    try {
        c = load_overhead_case(false);
    } catch (const std::exception& e) {
        state.SkipWithError(e.what());
        return;
    }
    const Oscillator problem = Oscillator::from_params(c->params);
    const MethodInfo& info = *find_method(c->methods.at(0));
    const double h = c->dts.at(0);
    const std::int64_t n = c->steps.at(0);
    std::int64_t evals = 0;
    with_kernel<Oscillator>(info, [&]<class K>() {
        for (auto _ : state) {
            Counters counters;
            K stepper(problem, info, h, counters);
            Vec z = problem.initial_state();
            const IntegrateOutcome res = integrate(stepper, z, c->t0, h, n);
            benchmark::DoNotOptimize(z.data());
            benchmark::ClobberMemory();
            if (res.status != RunStatus::ok) {
                state.SkipWithError("bare integrate failed");
                return;
            }
            evals += counters.rhs_evals;
        }
    });
    set_step_counters(state, n, evals);
}

void run_cases_pendulum_csv1(benchmark::State& state) {
    const nlohmann::json j = {
        {"id", "bench-pendulum-csv1"},
        {"problem",
         {{"id", "pendulum"}, {"gamma", kGamma}, {"q0", kPendulumQ0}, {"p0", kPendulumP0}}},
        {"methods", {"csv1"}},
        {"t_end", kStep * static_cast<double>(kSteps1Dof)},
        {"dt", kStep},
        {"diagnostics", nlohmann::json::array()},
        {"no_checks_because", "a benchmark of the runner's overhead over the bare step loop"}};
    CaseSpec c;
    try {
        c = parse_case(j, "bench_overhead.cpp", {});
    } catch (const std::exception& e) {
        state.SkipWithError(e.what());
        return;
    }
    const std::int64_t n = c.steps.at(0);
    RunOptions opts;
    opts.jobs = 1;
    std::int64_t evals = 0;
    double loop_min = 1e300;
    for (auto _ : state) {
        const nlohmann::json report = run_cases({c}, opts);
        const auto& run = report["cases"][0]["runs"][0];
        if (run.value("status", std::string()) != "ok" || run["steps"].get<std::int64_t>() != n) {
            state.SkipWithError("the pendulum case did not run cleanly");
            return;
        }
        evals += run["rhs_evals"].get<std::int64_t>();
        loop_min = std::min(
            loop_min,
            report["timings"]["cases"][0]["runs"][0]["wall_seconds"].get<double>()); // the run's
    }
    set_step_counters(state, n, evals);
    state.counters["loop_ns_per_step"] = 1e9 * loop_min / static_cast<double>(n);
}

} // namespace

void register_overhead_benchmarks() {
    configure(benchmark::RegisterBenchmark("overhead/oscillator/run_cases-final-error",
                                           [](benchmark::State& s) { run_cases_bench(s, false); }),
              true);
    configure(
        benchmark::RegisterBenchmark("overhead/oscillator/bare-integrate", bare_integrate_bench),
        true);
    configure(benchmark::RegisterBenchmark("overhead/oscillator/run_cases-error-grid",
                                           [](benchmark::State& s) { run_cases_bench(s, true); }),
              false);
    configure(
        benchmark::RegisterBenchmark("overhead/pendulum/run_cases-csv1", run_cases_pendulum_csv1),
        true);
}

} // namespace dampsym::bench
