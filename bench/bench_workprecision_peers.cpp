// The peers of the work-precision benchmarks (bench_workprecision.cpp has the problems, the
// references and dampsym's methods), each on the problem's vector field written on plain arrays as
// a user of these libraries would write it:
//   wp/<problem>/odeint-dopri5/<k>             make_controlled(atol, rtol, runge_kutta_dopri5) +
//                                              integrate_adaptive (ends at t_end exactly), rtol =
//                                              10^-k
//   wp/<problem>/odeint-rkn-sb3a-m4-damped/<k> separable problems: symplectic_rkn_sb3a_m4_mclachlan
//                                              between exact damping half-steps p *= e^{−γh}
//                                              (bench_peers.cpp), h = h0/2^k
//   wp/<problem>/gsl-rk8pd/<k>                 gsl_odeiv2_driver_apply, control_y_new(atol, rtol)
//   wp/<problem>/gsl-rk4imp/<k>                gsl_odeiv2_step_apply at the fixed h = h0/2^k with
//   the
//                                              analytic Jacobian; the driver only carries the
//                                              Newton tolerance (1e-12), as in bench_peers.cpp
// Force evaluations: calls of the force (the RKN) or of the whole vector field (the others).
#include "bench/workprecision.hpp"

// symplectic_rkn_sb3a_m4_mclachlan.hpp (Boost 1.74) uses its base class without including it.
#include <boost/numeric/odeint/integrate/integrate_adaptive.hpp>
#include <boost/numeric/odeint/stepper/base/symplectic_rkn_stepper_base.hpp>
#include <boost/numeric/odeint/stepper/generation.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_dopri5.hpp>
#include <boost/numeric/odeint/stepper/symplectic_rkn_sb3a_m4_mclachlan.hpp>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <memory>
#include <stdexcept>
#include <string>

