// Shared pieces of the work-precision benchmarks wp/<problem>/<solver>/<k>
// (bench_workprecision.cpp: dampsym's kernels, the problems and references;
// bench_workprecision_peers.cpp: Boost.Odeint and GSL).
#pragma once

#include "bench/bench_common.hpp"
#include "problems/kepler.hpp"
#include "problems/pendulum.hpp"
#include "problems/rigid_body.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <string>

namespace dampsym::bench {

// The span of a problem's runs and its ladders: fixed steps h0/2^k (k < fixed_rungs), tolerances
// rtol = 10^-k (tol_first <= k <= tol_last) with atol = atol_over_rtol · rtol.
struct WpSpan {
    double t0 = 0.0, t_end = 0.0, h0 = 0.0;
    int fixed_rungs = 6, tol_first = 3, tol_last = 12;
    double atol_over_rtol = 1e-3;
};

// Steps of the fixed-step rung k: (t_end − t0)/h0 rounded, times 2^k (h = (t_end − t0)/steps).
inline std::int64_t rung_steps(const WpSpan& s, int k) {
    return std::llround((s.t_end - s.t0) / s.h0) << k;
}

// Repetitions: the minimum over them is the time drawn (bench_common.hpp, configure()).
inline void configure_wp(benchmark::internal::Benchmark* b) {
    b->ComputeStatistics("min", min_of)->Unit(benchmark::kMillisecond);
    if (options().quick)
        b->Repetitions(1)->MinTime(0.001);
    else
        b->Repetitions(3)->MinTime(0.02);
}

// The counters of every wp benchmark, from its last iteration: the final state z0 ... z{dim−1},
// steps, force evaluations and Jacobian evaluations of one integration.
inline void set_wp_counters(benchmark::State& state, const double* z, int dim, std::int64_t steps,
                            std::int64_t evals, std::int64_t jacs) {
    for (int i = 0; i < dim; ++i) state.counters["z" + std::to_string(i)] = z[i];
    state.counters["steps"] = static_cast<double>(steps);
    state.counters["force_evals"] = static_cast<double>(evals);
    state.counters["jac_evals"] = static_cast<double>(jacs);
}

// Registers the Boost.Odeint and GSL benchmarks of one problem (bench_workprecision_peers.cpp)
// after checking their plain-array vector field against the problem's own rhs (throws if they
// differ); returns that vector field at two states ([{t, z, f}], for bench/work_precision.py's
// check of scipy's).
nlohmann::json register_wp_peers(const std::string& label, const Pendulum& p, const WpSpan& s);
nlohmann::json register_wp_peers(const std::string& label, const Kepler& p, const WpSpan& s);
nlohmann::json register_wp_peers(const std::string& label, const RigidBody& p, const WpSpan& s);

} // namespace dampsym::bench
