// Shared pieces of dampsym_bench: the benchmark problems (one pendulum for every pendulum
// benchmark), the per-iteration counters and the registration options.
//
// Counters. Every stepping benchmark reports, per repetition,
//   ns_per_step       = CPU time / (steps per iteration × iterations)      [ns]
//   ns_per_force_eval = CPU time / (force evaluations over all iterations)  [ns]
// as benchmark::Counter(1e-9·count, kIsRate | kInvert): Google Benchmark divides the value by the
// CPU time of the repetition (kIsRate) and inverts it (kInvert), which gives seconds per 1e-9
// counts, i.e. nanoseconds per count (the console prints these counters with an "s" suffix; the
// numbers are ns). `steps` and `force_evals` are the per-iteration counts
// (kAvgIterations) so that bench_report.py can recompute both numbers from cpu_time and check them.
#pragma once

#include "core/problem.hpp"
#include "core/types.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace dampsym::bench {

// One pendulum for every pendulum benchmark (harness, bare loop, Boost.Odeint, GSL).
inline constexpr double kGamma = 0.1;
inline constexpr double kPendulumQ0 = 1.0;
inline constexpr double kPendulumP0 = 0.0;
inline constexpr double kStep = 0.01;             // h for every stepping benchmark
inline constexpr std::int64_t kSteps1Dof = 10000; // oscillator, pendulum, rigid body: t = 100
inline constexpr std::int64_t kStepsNBody = 500;  // nbody: t = 5

// Options of this run (set from the command line in bench_main.cpp).
struct Options {
    bool quick = false; // one repetition, short minimum time: a smoke test, not a measurement
};
Options& options();

// Minimum over repetitions, reported next to Google Benchmark's mean/median/stddev aggregates; the
// report uses the minimum (the least disturbed repetition on a shared machine).
inline double min_of(const std::vector<double>& v) {
    return v.empty() ? 0.0 : *std::min_element(v.begin(), v.end());
}

// Repetitions and minimum time: `key` benchmarks enter an acceptance ratio.
inline benchmark::internal::Benchmark* configure(benchmark::internal::Benchmark* b, bool key) {
    b->ComputeStatistics("min", min_of)->Unit(benchmark::kMillisecond);
    if (options().quick) return b->Repetitions(1)->MinTime(0.01);
    return key ? b->Repetitions(7)->MinTime(0.2) : b->Repetitions(3)->MinTime(0.05);
}

// The stepping counters described above, after the timing loop.
inline void set_step_counters(benchmark::State& state, std::int64_t steps_per_iteration,
                              std::int64_t total_force_evals) {
    const double iters = static_cast<double>(state.iterations());
    const double steps = static_cast<double>(steps_per_iteration) * iters;
    const double evals = static_cast<double>(total_force_evals);
    using C = benchmark::Counter;
    state.counters["ns_per_step"] = C(1e-9 * steps, C::kIsRate | C::kInvert);
    if (evals > 0) state.counters["ns_per_force_eval"] = C(1e-9 * evals, C::kIsRate | C::kInvert);
    state.counters["steps"] = C(steps, C::kAvgIterations);
    state.counters["force_evals"] = C(evals, C::kAvgIterations);
}

// A problem's validated parameters: its defaults, with `scalars` and `arrays` overriding them.
template <class P>
P make_problem(const std::vector<std::pair<std::string, double>>& scalars,
               const std::vector<std::pair<std::string, std::vector<double>>>& arrays = {}) {
    ParamMap m;
    for (const ParamSpec& s : P::param_specs()) {
        if (s.is_array)
            m.arrays[s.name] = s.default_array;
        else
            m.scalars[s.name] = s.default_value;
    }
    for (const auto& [k, v] : scalars) m.scalars[k] = v;
    for (const auto& [k, v] : arrays) m.arrays[k] = v;
    return P::from_params(m);
}

// Registration of each group (one translation unit each).
void register_harness_benchmarks(); // bench_harness.cpp: catalog × problems
void register_peer_benchmarks();    // bench_peers.cpp: bare csv1 loop, Boost.Odeint, GSL
// bench_harness.cpp: whether catalog method `method` on the benchmarks' pendulum, stepped
// kSteps1Dof steps of kStep by the harness's kernel, ends at (q, p) bit for bit (a bare loop that
// claims to compute a kernel's arithmetic is checked against it).
bool kernel_ends_at(std::string_view method, double q, double p);
void register_reference_benchmark(); // bench_reference.cpp: certified GSL reference
void register_overhead_benchmarks(); // bench_overhead.cpp: run_cases vs bare integrate()
void register_pde_benchmarks();      // bench_pde.cpp: B ch. 5 schemes, M = 256 ... 8192
// bench_workprecision.cpp: wp/<problem>/<solver>/<k>, dampsym's methods beside Boost.Odeint and GSL
void register_workprecision_benchmarks();

} // namespace dampsym::bench
