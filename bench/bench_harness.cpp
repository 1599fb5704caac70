// Every registered method on oscillator, pendulum, rigid body and N-body (N = 3, 6, 10) through the
// harness's own path: the library's compiled (kernel, problem) pair, kernel_ops<P>(info)->run, as
// TypedCase::integrate_with calls it for a run without observer (a fresh stepper, the bare step
// loop in chunks under a case guard without budget). Methods whose kernel does not apply to a
// problem are not registered. Nothing here instantiates a kernel: the numbers are those of the
// code the runner runs.
//
// Benchmark names: harness/<problem>/<method>; harness/pendulum/rk4-file and
// harness/pendulum/stormer-verlet-file are the same methods loaded from examples/methods/;
// harness/pendulum/plugin-csv1 is csv1 as the example C plugin (examples/plugins).
#include "bench/bench_common.hpp"

#include "core/integrate.hpp"
#include "harness/problem_list.hpp"
#include "harness/report/provenance.hpp"
#include "harness/run/kernel_ops.hpp"
#include "harness/run/limits.hpp"
#include "harness/user_methods/method_files.hpp"
#include "harness/user_methods/plugins.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <memory>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace dampsym::bench {
namespace {

// The bare run of the method's kernel (the library's) from the problem's initial state.
template <class P>
IntegrateOutcome bare_run(const KernelOps<P>& ops, const P& problem, const MethodInfo& info,
                          std::int64_t n, Counters& counters, Vec& z) {
    static const CaseGuard no_budget;
    double wall = 0.0;
    z = problem.initial_state();
    return ops.run(problem, info, kStep, counters, z, 0.0, n, nullptr, no_budget, nullptr, wall);
}

// Runs the method on a copy of `problem` for n steps per iteration.
template <class P>
void register_one(const std::string& label, std::shared_ptr<const P> problem,
                  const MethodInfo& info, std::int64_t n, bool key) {
    KernelMatch match = KernelMatch::unknown_kernel;
    const KernelOps<P>* ops = kernel_ops<P>(info, match);
    if (ops == nullptr) return;
    const std::string name = "harness/" + label + "/" + std::string(info.id);
    auto* b = benchmark::RegisterBenchmark(
        name.c_str(), [problem, &info, n, ops](benchmark::State& state) {
            std::int64_t evals = 0;
            Vec z;
            for (auto _ : state) {
                Counters counters;
                const IntegrateOutcome res = bare_run(*ops, *problem, info, n, counters, z);
                benchmark::DoNotOptimize(z.data());
                benchmark::ClobberMemory();
                if (res.status != RunStatus::ok) {
                    state.SkipWithError((std::string(to_string(res.status)) + " at step " +
                                         std::to_string(res.failed_step))
                                            .c_str());
                    break;
                }
                evals += counters.rhs_evals;
            }
            set_step_counters(state, n, evals);
        });
    configure(b, key);
}

template <class P>
void register_problem(const std::string& label, const P& p, std::int64_t n) {
    auto problem = std::make_shared<const P>(p);
    for (const MethodInfo& info : method_catalog()) {
        // These methods on the pendulum enter acceptance ratios (bench_report.py).
        static const std::set<std::string_view> acceptance{
            "csv1",   "stormer-verlet", "csv1-perk", "cse-if",  "cse-etd", "rk4",   "gauss1",
            "gauss2", "gauss3",         "glifrk1",   "glifrk2", "glifrk3", "etdrk2"};
        const bool key = label == "pendulum" && acceptance.count(info.id) != 0;
        register_one(label, problem, info, n, key);
    }
    // Methods loaded from files (docs/method-files.md): rk4 and stormer-verlet from
    // examples/methods/ against their built-in twins (bench_report.py: within 1.10x).
    if (label == "pendulum")
        for (const char* file : {"rk4.json", "stormer-verlet.json"})
            for (const MethodInfo* info :
                 load_method_file(dampsym::source_dir() + "/examples/methods/" + file))
                register_one(label, problem, *info, n, true);
    // A C plugin's csv1 (examples/plugins, docs/plugins.md) against the built-in csv1.
    if (label == "pendulum")
        for (const MethodInfo* info : load_plugin(DAMPSYM_EXAMPLE_PLUGIN))
            if (info->id == "plugin-csv1") register_one(label, problem, *info, n, true);
}

// Gravity: a central body of mass 1 and N−1 light bodies (mass 1e-3) on circular orbits of radii
// 3, 4, 5, ... at phases spaced by the golden angle, slightly inclined, total momentum zero. Over
// the benchmarked t = 5 (500 steps of 0.01, γ = 0.1) no two bodies come closer than 2.5 (checked
// against a scipy solve at rtol 1e-10), so no close encounter makes any method unstable.
NBody make_nbody(int bodies) {
    std::vector<double> m{1.0}, q{0.0, 0.0, 0.0}, p{0.0, 0.0, 0.0};
    for (int k = 1; k < bodies; ++k) {
        const double r = 2.0 + k, th = 2.399963229728653 * k, inc = 0.05 * std::sin(1.0 * k);
        const double mk = 1e-3, v = std::sqrt(1.0 / r);
        m.push_back(mk);
        q.insert(q.end(), {r * std::cos(th), r * std::sin(th), r * std::sin(inc)});
        p.insert(p.end(), {-mk * v * std::sin(th), mk * v * std::cos(th), 0.0});
        for (int c = 0; c < 3; ++c) p[static_cast<std::size_t>(c)] -= p[p.size() - 3 + c];
    }
    return make_problem<NBody>({{"gamma", kGamma}, {"G", 1.0}, {"potential", 0.0}, {"dim", 3.0}},
                               {{"masses", m}, {"q", q}, {"p", p}});
}

} // namespace

bool kernel_ends_at(std::string_view method, double q, double p) {
    const Pendulum problem =
        make_problem<Pendulum>({{"gamma", kGamma}, {"q0", kPendulumQ0}, {"p0", kPendulumP0}});
    const MethodInfo* info = find_method(method);
    if (info == nullptr) return false;
    KernelMatch match = KernelMatch::unknown_kernel;
    const KernelOps<Pendulum>* ops = kernel_ops<Pendulum>(*info, match);
    if (ops == nullptr) return false;
    Counters counters;
    Vec z;
    bare_run(*ops, problem, *info, kSteps1Dof, counters, z);
    return std::bit_cast<std::uint64_t>(z[0]) == std::bit_cast<std::uint64_t>(q) &&
           std::bit_cast<std::uint64_t>(z[1]) == std::bit_cast<std::uint64_t>(p);
}

void register_harness_benchmarks() {
    register_problem(
        "oscillator",
        make_problem<Oscillator>({{"omega", 1.0}, {"gamma", kGamma}, {"q0", 1.0}, {"p0", 0.0}}),
        kSteps1Dof);
    register_problem(
        "pendulum",
        make_problem<Pendulum>({{"gamma", kGamma}, {"q0", kPendulumQ0}, {"p0", kPendulumP0}}),
        kSteps1Dof);
    // γ(t) = ½ε cos 2t: ε = 2γ gives the amplitude γ = 0.1.
    register_problem("rigid-body", make_problem<RigidBody>({{"epsilon", 2.0 * kGamma}}),
                     kSteps1Dof);
    for (int bodies : {3, 6, 10})
        register_problem("nbody-" + std::to_string(bodies), make_nbody(bodies), kStepsNBody);
}

} // namespace dampsym::bench
