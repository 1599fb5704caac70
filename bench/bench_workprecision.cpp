// Work-precision (docs/benchmarks.md "Work-precision"): dampsym's conformal methods beside
// Boost.Odeint and GSL (scipy's solvers are run by bench/work_precision.py, in the same run) on
// three problems of the default suite, exactly as its case files give them:
//   pendulum    verify/cases/pend-table41-g0.05.json       γ = 0.05, q0 = 1, p0 = 0, t_end = 100;
//               reference: the case's certified GSL rk8pd solve (epsrel 1e-14, epsabs 1e-15,
//               certified by rk8pd at 1e-15), through the harness's own request
//   kepler      verify/cases/kepler-fig21-precession.json  e = 0.6 (HLW(2.9)), t_end = 200
//               (dampsym's Kepler problem is undamped, γ ≡ 0); reference: exact (Kepler's
//               equation, reference/kepler_exact.hpp)
//   rigid-body  verify/cases/rb-orders.json                ε = 0.5, I = (4, 3, 2), z0 = (4, 3, 0),
//               t_end = 10; reference: exact (Jacobi elliptic functions)
// Benchmark wp/<problem>/<solver>/<k>: one integration from t0 to t_end per iteration, the bare
// loop (no observer, no output). Counters: h (fixed step) or rtol and atol (adaptive), steps,
// force_evals (calls of the force, or of the whole vector field where the solver asks for it),
// jac_evals, and the final state z0 ... z{d-1}. bench/work_precision.py computes every error from
// the final state and the reference, which this file puts in the context (dampsym.wp.<problem>,
// JSON), so that one function measures dampsym's, the peers' and scipy's error alike.
//   <method>   dampsym's kernel (with_kernel, constructed as bench_harness.cpp does), h = h0/2^k;
//              the peers (Boost.Odeint, GSL) are in bench_workprecision_peers.cpp.
// Adaptive solvers run over rtol = 1e-3 ... 1e-12 with atol = 1e-3 rtol (as bench/pde_scipy.py).
// The problems' references are computed when the benchmarks are registered (~0.1 s).
#include "bench/workprecision.hpp"

