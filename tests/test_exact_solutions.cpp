// Tests of the class, not the instance: every problem in ProblemList (src/harness/registry.hpp)
// with has_exact is checked here the day it is registered, through the exact-solution contract of
// core/problem.hpp (exact(t0, z0, t, out): the solution of the problem's own ODE with z(t0) = z0):
//   (a) z'(t) − f(t, z(t)) ≈ 0 at random times, t0 ≠ 0 included, by a 6th-order central difference;
//   (b) agreement with the certified GSL reference of the same problem from random t0 and states;
//   (c) z(t0) = z0 exactly; the solution from (t0, z0) continued from (t1, z(t1)) is the same
//       solution; for autonomous problems the solution from (t0, z0) at t0 + s is the one from
//       (0, z0) at s (and `autonomous` is true of f).
// And the other places where time enters, for every registered problem: Γ(0) = 0, Γ' = γ, dGamma
// = Γ(t+h) − Γ(t); periodic forcing of period T; d(t) of the maxima counted from t0; the output
// grid of a case that does not start at 0. Random problems: each scalar parameter drawn around its
// default (redrawn until from_params accepts it); random states around initial_state().
#include "diagnostics/capabilities.hpp"
#include "diagnostics/maxima.hpp"
#include "harness/registry.hpp"
#include "harness/run/case_job.hpp"
#include "reference/gsl_reference.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>

namespace {

using Catch::Matchers::WithinAbs;
using dampsym::Mat;
using dampsym::Vec;

constexpr double kEpsExact = std::numeric_limits<double>::epsilon();

template <class F>
void for_each_problem(F&& f) {
    dampsym::for_each_type(dampsym::ProblemList{}, [&]<class P>() { f.template operator()<P>(); });
}

template <class F>
void for_each_exact_problem(F&& f) {
    for_each_problem([&]<class P>() {
        if constexpr (P::has_exact) f.template operator()<P>();
    });
}

double uniform(std::mt19937_64& rng, double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
}

// Parameters drawn around the defaults: v = d (1 + 0.2u) + 0.2u', u, u' uniform in [−1, 1], the
// parameter's range respected; arrays keep their defaults. Redrawn until from_params accepts; a
// problem with constraints the draw keeps missing (e.g. counts) gets its defaults.
template <class P>
P random_problem(std::mt19937_64& rng, std::string& desc) {
    for (int attempt = 0; attempt <= 50; ++attempt) {
        const bool defaults = attempt == 50;
        dampsym::ParamMap m;
        std::ostringstream os;
        for (const dampsym::ParamSpec& s : P::param_specs()) {
            if (s.is_array) {
                m.arrays[s.name] = s.default_array;
                continue;
            }
            double v = s.default_value;
            if (!defaults) {
                v = v * (1.0 + 0.2 * uniform(rng, -1, 1)) + 0.2 * uniform(rng, -1, 1);
                if (s.range.lo >= 0.0) v = std::abs(v) + (s.range.lo_open ? 0.1 : 0.0);
                if (!s.range.contains(v)) v = s.default_value; // outside the problem's range
            }
            m[s.name] = v;
            os << s.name << "=" << v << " ";
        }
        try {
            P p = P::from_params(m);
            desc = os.str();
            return p;
        } catch (const std::exception& e) {
            if (defaults)
                throw std::runtime_error(std::string(P::id) + ": defaults rejected: " + e.what());
        }
    }
    throw std::logic_error("unreachable");
}

// A state near the initial one (first draw: z0 itself): each component moved by up to 2% of itself
// plus 0.2% of |z0| (small enough to stay on a bound Kepler orbit).
template <class P>
Vec random_state(const P& p, std::mt19937_64& rng, bool first) {
    Vec z = p.initial_state();
    if (first) return z;
    const double scale = z.norm();
    for (Eigen::Index i = 0; i < z.size(); ++i)
        z[i] += 0.02 * z[i] * uniform(rng, -1, 1) + 0.002 * scale * uniform(rng, -1, 1);
    return z;
}

template <class P>
Vec exact_at(const P& p, double t0, const Vec& z0, double t) {
    Vec z(p.dim());
    p.exact(t0, z0, t, z);
    return z;
}

template <class P>
Vec rhs_at(const P& p, double t, const Vec& z) {
    Vec f(p.dim());
    p.rhs(t, z, f);
    return f;
}

// 6th-order central difference D_h z(t) = [45(z(t+h) − z(t−h)) − 9(z(t+2h) − z(t−2h)) + (z(t+3h) −
// z(t−3h))]/(60h) = z'(t) + h⁶ z⁽⁷⁾(ξ)/140.
template <class P>
Vec central6(const P& p, double t0, const Vec& z0, double t, double h) {
    auto z = [&](double s) { return exact_at(p, t0, z0, t + s); };
    return (45.0 * (z(h) - z(-h)) - 9.0 * (z(2 * h) - z(-2 * h)) + (z(3 * h) - z(-3 * h))) /
           (60.0 * h);
}

} // namespace

