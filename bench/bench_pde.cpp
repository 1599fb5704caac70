// Cost per step of the PDE schemes of B ch. 5 (docs/pde.md, docs/benchmarks.md)
// for M = 256, 512, ..., 8192 grid points:
//
//   pde/kg-csv1/M    B (5.3) = csv1 on the semi-discrete Klein–Gordon problem, through the
//                    harness's kernel (Csv1<KleinGordon>): explicit, O(M) per step
//   pde/kg-box/M     B (5.5), pde::KGBox: one O(M) cyclic tridiagonal solve per step
//   pde/nls-if/M     B (4.15), pde::NLSStepper (IF, damped cubic NLS): FFTs, O(M log M) per step
//
// Every benchmark runs kPdeSteps steps per iteration at h = kPdeStep (below the explicit
// scheme's stability limit h < Δx at M = 8192), from B (5.1)'s plane wave (KG) or a plane wave
// (NLS). The counter `error` of pde/kg-csv1 is the max-norm error of the final state against the
// exact semi-discrete solution (pde::kg_semidiscrete_exact): bench/pde_scipy.py runs scipy's
// RK45 on the same semi-discrete system at the rtol that matches it, side by side.
#include "bench/bench_common.hpp"

#include "core/integrate.hpp"
#include "harness/registry.hpp"
#include "pde/klein_gordon/schemes.hpp"
#include "pde/nls/schemes.hpp"

#include <cmath>
#include <memory>
#include <numbers>
#include <string>

namespace dampsym::bench {
namespace {

constexpr double kPdeStep = 2.0e-4;     // < Δx = 2π/8192 = 7.7e-4 (csv1 stable for every M)
constexpr std::int64_t kPdeSteps = 200; // per iteration: t = 0.04
constexpr double kKgGamma = 0.375, kKgC = 1.0;
constexpr int kKgK = 1;

void kg_csv1(benchmark::State& state, int M) {
    const auto p =
        make_problem<KleinGordon>({{"M", M}, {"gamma", kKgGamma}, {"c", kKgC}, {"K", kKgK}});
    const MethodInfo* info = find_method("csv1");
    Vec z;
    for (auto _ : state) {
        Counters counters;
        Csv1<KleinGordon> stepper(p, *info, kPdeStep, counters);
        z = p.initial_state();
        integrate(stepper, z, 0.0, kPdeStep, kPdeSteps);
        benchmark::DoNotOptimize(z.data());
        benchmark::ClobberMemory();
    }
    Vec ex;
    p.exact(0.0, p.initial_state(), time_at(0.0, kPdeStep, kPdeSteps), ex);
    set_step_counters(state, kPdeSteps,
                      2 * kPdeSteps * static_cast<std::int64_t>(state.iterations()));
    state.counters["M"] = M;
    state.counters["h"] = kPdeStep;
    state.counters["t_end"] = time_at(0.0, kPdeStep, kPdeSteps);
    state.counters["error"] = (z - ex).cwiseAbs().maxCoeff();
}

void kg_box(benchmark::State& state, int M) {
    const pde::PeriodicGrid g(M, std::numbers::pi);
    Vec u0, v0;
    pde::kg_plane_wave(g, kKgGamma, kKgK, pde::kg_frequency(kKgK * kKgK, kKgC, kKgGamma), 0.0, u0,
                       v0);
    for (auto _ : state) {
        pde::KGBox box(g, kKgC, kKgGamma, kPdeStep);
        box.start(u0, v0);
        for (std::int64_t i = 1; i < kPdeSteps; ++i) box.step();
        benchmark::DoNotOptimize(box.u_curr().data());
        benchmark::ClobberMemory();
    }
    set_step_counters(state, kPdeSteps, 0);
    state.counters["M"] = M;
}

void nls_if(benchmark::State& state, int M) {
    const pde::PeriodicGrid g(M, std::numbers::pi);
    pde::NLSParams np;
    np.gamma = 0.05;
    const pde::CVec psi0 = pde::nls_plane_wave(g, np, 1.0, 3, 0.0, true);
    for (auto _ : state) {
        pde::NLSStepper st(g, np, kPdeStep, pde::NLSScheme::integrating_factor);
        pde::CVec psi = psi0;
        for (std::int64_t i = 0; i < kPdeSteps; ++i)
            if (!st.step(time_at(0.0, kPdeStep, i), psi)) {
                state.SkipWithError(st.why().c_str());
                return;
            }
        benchmark::DoNotOptimize(psi.data());
        benchmark::ClobberMemory();
    }
    set_step_counters(state, kPdeSteps, 0);
    state.counters["M"] = M;
}

} // namespace

void register_pde_benchmarks() {
    for (int M = 256; M <= 8192; M *= 2) {
        const std::string m = std::to_string(M);
        configure(benchmark::RegisterBenchmark(("pde/kg-csv1/" + m).c_str(),
                                               [M](benchmark::State& s) { kg_csv1(s, M); }),
                  true);
        configure(benchmark::RegisterBenchmark(("pde/kg-box/" + m).c_str(),
                                               [M](benchmark::State& s) { kg_box(s, M); }),
                  true);
        configure(benchmark::RegisterBenchmark(("pde/nls-if/" + m).c_str(),
                                               [M](benchmark::State& s) { nls_if(s, M); }),
                  true);
    }
}

} // namespace dampsym::bench