#include "core/integrate.hpp"
#include "harness/case/case.hpp"
#include "harness/registry.hpp"
#include "harness/run/case_job.hpp"
#include "reference/gsl_reference.hpp"

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace dampsym::bench {
namespace {

// A problem of the comparison: its case file, the coarsest step of the fixed-step ladders and
// dampsym's methods drawn.
struct Setup {
    std::string label, case_file;
    double h0;
    std::vector<std::string> methods;
};

// dampsym's method `info` through the harness's kernel K on problem P, at rung k.
template <class K, class P>
void register_kernel(const std::string& label, std::shared_ptr<const P> problem,
                     const MethodInfo& info, const WpSpan& s, int k) {
    const std::int64_t n = rung_steps(s, k);
    const double h = (s.t_end - s.t0) / static_cast<double>(n), t0 = s.t0;
    const std::string name = "wp/" + label + "/" + std::string(info.id) + "/" + std::to_string(k);
    auto* b = benchmark::RegisterBenchmark(name.c_str(), [=, &info](benchmark::State& state) {
        Counters counters;
        Vec z;
        for (auto _ : state) {
            counters = {};
            K stepper(*problem, info, h, counters);
            z = problem->initial_state();
            const IntegrateOutcome res = integrate(stepper, z, t0, h, n);
            benchmark::DoNotOptimize(z.data());
            benchmark::ClobberMemory();
            if (res.status != RunStatus::ok) {
                state.SkipWithError((std::string(to_string(res.status)) + " at step " +
                                     std::to_string(res.failed_step))
                                        .c_str());
                return;
            }
        }
        set_wp_counters(state, z.data(), static_cast<int>(z.size()), n, counters.rhs_evals,
                        counters.jac_evals);
        state.counters["h"] = h;
    });
    configure_wp(b);
}

// The reference's final state and its name, as JSON for the context.
template <class P>
nlohmann::json reference_of(const P& problem, const CaseSpec& c) {
    nlohmann::json out;
    Vec ref(problem.dim());
    if constexpr (HasExactSolution<P>) {
        problem.exact(c.t0, problem.initial_state(), c.t_end, ref);
        out["kind"] = "exact";
        out["name"] = P::id == "kepler" ? "exact solution (Kepler's equation, HLW I.2)"
                                        : "exact solution (Jacobi elliptic functions, B(1.7))";
        out["error_estimate"] = 0.0;
    } else {
        // The harness's own request for the case (as bench_reference.cpp), certified.
        const std::int64_t points = detail::output_points(c);
        const ReferenceSolution sol = certified_reference(detail::reference_request(
            problem, c, detail::reference_times(c, points, detail::case_needs_grid(c, points))));
        if (!sol.ok) throw std::runtime_error(c.id + ": reference: " + sol.error);
        ref = sol.states.col(sol.states.cols() - 1);
        auto num = [](double v) { return nlohmann::json(v).dump(); };
        out["kind"] = "gsl-certified";
        out["name"] = "certified GSL " + sol.stepper + " (epsrel " + num(sol.epsrel) + ", epsabs " +
                      num(sol.epsabs) + "; certified by " + sol.certifier + " at epsrel " +
                      num(sol.cert_epsrel) + ")";
        out["error_estimate"] = sol.error_estimate;
    }
    out["final_state"] = std::vector<double>(ref.data(), ref.data() + ref.size());
    return out;
}

// Every benchmark of one problem (dampsym's methods, then the peers) and its context entry
// dampsym.wp.<label>: case, parameters, span, ladders, reference, vector-field samples.
template <class P>
void register_problem_wp(const Setup& setup) {
    const CaseSpec c =
        load_case(std::string(DAMPSYM_BENCH_DIR) + "/../verify/cases/" + setup.case_file, {});
    auto problem = std::make_shared<const P>(P::from_params(c.params));
    const WpSpan s{c.t0, c.t_end, setup.h0};
    for (const std::string& m : setup.methods) {
        const MethodInfo* info = find_method(m);
        if (info == nullptr) throw std::logic_error("no method " + m);
        for (int k = 0; k < s.fixed_rungs; ++k)
            with_kernel<P>(*info, [&]<class K>() {
                register_kernel<K, P>(setup.label, problem, *info, s, k);
            });
    }
    nlohmann::json samples = register_wp_peers(setup.label, *problem, s);
    nlohmann::json params = nlohmann::json::object();
    for (const auto& [k, v] : c.params.scalars) params[k] = v;
    const Vec z0 = problem->initial_state();
    const nlohmann::json ctx = {
        {"case", c.id},
        {"case_file", "verify/cases/" + setup.case_file},
        {"problem", c.problem_id},
        {"params", params},
        {"t0", c.t0},
        {"t_end", c.t_end},
        {"initial_state", std::vector<double>(z0.data(), z0.data() + z0.size())},
        {"h0", s.h0},
        {"fixed_rungs", s.fixed_rungs},
        {"rtol_exponents", {s.tol_first, s.tol_last}},
        {"atol_over_rtol", s.atol_over_rtol},
        {"methods", setup.methods},
        {"rhs_samples", samples},
        {"reference", reference_of(*problem, c)}};
    benchmark::AddCustomContext("dampsym.wp." + setup.label, ctx.dump());
}

} // namespace

void register_workprecision_benchmarks() {
    try {
        register_problem_wp<Pendulum>(
            {"pendulum", "pend-table41-g0.05.json", 0.1, {"csv1", "glifrk2", "glifrk3"}});
        register_problem_wp<Kepler>(
            {"kepler", "kepler-fig21-precession.json", 0.05, {"csv1", "glifrk2", "glifrk3"}});
        register_problem_wp<RigidBody>(
            {"rigid-body", "rb-orders.json", 0.1, {"cimp", "glifrk2", "glifrk3"}});
    } catch (const std::exception& e) {
        std::fprintf(stderr, "dampsym_bench: work-precision: %s\n", e.what());
        std::exit(2);
    }
}

} // namespace dampsym::bench