TEST_CASE("exact solutions: every registered problem with one satisfies its ODE from any t0",
          "[exact]") {
    // Tolerance from the difference formula at h = 2⁻⁸ (t ± kh exact for the dyadic t below):
    // truncation h⁶|z⁽⁷⁾|/140, estimated by |D_{2h} − D_h| (= 63 × the truncation of D_h to
    // leading order, so counted once in full covers it), plus round-off Σ|c_k|/60 · δ/h =
    // (110/60) δ/h with δ = 64 ulp of max|z| the accuracy of one exact evaluation.
    std::mt19937_64 rng(20261123);
    int checked_problems = 0;
    for_each_exact_problem([&]<class P>() {
        ++checked_problems;
        const double h = std::ldexp(1.0, -8);
        for (int draw = 0; draw < 4; ++draw) {
            std::string desc;
            const P p = random_problem<P>(rng, desc);
            const Vec z0 = random_state(p, rng, draw == 0);
            const double t0 =
                draw == 0 ? 0.0 : std::ldexp(std::round(uniform(rng, -3, 3) * 256), -8);
            for (int k = 0; k < 3; ++k) {
                const double t = t0 + std::ldexp(std::round(uniform(rng, 0, 4) * 256), -8);
                const Vec d1 = central6(p, t0, z0, t, h);
                const Vec d2 = central6(p, t0, z0, t, 2 * h);
                const Vec z = exact_at(p, t0, z0, t);
                const Vec f = rhs_at(p, t, z);
                const double round_off =
                    (110.0 / 60.0) * 64 * kEpsExact * z.cwiseAbs().maxCoeff() / h;
                const double tol = (d2 - d1).cwiseAbs().maxCoeff() + round_off;
                const double residual = (d1 - f).cwiseAbs().maxCoeff();
                INFO(P::id << " " << desc << " t0 = " << t0 << " t = " << t
                           << ": |z' - f| = " << residual << ", tolerance " << tol);
                CHECK(std::isfinite(residual));
                CHECK(residual <= tol);
                // The tolerance is a statement about smoothness, far below any O(1) defect.
                CHECK(tol <= 1e-6 * std::max(1.0, f.cwiseAbs().maxCoeff()));
            }
        }
    });
    CHECK(checked_problems >= 3); // oscillator, kepler, rigid-body today
}

