// Peers on the same damped pendulum q'' + 2γq' + sin q = 0 (γ = 0.1, q0 = 1, p0 = 0), same h and
// step count as harness/pendulum/*:
//   peer/pendulum/bare-csv1                 csv1's formulas (src/methods/csv1.hpp, constant γ) on
//                                           plain doubles: the physical limit of that step
//   peer/pendulum/bare-stormer-verlet       stormer-verlet's arithmetic (Lobatto IIIA-IIIB with the
//                                           damping −2γp in the vector field, as the partitioned
//                                           engine computes it) on plain doubles
//   peer/pendulum/bare-cse-if               cse-if's arithmetic (B(2.18), as the partitioned engine
//                                           computes it) on plain doubles; cse-etd B(2.19) differs
//                                           only in two coefficients
//   peer/pendulum/bare-csv1-perk            csv1-perk's arithmetic (B(2.20) as the partitioned
//                                           engine computes it) on plain doubles
//   peer/pendulum/odeint-velocity-verlet    Boost.Odeint velocity_verlet, damping −2γp in the force
//                                           (a non-conformal baseline; FSAL: one force call a step)
//   peer/pendulum/odeint-rkn-sb3a-m4-damped symplectic_rkn_sb3a_m4_mclachlan between exact damping
//                                           half-steps p *= e^{−γh} (p decays as e^{−2γt})
//   peer/pendulum/odeint-rk4                runge_kutta4 on z' = [p, −sin q − 2γp]
//   peer/pendulum/gsl-rk4imp, gsl-rk2imp    GSL's implicit Gauss steppers (2 and 1 stages) through
//                                           gsl_odeiv2_step_apply with the analytic Jacobian
// Force evaluations are counted by the functors (one per evaluation of −sin q or of the full rhs).
#include "bench/bench_common.hpp"

// symplectic_rkn_sb3a_m4_mclachlan.hpp (Boost 1.74) uses its base class without including it.
#include <boost/numeric/odeint/stepper/base/symplectic_rkn_stepper_base.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta4.hpp>
#include <boost/numeric/odeint/stepper/symplectic_rkn_sb3a_m4_mclachlan.hpp>
#include <boost/numeric/odeint/stepper/velocity_verlet.hpp>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_odeiv2.h>

#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <string_view>
#include <utility>

