// Certified GSL reference for a pendulum case, exactly as the harness computes it: the case is the
// default suite's verify/cases/pend-table41-g0.05.json (main solve rk8pd at epsrel 1e-14, epsabs
// 1e-15, the reference of the pendulum Table 4.1 cases; t_end = 100, output_dt = 1) loaded through
// load_case with --set problem.gamma=0.1 so that it is the pendulum of every other benchmark. The
// output times, the ReferenceRequest and its rhs are built by the helpers TypedCase<P>::prepare()
// and numerical_reference() use (src/harness/run/case_job.hpp), and certified_reference() is called
// directly (run_cases would answer repeated calls from its reference cache).
//
//   reference/pendulum/certified   certified_reference(): main solve + rk8pd certifying solve at
//                                  min(1e-14, epsrel/10)
//   reference/pendulum/main-only   solve_reference(): the main solve alone (for context)
//
// Counters record the problem, tolerances and final time, which bench_report.py hands to scipy.
#include "bench/bench_common.hpp"

#include "harness/case/case.hpp"
#include "harness/run/case_job.hpp"
#include "problems/pendulum.hpp"
#include "reference/gsl_reference.hpp"

#include <string>
#include <vector>

namespace dampsym::bench {
namespace {

const char* const kCaseFile = DAMPSYM_BENCH_DIR "/../verify/cases/pend-table41-g0.05.json";

// The request TypedCase<Pendulum>::prepare()/numerical_reference() builds for case c (the same
// helpers, src/harness/run/case_job.hpp).
ReferenceRequest harness_request(const CaseSpec& c) {
    const std::int64_t points = detail::output_points(c);
    return detail::reference_request(
        Pendulum::from_params(c.params), c,
        detail::reference_times(c, points, detail::case_needs_grid(c, points)));
}

void reference(benchmark::State& state, bool certified) {
    CaseSpec c;
    try {
        c = load_case(kCaseFile, {"problem.gamma=" + std::to_string(kGamma)});
    } catch (const std::exception& e) {
        state.SkipWithError(e.what());
        return;
    }
    const ReferenceRequest req = harness_request(c);
    ReferenceSolution sol;
    for (auto _ : state) {
        sol = certified ? certified_reference(req) : solve_reference(req);
        benchmark::DoNotOptimize(sol.states.data());
        if (!sol.ok) {
            state.SkipWithError(sol.error.c_str());
            return;
        }
    }
    state.counters["gamma"] = c.params.at("gamma");
    state.counters["q0"] = c.params.at("q0");
    state.counters["p0"] = c.params.at("p0");
    state.counters["t0"] = c.t0;
    state.counters["t_end"] = c.t_end;
    state.counters["points"] = static_cast<double>(req.times.size());
    state.counters["epsrel"] = sol.epsrel;
    state.counters["epsabs"] = sol.epsabs;
    state.counters["rhs_evals"] = static_cast<double>(sol.rhs_evals);
    if (certified) {
        state.counters["cert_epsrel"] = sol.cert_epsrel;
        state.counters["cert_epsabs"] = sol.cert_epsabs;
        state.counters["error_estimate"] = sol.error_estimate;
    }
    state.SetLabel(c.id + " --set problem.gamma=" + std::to_string(kGamma) + ", " + sol.stepper +
                   (certified ? " certified by " + sol.certifier : std::string()));
}

} // namespace

void register_reference_benchmark() {
    configure(benchmark::RegisterBenchmark("reference/pendulum/certified",
                                           [](benchmark::State& s) { reference(s, true); }),
              true);
    configure(benchmark::RegisterBenchmark("reference/pendulum/main-only",
                                           [](benchmark::State& s) { reference(s, false); }),
              false);
}

} // namespace dampsym::bench