TEST_CASE("exact solutions: agree with the certified GSL reference from random t0 and states",
          "[exact]") {
    // rk8pd at epsrel 1e-13, epsabs 1e-14, certified by rk8pd at 1e-14/1e-15, t ∈ [t0, t0 + 3].
    // Check: max-norm difference ≤ 10 × max(estimate, 64 ulp of max|z|) (the estimate is the
    // difference of two solves; the factor allows its being an estimate).
    std::mt19937_64 rng(7);
    for_each_exact_problem([&]<class P>() {
        for (int draw = 0; draw < 3; ++draw) {
            std::string desc;
            const P p = random_problem<P>(rng, desc);
            dampsym::ReferenceRequest r;
            r.dim = p.dim();
            r.t0 = draw == 0 ? 0.0 : uniform(rng, -5, 5);
            r.y0 = random_state(p, rng, draw == 0);
            for (int k = 0; k <= 6; ++k) r.times.push_back(r.t0 + 0.5 * k);
            r.rhs = [p, z = Vec(p.dim()), f = Vec(p.dim())](double t, const double* y,
                                                            double* dydt) mutable {
                z = Eigen::Map<const Vec>(y, z.size());
                p.rhs(t, z, f);
                Eigen::Map<Vec>(dydt, f.size()) = f;
            };
            r.stepper = "rk8pd";
            r.epsrel = 1e-13;
            r.epsabs = 1e-14;
            const dampsym::ReferenceSolution ref = dampsym::certified_reference(r);
            INFO(P::id << " " << desc << " t0 = " << r.t0 << ": " << ref.error);
            REQUIRE(ref.ok);
            double diff = 0.0, scale = 0.0;
            for (std::size_t k = 0; k < r.times.size(); ++k) {
                const Vec z = exact_at(p, r.t0, r.y0, r.times[k]);
                const auto col = ref.states.col(static_cast<Eigen::Index>(k));
                diff = std::max(diff, (z - col).cwiseAbs().maxCoeff());
                scale = std::max(scale, col.cwiseAbs().maxCoeff());
            }
            const double tol = 10.0 * std::max(ref.error_estimate, 64 * kEpsExact * scale);
            INFO("max |exact - GSL| = " << diff << ", estimate " << ref.error_estimate);
            CHECK(diff <= tol);
        }
    });
}

TEST_CASE("exact solutions: z(t0) = z0 exactly, restarts and time shifts", "[exact]") {
    std::mt19937_64 rng(99);
    for_each_exact_problem([&]<class P>() {
        for (int draw = 0; draw < 6; ++draw) {
            std::string desc;
            const P p = random_problem<P>(rng, desc);
            const Vec z0 = random_state(p, rng, draw == 0);
            const double t0 = uniform(rng, -10, 10);
            const double s = uniform(rng, 0.1, 4.0);
            INFO(P::id << " " << desc << " t0 = " << t0 << " s = " << s);
            CHECK(exact_at(p, t0, z0, t0) == z0);
            CHECK(exact_at(p, 0.0, z0, 0.0) == z0);

            const Vec zs = exact_at(p, t0, z0, t0 + s);
            const double scale =
                std::max(zs.cwiseAbs().maxCoeff(), rhs_at(p, t0 + s, zs).cwiseAbs().maxCoeff());
            // t0 + s and (t0 + s) − t0 are rounded: allow 64 ulp of (1 + |t0| + s) per unit rate.
            const double tol = 64 * kEpsExact * (1.0 + std::abs(t0) + s) * std::max(1.0, scale);

            // Restart: the solution from (t0, z0) through (t1, z(t1)) is the same solution.
            const double t1 = t0 + 0.37 * s;
            const Vec via = exact_at(p, t1, exact_at(p, t0, z0, t1), t0 + s);
            INFO("restart difference " << (via - zs).cwiseAbs().maxCoeff() << ", tol " << tol);
            CHECK((via - zs).cwiseAbs().maxCoeff() <= tol);

            if constexpr (P::autonomous) {
                const Vec from0 = exact_at(p, 0.0, z0, s);
                INFO("shift difference " << (from0 - zs).cwiseAbs().maxCoeff() << ", tol " << tol);
                CHECK((from0 - zs).cwiseAbs().maxCoeff() <= tol);
                // The declaration is true of f: the vector field does not depend on t.
                CHECK(rhs_at(p, t0, z0) == rhs_at(p, t0 + s, z0));
            }
        }
    });
}