namespace dampsym::bench {
namespace {

namespace odeint = boost::numeric::odeint;
using State1 = std::array<double, 1>;
using State2 = std::array<double, 2>;

constexpr std::int64_t kN = kSteps1Dof;

// Fails the benchmark if the final state is not finite (a peer that blew up is not a timing).
bool finite_or_skip(benchmark::State& state, double q, double p) {
    if (std::isfinite(q) && std::isfinite(p)) return true;
    state.SkipWithError("non-finite final state");
    return false;
}

// Fails the benchmark of a bare loop that claims method's arithmetic if its final state is not the
// kernel's bit for bit (then it would time something else).
void same_as_kernel_or_skip(benchmark::State& state, std::string_view method, double q, double p) {
    if (!kernel_ends_at(method, q, p))
        state.SkipWithError(("final state differs from " + std::string(method) + "'s").c_str());
}

void bare_csv1(benchmark::State& state) {
    const double h = kStep, hh = 0.5 * kStep;
    // csv1 with constant γ: d1 = d2 = e^{−2γ(h/2)} = e^{−γh}.
    const double d = std::exp(-kGamma * h);
    std::int64_t evals = 0;
    for (auto _ : state) {
        double q = kPendulumQ0, p = kPendulumP0;
        benchmark::DoNotOptimize(q);
        benchmark::DoNotOptimize(p);
        for (std::int64_t k = 0; k < kN; ++k) {
            p = d * p + hh * (-std::sin(q));   // p½ = e^{−γh}p − (h/2)∇V(q)
            q += h * p;                        // q₁ = q + h∇T(p½)
            p = d * (p + hh * (-std::sin(q))); // p₁ = e^{−γh}(p½ − (h/2)∇V(q₁))
        }
        evals += 2 * kN;
        benchmark::DoNotOptimize(q);
        benchmark::DoNotOptimize(p);
        if (!finite_or_skip(state, q, p)) break;
    }
    set_step_counters(state, kN, evals);
}

// The timing loop of a bare loop that claims `method`'s arithmetic: kN calls of step(q, p) from the
// pendulum's initial state per iteration, evals_per_step force evaluations each; the final state
// must be the kernel's bit for bit (same_as_kernel_or_skip).
template <class Step>
void time_bare_loop(benchmark::State& state, std::string_view method, int evals_per_step,
                    Step step) {
    std::int64_t evals = 0;
    double q_end = 0.0, p_end = 0.0;
    for (auto _ : state) {
        double q = kPendulumQ0, p = kPendulumP0;
        benchmark::DoNotOptimize(q);
        benchmark::DoNotOptimize(p);
        for (std::int64_t k = 0; k < kN; ++k) step(q, p);
        evals += evals_per_step * kN;
        benchmark::DoNotOptimize(q);
        benchmark::DoNotOptimize(p);
        q_end = q;
        p_end = p;
        if (!finite_or_skip(state, q, p)) break;
    }
    same_as_kernel_or_skip(state, method, q_end, p_end);
    set_step_counters(state, kN, evals);
}

// stormer-verlet (HLW(3.6), Lobatto IIIA-IIIB) in the Rayleigh form p' = −sin q − 2γp, operation
// for operation as the partitioned engine steps it (partitioned_engine.hpp: schedule Q₁ P₁ P₂ Q₂,
// the P₁ stage a linear solve). Its chain from q_n to q_{n+1} holds a division by 1 + hγ and
// the force at Q₂ (= q_{n+1}); the force at Q₁ = q_n is the previous step's F₂, which the
// compiler shares.
void bare_stormer_verlet(benchmark::State& state) {
    const double h = kStep, hh = 0.5 * kStep, g = kGamma;
    const double hd = 2.0 * h * 0.5 * g, denominator = 1.0 + (2.0 * h * 0.5) * g;
    time_bare_loop(
        state, "stormer-verlet", 2, [=](double& q, double& p) __attribute__((always_inline)) {
            const double f1 = -std::sin(q);                // F(Q₁), Q₁ = q
            const double p1 = (p + hh * f1) / denominator; // (1 + hγ)P₁ = p + (h/2)F₁
            const double p2 = p + hh * f1 - hd * p1;       // P₂ = p + (h/2)(F₁ − 2γP₁)
            const double q2 = q + hh * p1 + hh * p2;       // Q₂ = q + (h/2)(P₁ + P₂)
            const double f2 = -std::sin(q2);               // F(Q₂)
            q = q + hh * p1 + hh * p2;                     // q₁ = Q₂
            p = p + hh * (f1 - 2.0 * g * p1);              // p₁ = p + (h/2)(F₁ − 2γP₁)
            p = p + hh * (f2 - 2.0 * g * p2);              //        + (h/2)(F₂ − 2γP₂)
        });
}

// cse-if (B(2.18), symplectic Euler under the integrating factor, x_B = 2γh) as the partitioned
// engine steps it: P₁ = e^{−x_B} p + h F(q), q₁ = q + h P₁, p₁ = P₁. One force evaluation a step,
// on the chain from q_n to q_{n+1}.
void bare_cse_if(benchmark::State& state) {
    const double h = kStep, e = std::exp(-2.0 * (kGamma * h));
    time_bare_loop(
        state, "cse-if", 1, [=](double& q, double& p) __attribute__((always_inline)) {
            p = e * p + h * (-std::sin(q));
            q = q + h * p;
        });
}

// csv1-perk (B(2.20), x_B = 2γh) as the partitioned engine steps it (damping in the
// coefficients): P₁ = P₂ = e^{−x_B/2} p + (h/2) F(q), Q₂ = q + (h/2)P₁ + (h/2)P₂,
// q₁ = q + h(½P₁ + ½P₂), p₁ = e^{−x_B} p + (h/2)e^{−x_B/2}(F(q) + F(Q₂)). Q₂ and q₁ are the same
// number but rounded differently, so the next step's F(q₁) is a second evaluation.
void bare_csv1_perk(benchmark::State& state) {
    const double h = kStep, hh = h * 0.5, xb = 2.0 * (kGamma * h);
    const double e = std::exp(-0.5 * xb), e2 = std::exp(-xb), w = h * (0.5 * e);
    time_bare_loop(
        state, "csv1-perk", 2, [=](double& q, double& p) __attribute__((always_inline)) {
            const double f1 = -std::sin(q);
            const double p1 = e * p + hh * f1;
            const double q2 = q + hh * p1 + hh * p1;
            const double f2 = -std::sin(q2);
            q = q + h * (0.5 * p1 + 0.5 * p1);
            p = e2 * p + (w * f1 + w * f2);
        });
}

// velocity_verlet's system: a = F(q, v, t) with the damping in the "force".
struct DampedPendulumAccel {
    std::int64_t* evals;
    void operator()(const State1& q, const State1& v, State1& a, double) const {
        ++*evals;
        a[0] = -std::sin(q[0]) - 2.0 * kGamma * v[0];
    }
};

void odeint_velocity_verlet(benchmark::State& state) {
    std::int64_t evals = 0;
    for (auto _ : state) {
        odeint::velocity_verlet<State1> stepper;
        std::pair<State1, State1> x{{kPendulumQ0}, {kPendulumP0}};
        DampedPendulumAccel sys{&evals};
        for (std::int64_t k = 0; k < kN; ++k)
            stepper.do_step(sys, x, static_cast<double>(k) * kStep, kStep);
        benchmark::DoNotOptimize(x);
        if (!finite_or_skip(state, x.first[0], x.second[0])) break;
    }
    set_step_counters(state, kN, evals);
}

struct PendulumForce {
    std::int64_t* evals;
    void operator()(const State1& q, State1& dpdt) const {
        ++*evals;
        dpdt[0] = -std::sin(q[0]);
    }
};

void odeint_rkn_damped(benchmark::State& state) {
    const double half = std::exp(-kGamma * kStep); // e^{−2γ(h/2)}
    std::int64_t evals = 0;
    for (auto _ : state) {
        odeint::symplectic_rkn_sb3a_m4_mclachlan<State1> stepper;
        State1 q{kPendulumQ0}, p{kPendulumP0};
        PendulumForce force{&evals};
        for (std::int64_t k = 0; k < kN; ++k) {
            p[0] *= half;
            stepper.do_step(force, q, p, static_cast<double>(k) * kStep, kStep);
            p[0] *= half;
        }
        benchmark::DoNotOptimize(q);
        benchmark::DoNotOptimize(p);
        if (!finite_or_skip(state, q[0], p[0])) break;
    }
    set_step_counters(state, kN, evals);
}

struct PendulumRhs {
    std::int64_t* evals;
    void operator()(const State2& z, State2& dz, double) const {
        ++*evals;
        dz[0] = z[1];
        dz[1] = -std::sin(z[0]) - 2.0 * kGamma * z[1];
    }
};

void odeint_rk4(benchmark::State& state) {
    std::int64_t evals = 0;
    for (auto _ : state) {
        odeint::runge_kutta4<State2> stepper;
        State2 z{kPendulumQ0, kPendulumP0};
        PendulumRhs rhs{&evals};
        for (std::int64_t k = 0; k < kN; ++k)
            stepper.do_step(rhs, z, static_cast<double>(k) * kStep, kStep);
        benchmark::DoNotOptimize(z);
        if (!finite_or_skip(state, z[0], z[1])) break;
    }
    set_step_counters(state, kN, evals);
}

// ---- GSL implicit Gauss steppers ----

struct GslCounts {
    std::int64_t rhs = 0, jac = 0;
};

int gsl_pendulum_rhs(double, const double y[], double dydt[], void* params) {
    ++static_cast<GslCounts*>(params)->rhs;
    dydt[0] = y[1];
    dydt[1] = -std::sin(y[0]) - 2.0 * kGamma * y[1];
    return GSL_SUCCESS;
}

int gsl_pendulum_jac(double, const double y[], double* dfdy, double dfdt[], void* params) {
    ++static_cast<GslCounts*>(params)->jac;
    gsl_matrix_view m = gsl_matrix_view_array(dfdy, 2, 2);
    gsl_matrix_set(&m.matrix, 0, 0, 0.0);
    gsl_matrix_set(&m.matrix, 0, 1, 1.0);
    gsl_matrix_set(&m.matrix, 1, 0, -std::cos(y[0]));
    gsl_matrix_set(&m.matrix, 1, 1, -2.0 * kGamma);
    dfdt[0] = 0.0;
    dfdt[1] = 0.0;
    return GSL_SUCCESS;
}

// GSL's Newton tolerance for its implicit steppers comes from the driver's control object (the
// steppers refuse to step without a driver), so a driver is allocated only to carry it; every
// step is gsl_odeiv2_step_apply at the fixed h. rk4imp and rk2imp estimate their error by step
// doubling: each step is one full step and two half steps (three nonlinear solves).
constexpr double kGslEpsAbs = 1e-12, kGslEpsRel = 1e-12;

struct DriverDeleter {
    void operator()(gsl_odeiv2_driver* d) const { gsl_odeiv2_driver_free(d); }
};

void gsl_implicit(benchmark::State& state, const gsl_odeiv2_step_type* type) {
    gsl_set_error_handler_off();
    GslCounts counts;
    gsl_odeiv2_system sys{gsl_pendulum_rhs, gsl_pendulum_jac, 2, &counts};
    std::unique_ptr<gsl_odeiv2_driver, DriverDeleter> drv(
        gsl_odeiv2_driver_alloc_y_new(&sys, type, kStep, kGslEpsAbs, kGslEpsRel));
    if (!drv) {
        state.SkipWithError("gsl_odeiv2_driver_alloc_y_new failed");
        return;
    }
    gsl_odeiv2_step* step = drv->s;
    std::int64_t evals = 0, jacs = 0;
    for (auto _ : state) {
        counts = {};
        if (int s = gsl_odeiv2_step_reset(step); s != GSL_SUCCESS) {
            state.SkipWithError((std::string("gsl_odeiv2_step_reset: ") + gsl_strerror(s)).c_str());
            break;
        }
        double y[2] = {kPendulumQ0, kPendulumP0}, yerr[2];
        int status = GSL_SUCCESS;
        std::int64_t k = 0;
        for (; k < kN && status == GSL_SUCCESS; ++k)
            status = gsl_odeiv2_step_apply(step, static_cast<double>(k) * kStep, kStep, y, yerr,
                                           nullptr, nullptr, &sys);
        benchmark::DoNotOptimize(y);
        if (status != GSL_SUCCESS) {
            state.SkipWithError((std::string("gsl_odeiv2_step_apply: ") + gsl_strerror(status) +
                                 " at step " + std::to_string(k))
                                    .c_str());
            break;
        }
        if (!finite_or_skip(state, y[0], y[1])) break;
        evals += counts.rhs;
        jacs += counts.jac;
    }
    set_step_counters(state, kN, evals);
    const double iters =
        static_cast<double>(std::max<benchmark::IterationCount>(state.iterations(), 1));
    state.counters["jac_evals"] = static_cast<double>(jacs) / iters;
    state.counters["newton_tolerance_epsabs"] = kGslEpsAbs;
    state.counters["newton_tolerance_epsrel"] = kGslEpsRel;
}

} // namespace

void register_peer_benchmarks() {
    configure(benchmark::RegisterBenchmark("peer/pendulum/bare-csv1", bare_csv1), true);
    configure(
        benchmark::RegisterBenchmark("peer/pendulum/bare-stormer-verlet", bare_stormer_verlet),
        true);
    configure(benchmark::RegisterBenchmark("peer/pendulum/bare-cse-if", bare_cse_if), true);
    configure(benchmark::RegisterBenchmark("peer/pendulum/bare-csv1-perk", bare_csv1_perk), true);
    configure(benchmark::RegisterBenchmark("peer/pendulum/odeint-velocity-verlet",
                                           odeint_velocity_verlet),
              true);
    configure(
        benchmark::RegisterBenchmark("peer/pendulum/odeint-rkn-sb3a-m4-damped", odeint_rkn_damped),
        false);
    configure(benchmark::RegisterBenchmark("peer/pendulum/odeint-rk4", odeint_rk4), false);
    configure(benchmark::RegisterBenchmark(
                  "peer/pendulum/gsl-rk4imp",
                  [](benchmark::State& s) { gsl_implicit(s, gsl_odeiv2_step_rk4imp); }),
              true);
    configure(benchmark::RegisterBenchmark(
                  "peer/pendulum/gsl-rk2imp",
                  [](benchmark::State& s) { gsl_implicit(s, gsl_odeiv2_step_rk2imp); }),
              true);
}

} // namespace dampsym::bench