namespace dampsym::bench {
namespace {

namespace odeint = boost::numeric::odeint;

// A separable problem with unit mass and constant γ: q' = p, p' = F(q) − 2γp.
template <class P>
struct SeparableSystem {
    static constexpr int n = P::static_n, dim = 2 * n;
    static constexpr bool separable = true;
    P problem;
    double gamma;
    explicit SeparableSystem(const P& p) : problem(p), gamma(p.gamma_at(0.0)) {}
    void rhs(double t, const double* y, double* dy) const {
        for (int i = 0; i < n; ++i) dy[i] = y[n + i];
        double* po = dy + n;
        problem.force(t, y, po);
        for (int i = 0; i < n; ++i) po[i] -= 2.0 * gamma * y[n + i];
    }
    // Row-major ∂f/∂y = [0, I; ∂F/∂q, −2γI].
    void jac(double t, const double* y, double* J) const {
        Eigen::Matrix<double, n, n> dF;
        problem.force_jacobian(t, y, dF);
        std::fill(J, J + dim * dim, 0.0);
        for (int i = 0; i < n; ++i) {
            J[i * dim + n + i] = 1.0;
            for (int j = 0; j < n; ++j) J[(n + i) * dim + j] = dF(i, j);
            J[(n + i) * dim + n + i] = -2.0 * gamma;
        }
    }
};

// The perturbed rigid body B(1.7): z' = z × (I⁻¹z) − γ(t) z, γ(t) = ½ε cos 2t.
struct RigidBodySystem {
    static constexpr int dim = 3;
    static constexpr bool separable = false;
    RigidBody problem;
    explicit RigidBodySystem(const RigidBody& p) : problem(p) {}
    void rhs(double t, const double* z, double* dz) const {
        const double w1 = z[0] / problem.I1, w2 = z[1] / problem.I2, w3 = z[2] / problem.I3;
        const double g = problem.gamma_at(t);
        dz[0] = z[1] * w3 - z[2] * w2 - g * z[0];
        dz[1] = z[2] * w1 - z[0] * w3 - g * z[1];
        dz[2] = z[0] * w2 - z[1] * w1 - g * z[2];
    }
    void jac(double t, const double* z, double* J) const {
        Mat m(3, 3);
        problem.rhs_jacobian(t, Eigen::Map<const Vec>(z, 3), m);
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) J[i * 3 + j] = m(i, j);
    }
};

template <class Sys>
using StateOf = std::array<double, Sys::dim>;

template <class Sys>
StateOf<Sys> initial_of(const Sys& sys) {
    const Vec z0 = sys.problem.initial_state();
    StateOf<Sys> y;
    std::copy(z0.data(), z0.data() + Sys::dim, y.begin());
    return y;
}

void skip_unless_finite(benchmark::State& state, const double* y, int dim) {
    for (int i = 0; i < dim; ++i)
        if (!std::isfinite(y[i])) {
            state.SkipWithError("non-finite final state");
            return;
        }
}

template <class Sys>
void run_odeint_dopri5(benchmark::State& state, const Sys& sys, const WpSpan& s, double rtol,
                       double atol) {
    using State = StateOf<Sys>;
    std::int64_t evals = 0;
    std::size_t steps = 0;
    State x{};
    auto f = [&sys, &evals](const State& y, State& dy, double t) {
        ++evals;
        sys.rhs(t, y.data(), dy.data());
    };
    for (auto _ : state) {
        evals = 0;
        x = initial_of(sys);
        auto stepper = odeint::make_controlled(atol, rtol, odeint::runge_kutta_dopri5<State>());
        steps = odeint::integrate_adaptive(stepper, f, x, s.t0, s.t_end, 1e-3);
        benchmark::DoNotOptimize(x);
    }
    skip_unless_finite(state, x.data(), Sys::dim);
    set_wp_counters(state, x.data(), Sys::dim, static_cast<std::int64_t>(steps), evals, 0);
    state.counters["rtol"] = rtol;
    state.counters["atol"] = atol;
}

template <class Sys>
void run_odeint_rkn(benchmark::State& state, const Sys& sys, const WpSpan& s, std::int64_t steps) {
    using Coor = std::array<double, Sys::n>;
    const double h = (s.t_end - s.t0) / static_cast<double>(steps);
    const double half = std::exp(-sys.gamma * h); // p' = −2γp over h/2
    std::int64_t evals = 0;
    Coor q{}, p{};
    auto force = [&sys, &evals](const Coor& x, Coor& dpdt) {
        ++evals;
        sys.problem.force(0.0, x, dpdt);
    };
    for (auto _ : state) {
        evals = 0;
        const StateOf<Sys> y0 = initial_of(sys);
        std::copy(y0.begin(), y0.begin() + Sys::n, q.begin());
        std::copy(y0.begin() + Sys::n, y0.end(), p.begin());
        odeint::symplectic_rkn_sb3a_m4_mclachlan<Coor> stepper;
        for (std::int64_t k = 0; k < steps; ++k) {
            for (double& v : p) v *= half;
            stepper.do_step(force, q, p, s.t0 + static_cast<double>(k) * h, h);
            for (double& v : p) v *= half;
        }
        benchmark::DoNotOptimize(q);
        benchmark::DoNotOptimize(p);
    }
    StateOf<Sys> z;
    std::copy(q.begin(), q.end(), z.begin());
    std::copy(p.begin(), p.end(), z.begin() + Sys::n);
    skip_unless_finite(state, z.data(), Sys::dim);
    set_wp_counters(state, z.data(), Sys::dim, steps, evals, 0);
    state.counters["h"] = h;
}

// ---- GSL ----

template <class Sys>
struct GslContext {
    const Sys* sys;
    std::int64_t evals = 0, jacs = 0;
};

template <class Sys>
int gsl_rhs(double t, const double y[], double dydt[], void* params) {
    auto* c = static_cast<GslContext<Sys>*>(params);
    ++c->evals;
    c->sys->rhs(t, y, dydt);
    return GSL_SUCCESS;
}

template <class Sys>
int gsl_jac(double t, const double y[], double* dfdy, double dfdt[], void* params) {
    auto* c = static_cast<GslContext<Sys>*>(params);
    ++c->jacs;
    c->sys->jac(t, y, dfdy);
    std::fill(dfdt, dfdt + Sys::dim, 0.0); // not used by rk4imp's Newton iteration
    return GSL_SUCCESS;
}

struct DriverDeleter {
    void operator()(gsl_odeiv2_driver* d) const { gsl_odeiv2_driver_free(d); }
};
using Driver = std::unique_ptr<gsl_odeiv2_driver, DriverDeleter>;

void skip_gsl(benchmark::State& state, const char* what, int status) {
    state.SkipWithError((std::string(what) + ": " + gsl_strerror(status)).c_str());
}

template <class Sys>
void run_gsl_rk8pd(benchmark::State& state, const Sys& sys, const WpSpan& s, double rtol,
                   double atol) {
    gsl_set_error_handler_off();
    GslContext<Sys> ctx{&sys};
    gsl_odeiv2_system gs{gsl_rhs<Sys>, gsl_jac<Sys>, Sys::dim, &ctx};
    StateOf<Sys> y{};
    unsigned long steps = 0;
    for (auto _ : state) {
        ctx.evals = 0;
        Driver d(gsl_odeiv2_driver_alloc_y_new(&gs, gsl_odeiv2_step_rk8pd, 1e-3, atol, rtol));
        y = initial_of(sys);
        double t = s.t0;
        if (int st = gsl_odeiv2_driver_apply(d.get(), &t, s.t_end, y.data()); st != GSL_SUCCESS)
            return skip_gsl(state, "gsl_odeiv2_driver_apply", st);
        steps = d->n;
        benchmark::DoNotOptimize(y);
    }
    skip_unless_finite(state, y.data(), Sys::dim);
    set_wp_counters(state, y.data(), Sys::dim, static_cast<std::int64_t>(steps), ctx.evals, 0);
    state.counters["rtol"] = rtol;
    state.counters["atol"] = atol;
}

template <class Sys>
void run_gsl_rk4imp(benchmark::State& state, const Sys& sys, const WpSpan& s, std::int64_t steps) {
    gsl_set_error_handler_off();
    const double h = (s.t_end - s.t0) / static_cast<double>(steps);
    GslContext<Sys> ctx{&sys};
    gsl_odeiv2_system gs{gsl_rhs<Sys>, gsl_jac<Sys>, Sys::dim, &ctx};
    Driver d(gsl_odeiv2_driver_alloc_y_new(&gs, gsl_odeiv2_step_rk4imp, h, 1e-12, 1e-12));
    StateOf<Sys> y{}, yerr{};
    for (auto _ : state) {
        ctx.evals = ctx.jacs = 0;
        if (int st = gsl_odeiv2_step_reset(d->s); st != GSL_SUCCESS)
            return skip_gsl(state, "gsl_odeiv2_step_reset", st);
        y = initial_of(sys);
        for (std::int64_t k = 0; k < steps; ++k)
            if (int st = gsl_odeiv2_step_apply(d->s, s.t0 + static_cast<double>(k) * h, h, y.data(),
                                               yerr.data(), nullptr, nullptr, &gs);
                st != GSL_SUCCESS)
                return skip_gsl(state, "gsl_odeiv2_step_apply", st);
        benchmark::DoNotOptimize(y);
    }
    skip_unless_finite(state, y.data(), Sys::dim);
    set_wp_counters(state, y.data(), Sys::dim, steps, ctx.evals, ctx.jacs);
    state.counters["h"] = h;
}

// The plain vector field against the problem's rhs (and its Jacobian) at two states; returns the
// samples [{t, z, f}].
template <class P, class Sys>
nlohmann::json checked_samples(const P& problem, const Sys& sys, double t0,
                               const std::string& label) {
    nlohmann::json out = nlohmann::json::array();
    for (const double scale : {1.0, 0.9}) {
        const double t = t0 + (scale == 1.0 ? 0.0 : 0.3);
        const Vec z = scale * problem.initial_state();
        Vec f(Sys::dim), g(Sys::dim);
        Mat J(Sys::dim, Sys::dim);
        std::array<double, Sys::dim * Sys::dim> Jp{};
        sys.rhs(t, z.data(), f.data());
        sys.jac(t, z.data(), Jp.data());
        problem.rhs(t, z, g);
        problem.rhs_jacobian(t, z, J);
        double jd = 0.0;
        for (int i = 0; i < Sys::dim; ++i)
            for (int j = 0; j < Sys::dim; ++j)
                jd = std::max(jd,
                              std::abs(Jp[static_cast<std::size_t>(i * Sys::dim + j)] - J(i, j)));
        if ((f - g).lpNorm<Eigen::Infinity>() > 1e-14 * (1.0 + g.lpNorm<Eigen::Infinity>()) ||
            jd > 1e-14 * (1.0 + J.lpNorm<Eigen::Infinity>()))
            throw std::logic_error(label + ": the peers' vector field differs from the problem's");
        out.push_back({{"t", t},
                       {"z", std::vector<double>(z.data(), z.data() + z.size())},
                       {"f", std::vector<double>(f.data(), f.data() + f.size())}});
    }
    return out;
}

template <class P, class Sys>
nlohmann::json register_peers(const std::string& label, const P& problem, const WpSpan& s) {
    const Sys sys(problem);
    nlohmann::json samples = checked_samples(problem, sys, s.t0, label);
    const std::string base = "wp/" + label + "/";
    auto reg = [&](const std::string& solver, int k, auto run) {
        configure_wp(
            benchmark::RegisterBenchmark((base + solver + "/" + std::to_string(k)).c_str(), run));
    };
    for (int k = 0; k < s.fixed_rungs; ++k) {
        const std::int64_t n = rung_steps(s, k);
        if constexpr (Sys::separable)
            reg("odeint-rkn-sb3a-m4-damped", k,
                [=](benchmark::State& st) { run_odeint_rkn(st, sys, s, n); });
        reg("gsl-rk4imp", k, [=](benchmark::State& st) { run_gsl_rk4imp(st, sys, s, n); });
    }
    for (int k = s.tol_first; k <= s.tol_last; ++k) {
        const double rtol = std::pow(10.0, -k), atol = s.atol_over_rtol * rtol;
        reg("odeint-dopri5", k,
            [=](benchmark::State& st) { run_odeint_dopri5(st, sys, s, rtol, atol); });
        reg("gsl-rk8pd", k, [=](benchmark::State& st) { run_gsl_rk8pd(st, sys, s, rtol, atol); });
    }
    return samples;
}

} // namespace

nlohmann::json register_wp_peers(const std::string& label, const Pendulum& p, const WpSpan& s) {
    return register_peers<Pendulum, SeparableSystem<Pendulum>>(label, p, s);
}
nlohmann::json register_wp_peers(const std::string& label, const Kepler& p, const WpSpan& s) {
    return register_peers<Kepler, SeparableSystem<Kepler>>(label, p, s);
}
nlohmann::json register_wp_peers(const std::string& label, const RigidBody& p, const WpSpan& s) {
    return register_peers<RigidBody, RigidBodySystem>(label, p, s);
}

} // namespace dampsym::bench