TEST_CASE("time in every registered problem: Gamma(0) = 0, Gamma' = gamma, dGamma, forcing "
          "period",
          "[exact]") {
    // Γ' by the central difference above at h = 2⁻⁶ (Γ is a trigonometric polynomial or linear:
    // truncation ≤ h⁶ max|Γ⁽⁷⁾|/140 with |Γ⁽⁷⁾| ≤ 2⁶|ε|/2, round-off (110/60) · 8 ulp/h).
    std::mt19937_64 rng(3);
    for_each_problem([&]<class P>() {
        std::string desc;
        const P p = random_problem<P>(rng, desc);
        INFO(P::id << " " << desc);
        CHECK(p.Gamma(0.0) == 0.0);
        for (int k = 0; k < 8; ++k) {
            const double t = uniform(rng, -20, 20), dt = uniform(rng, -2, 2);
            const double h = std::ldexp(1.0, -6);
            auto G = [&](double s) { return p.Gamma(t + s); };
            const double dG =
                (45.0 * (G(h) - G(-h)) - 9.0 * (G(2 * h) - G(-2 * h)) + (G(3 * h) - G(-3 * h))) /
                (60.0 * h);
            const double mag = std::max({1.0, std::abs(p.Gamma(t)), std::abs(p.gamma_at(t))});
            INFO("t = " << t << " dt = " << dt);
            CHECK_THAT(dG, WithinAbs(p.gamma_at(t), 1e-9 * mag));
            CHECK_THAT(p.dGamma(t, dt), WithinAbs(p.Gamma(t + dt) - p.Gamma(t),
                                                  16 * kEpsExact * (mag + std::abs(t))));
            if (dampsym::detail::declares_constant_gamma<P>())
                CHECK(p.gamma_at(t) == p.gamma_at(0.0));
        }
        if constexpr (dampsym::HasForcingPeriod<P>) {
            // Poincaré sections at t0 + kT need f(t + T, z) = f(t, z) for every t, not only t0 = 0.
            const double T = p.forcing_period();
            for (int k = 0; k < 8; ++k) {
                const double t = uniform(rng, -20, 20);
                const Vec z = random_state(p, rng, false);
                const Vec a = rhs_at(p, t, z), b = rhs_at(p, t + T, z);
                INFO("t = " << t << " T = " << T);
                CHECK((a - b).cwiseAbs().maxCoeff() <= 64 * kEpsExact * (1.0 + std::abs(t)) *
                                                           std::max(1.0, a.cwiseAbs().maxCoeff()));
            }
        }
    });
}

TEST_CASE("dissipation drift d(t) counts Gamma from the start t0", "[exact]") {
    // The same initial state at t0 = 0 and at t0 = 5.3 on the damped oscillator: the maxima are
    // shifted by 5.3 and d(t) = ln q_max + Γ(t) − Γ(t0) is the same (with Γ(t) alone it would
    // move by γ · 5.3 = 0.53); along one run d is constant (each maximum is the previous one a
    // damped period later).
    dampsym::Oscillator p;
    p.omega = 1.3;
    p.gamma = 0.1;
    p.q0 = 0.7;
    p.p0 = 0.4;
    const Vec z0 = p.initial_state();
    auto maxima = [&](double t0) {
        dampsym::MaximaFinder<dampsym::Oscillator> finder(p, t0);
        for (int i = 0; i <= 2000; ++i) {
            const double t = t0 + 0.01 * i;
            finder.feed(t, exact_at(p, t0, z0, t));
        }
        return finder.maxima();
    };
    const auto a = maxima(0.0), b = maxima(5.3);
    REQUIRE(a.size() >= 3);
    REQUIRE(a.size() == b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        CHECK_THAT(b[i].t - 5.3, WithinAbs(a[i].t, 1e-12));
        CHECK_THAT(b[i].d, WithinAbs(a[i].d, 1e-12));
        CHECK_THAT(a[i].d, WithinAbs(a[0].d, 1e-10));
    }
}

TEST_CASE("the output grid of a case starting at t0 != 0", "[exact]") {
    dampsym::CaseSpec c;
    c.t0 = 0.5;
    c.t_end = 3.5;
    c.dts = {0.001};
    c.steps = {3000};
    const std::int64_t points = dampsym::detail::output_points(c);
    const std::vector<double> times = dampsym::detail::reference_times(c, points, true);
    REQUIRE(times.size() == static_cast<std::size_t>(points + 1));
    CHECK(times.front() == 0.5);
    CHECK(times.back() == 3.5);
    for (std::size_t i = 0; i < times.size(); ++i)
        CHECK_THAT(times[i], WithinAbs(0.5 + 0.001 * static_cast<double>(i), 1e-13));
}
