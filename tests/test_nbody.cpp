// The N-body family (src/problems/nbody.hpp, kepler.hpp, outer_solar_system.hpp, argon.hpp):
// analytic force Jacobians against central differences, force = −∇V, Newton's third law, the
// conformal momentum laws Σp(t) = e^{−2γt}Σp(0), L(t) = e^{−2γt}L(0) (B Ex. 1.3) on certified GSL
// solves of the plain form, Kepler's exact solution (HLW(2.1)–(2.9)) against its invariants,
// the ODE and the certified GSL reference, the data of HLW Tables 2.2 and 3.1, and parameter
// validation.
#include "harness/registry.hpp"
#include "problems/argon.hpp"
#include "problems/kepler.hpp"
#include "problems/nbody.hpp"
#include "problems/outer_solar_system.hpp"
#include "reference/gsl_reference.hpp"
#include "reference/kepler_exact.hpp"

#include <catch2/catch.hpp>

#include <quadmath.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using dampsym::Argon;
using dampsym::certified_reference;
using dampsym::Kepler;
using dampsym::Mat;
using dampsym::NBody;
using dampsym::OuterSolarSystem;
using dampsym::ParamMap;
using dampsym::ReferenceRequest;
using dampsym::Vec;

namespace {

constexpr double two_pi = 2.0 * std::numbers::pi;

template <class P>
ParamMap defaults() {
    ParamMap m;
    for (const auto& s : P::param_specs()) {
        if (s.is_array)
            m.arrays[s.name] = s.default_array;
        else
            m.scalars[s.name] = s.default_value;
    }
    return m;
}

// A 2-D Lennard-Jones N-body (potential 1) with unequal masses and a net momentum: four atoms near
// the LJ minimum distance 2^{1/6}σ, σ = 1.1, ε = 0.7.
NBody lj_cluster(double gamma) {
    ParamMap m = defaults<NBody>();
    m["gamma"] = gamma;
    m["potential"] = 1.0;
    m["dim"] = 2.0;
    m["lj_epsilon"] = 0.7;
    m["lj_sigma"] = 1.1;
    m.arrays["masses"] = {1.0, 2.0, 1.5, 0.8};
    m.arrays["q"] = {0.0, 0.0, 1.25, 0.1, 0.6, 1.1, -0.5, 1.2};
    m.arrays["p"] = {0.1, -0.2, 0.3, 0.05, -0.1, 0.25, 0.2, 0.1};
    return NBody::from_params(m);
}

// Max over row blocks i of max_j |J_ij − FD_ij| / max|J_ii|, FD = central differences of the force
// with step h (blocks of d rows; the diagonal block holds every pair acting on body i, so this
// scale is the natural one for row i even where single pairs are tiny, e.g. Pluto–Neptune).
template <class P>
double jacobian_block_error(const P& prob, const Vec& q, double h, int d) {
    const int n = prob.n();
    Mat J(n, n), Jfd(n, n);
    prob.force_jacobian(0.0, q, J);
    Vec fp(n), fm(n);
    for (int j = 0; j < n; ++j) {
        Vec qp = q, qm = q;
        qp[j] += h;
        qm[j] -= h;
        prob.force(0.0, qp, fp);
        prob.force(0.0, qm, fm);
        Jfd.col(j) = (fp - fm) / (2.0 * h);
    }
    double worst = 0.0;
    for (int i = 0; i < n / d; ++i) {
        const double scale = J.block(i * d, i * d, d, d).cwiseAbs().maxCoeff();
        const double err = (J - Jfd).middleRows(i * d, d).cwiseAbs().maxCoeff();
        worst = std::max(worst, err / scale);
    }
    return worst;
}

// ‖F − (−∇V)_FD‖_∞ / ‖F‖_∞ with V = energy at p = 0.
template <class P>
double force_gradient_error(const P& prob, const Vec& q, double h) {
    const int n = prob.n();
    Vec f(n);
    prob.force(0.0, q, f);
    Vec z = Vec::Zero(2 * n);
    Vec fd(n);
    for (int j = 0; j < n; ++j) {
        z.head(n) = q;
        z[j] = q[j] + h;
        const double vp = prob.energy(z);
        z[j] = q[j] - h;
        const double vm = prob.energy(z);
        fd[j] = -(vp - vm) / (2.0 * h);
    }
    return (f - fd).cwiseAbs().maxCoeff() / f.cwiseAbs().maxCoeff();
}

double min_distance(const Vec& q, int d) {
    double r = std::numeric_limits<double>::infinity();
    const auto N = q.size() / d;
    for (Eigen::Index i = 0; i < N; ++i)
        for (Eigen::Index j = i + 1; j < N; ++j)
            r = std::min(r, (q.segment(i * d, d) - q.segment(j * d, d)).norm());
    return r;
}

// Certified GSL solve (conventions §4) of the plain form z' = f(t, z) of a problem.
template <class P>
dampsym::ReferenceSolution solve(const P& prob, const std::vector<double>& times, double epsrel,
                                 double epsabs, const char* stepper = "rk8pd") {
    ReferenceRequest r;
    r.dim = prob.dim();
    r.y0 = prob.initial_state();
    r.times = times;
    r.stepper = stepper;
    r.epsrel = epsrel;
    r.epsabs = epsabs;
    r.rhs = [prob](double t, const double* y, double* dydt) {
        const int dim = prob.dim();
        const Vec z = Eigen::Map<const Vec>(y, dim);
        Vec f(dim);
        prob.rhs(t, z, f);
        Eigen::Map<Vec>(dydt, dim) = f;
    };
    return certified_reference(r);
}

// Largest relative deviation from Σp(t) = e^{−2γt}Σp(0) and L(t) = e^{−2γt}L(0) on a certified
// solve at t = 0, 1, ..., t_end.
template <class P>
std::pair<double, double> momentum_law_deviation(const P& prob, double t_end, double epsrel,
                                                 double epsabs) {
    std::vector<double> times;
    for (int k = 0; k <= static_cast<int>(t_end); ++k) times.push_back(k);
    const auto sol = solve(prob, times, epsrel, epsabs);
    REQUIRE(sol.ok);
    Vec P0, L0, Pt, Lt;
    prob.linear_momentum(prob.initial_state(), P0);
    prob.angular_momentum(prob.initial_state(), L0);
    double dp = 0.0, dl = 0.0;
    for (std::size_t k = 0; k < times.size(); ++k) {
        const Vec z = sol.states.col(static_cast<Eigen::Index>(k));
        prob.linear_momentum(z, Pt);
        prob.angular_momentum(z, Lt);
        const double decay = std::exp(-2.0 * prob.Gamma(times[k]));
        dp = std::max(dp, (Pt - decay * P0).norm() / (decay * P0.norm()));
        dl = std::max(dl, (Lt - decay * L0).norm() / (decay * L0.norm()));
    }
    return {dp, dl};
}

} // namespace

TEST_CASE("nbody: default configuration is 3-D, bound, with every momentum component nonzero",
          "[nbody]") {
    const NBody p = NBody::from_params(defaults<NBody>());
    REQUIRE(p.space_dim() == 3);
    REQUIRE(p.n() == 9);
    REQUIRE(p.dim() == 18);
    REQUIRE(p.gamma == 0.01);
    const Vec z0 = p.initial_state();
    REQUIRE(NBody{}.initial_state() == z0); // default-constructed = default parameters
    Vec P, L;
    p.linear_momentum(z0, P);
    p.angular_momentum(z0, L);
    REQUIRE(P.size() == 3);
    REQUIRE(L.size() == 3);
    CHECK_THAT(P[0], WithinRel(0.029435, 1e-12));
    CHECK_THAT(P[1], WithinRel(-0.018442, 1e-12));
    CHECK_THAT(P[2], WithinRel(0.010948, 1e-12));
    for (int k = 0; k < 3; ++k) CHECK(std::abs(L[k]) > 3e-4);
    CHECK(p.energy(z0) < 0.0);                        // bound
    CHECK(std::abs(p.sys.kinetic(z0.tail(9))) > 0.0); // T as Σ|p|²/(2m)
    CHECK_THAT(p.energy(z0), WithinRel(p.kinetic_energy(z0) + p.potential_energy(z0), 1e-15));
}

TEST_CASE("nbody: analytic force Jacobians match central differences", "[nbody]") {
    SECTION("nbody default (3-D gravity)") {
        const NBody p = NBody::from_params(defaults<NBody>());
        const Vec q = p.initial_state().head(p.n());
        const double e = jacobian_block_error(p, q, 1e-5 * min_distance(q, 3), 3);
        INFO("block-relative error " << e);
        CHECK(e <= 1e-7);
    }
    SECTION("2-D Lennard-Jones cluster") {
        const NBody p = lj_cluster(0.0);
        const Vec q = p.initial_state().head(p.n());
        const double e = jacobian_block_error(p, q, 1e-5 * min_distance(q, 2), 2);
        INFO("block-relative error " << e);
        CHECK(e <= 1e-7);
    }
    SECTION("Kepler") {
        const Kepler p;
        Vec z(4);
        p.exact(0.0, p.initial_state(), 1.3, z);
        const double e = jacobian_block_error(p, Vec(z.head(2)), 1e-5, 2);
        INFO("relative error " << e);
        CHECK(e <= 1e-7);
    }
    SECTION("outer solar system") {
        const OuterSolarSystem p;
        const Vec q = p.initial_state().head(p.n());
        const double e = jacobian_block_error(p, q, 1e-5 * min_distance(q, 3), 3);
        INFO("block-relative error " << e);
        CHECK(e <= 1e-7);
    }
    SECTION("argon") {
        const Argon p;
        const Vec q = p.initial_state().head(p.n());
        const double e = jacobian_block_error(p, q, 1e-5 * min_distance(q, 2), 2);
        INFO("block-relative error " << e);
        CHECK(e <= 1e-7);
    }
}

TEST_CASE("nbody: force = -grad V and Newton's third law", "[nbody]") {
    auto check = [](const auto& p, int d) {
        const Vec q = p.initial_state().head(p.n());
        const double e = force_gradient_error(p, q, 1e-5 * min_distance(q, d));
        INFO("force vs -dV/dq (FD): " << e);
        CHECK(e <= 1e-7);
        Vec f(p.n());
        p.force(0.0, q, f);
        // Σ F_i = 0 and Σ q_i × F_i = 0 to round-off.
        Vec sum = Vec::Zero(d);
        for (int i = 0; i < p.n() / d; ++i) sum += f.segment(i * d, d);
        const double fmax = f.cwiseAbs().maxCoeff();
        INFO("|sum F| / max|F_i| = " << sum.cwiseAbs().maxCoeff() / fmax);
        CHECK(sum.cwiseAbs().maxCoeff() <= 1e-14 * fmax);
        Vec zf(2 * p.n());
        zf << q, f;
        Vec torque;
        p.angular_momentum(zf, torque); // Σ q_i × F_i
        const double qmax = q.cwiseAbs().maxCoeff();
        CHECK(torque.cwiseAbs().maxCoeff() <= 1e-14 * qmax * fmax);
    };
    SECTION("nbody default") {
        check(NBody::from_params(defaults<NBody>()), 3);
    }
    SECTION("Lennard-Jones cluster") {
        check(lj_cluster(0.0), 2);
    }
    SECTION("outer solar system") {
        check(OuterSolarSystem{}, 3);
    }
    SECTION("argon") {
        check(Argon{}, 2);
    }
}

TEST_CASE("nbody: momentum laws of the exact flow, sum p and L decay as exp(-2 gamma t)",
          "[nbody]") {
    // The law fails if the damping had the wrong sign or factor (e^{+2γt}, e^{−γt}).
    SECTION("nbody default, gamma = 0.05, t <= 10") {
        ParamMap m = defaults<NBody>();
        m["gamma"] = 0.05;
        const NBody p = NBody::from_params(m);
        const auto [dp, dl] = momentum_law_deviation(p, 10.0, 1e-12, 1e-14);
        INFO("linear " << dp << ", angular " << dl);
        CHECK(dp <= 1e-10);
        CHECK(dl <= 1e-10);
    }
    SECTION("2-D Lennard-Jones cluster, gamma = 0.2, t <= 5 (L has length 1)") {
        const NBody p = lj_cluster(0.2);
        Vec L;
        p.angular_momentum(p.initial_state(), L);
        REQUIRE(L.size() == 1);
        const auto [dp, dl] = momentum_law_deviation(p, 5.0, 1e-12, 1e-14);
        INFO("linear " << dp << ", angular " << dl);
        CHECK(dp <= 1e-10);
        CHECK(dl <= 1e-10);
    }
    SECTION("the law detects a sign error: with gamma -> -gamma the deviation is O(1)") {
        ParamMap m = defaults<NBody>();
        m["gamma"] = 0.05;
        NBody p = NBody::from_params(m);
        const auto sol = solve(p, {0.0, 5.0}, 1e-10, 1e-12);
        REQUIRE(sol.ok);
        Vec P0, P5;
        p.linear_momentum(p.initial_state(), P0);
        p.linear_momentum(Vec(sol.states.col(1)), P5);
        const double wrong = std::exp(+2.0 * 0.05 * 5.0);
        CHECK((P5 - wrong * P0).norm() / (wrong * P0.norm()) > 0.5);
    }
}

namespace {

// The planar problem's initial state has energy H0 and angular momentum sqrt(1 - e^2), e = 0.6.
void check_kepler_initial_state(const Kepler& k) {
    REQUIRE(k.space_dim() == 2);
    const Vec z0 = k.initial_state();
    CHECK_THAT(k.energy(z0), WithinAbs(Kepler::H0(), 1e-15));
    CHECK_THAT(z0[0] * z0[3] - z0[1] * z0[2], WithinAbs(std::sqrt(1.0 - 0.36), 1e-15));
}

} // namespace

TEST_CASE("kepler: exact solution through Kepler's equation conserves H and L, period 2 pi",
          "[nbody]") {
    const Kepler k;
    check_kepler_initial_state(k);
    Vec z(4), z0 = k.initial_state();

    SECTION("H and L conserved to 1e-14, invariant and hook agree") {
        double dh = 0.0, dl = 0.0;
        std::vector<double> times;
        for (int i = 0; i <= 2000; ++i) times.push_back(0.0137 * i);
        for (double t : {-3.0, 100.0, 1e3 + 0.25, 12345.678, 1e6 + 0.3, 3e7}) times.push_back(t);
        for (double t : times) {
            k.exact(0.0, k.initial_state(), t, z);
            dh = std::max(dh, std::abs(k.energy(z) - Kepler::H0()));
            double inv = 0.0;
            k.invariants(t, z, &inv);
            dl = std::max(dl, std::abs(inv - k.L0()));
            Vec L;
            k.angular_momentum(z, L);
            REQUIRE(L.size() == 1);
            REQUIRE(L[0] == inv);
        }
        INFO("max |H - H0| = " << dh << ", max |L - L0| = " << dl);
        CHECK(dh <= 1e-14);
        CHECK(dl <= 1e-14);
    }
    SECTION("other eccentricities, e up to 0.99: H, L to round-off of the perihelion scale") {
        for (double e : {0.0, 0.3, 0.9, 0.99}) {
            Kepler ke;
            ke.e = e;
            const double scale = 1.0 / (1.0 - e);
            for (int i = 0; i <= 400; ++i) {
                ke.exact(0.0, ke.initial_state(), 0.0311 * i, z);
                CHECK_THAT(ke.energy(z), WithinAbs(-0.5, 1e-14 * scale));
                CHECK_THAT(z[0] * z[3] - z[1] * z[2], WithinAbs(ke.L0(), 1e-14 * scale));
            }
        }
    }
    SECTION("period 2 pi: z(2 pi) = z(0)") {
        k.exact(0.0, k.initial_state(), two_pi, z);
        for (int i = 0; i < 4; ++i) CHECK_THAT(z[i], WithinAbs(z0[i], 1e-14));
        k.exact(0.0, k.initial_state(), 0.0, z);
        for (int i = 0; i < 4; ++i) CHECK(z[i] == z0[i]);
    }
}

TEST_CASE("kepler: Kepler's equation to round-off, the exact solution solves the ODE and agrees "
          "with GSL",
          "[nbody]") {
    const Kepler k;
    check_kepler_initial_state(k);
    Vec z(4);

    SECTION("mean anomaly reduction is exact to ~1 ulp of pi for t >> 2 pi") {
        const __float128 pi_q = acosq(static_cast<__float128>(-1.0));
        const __float128 twopi_q = 2 * pi_q;
        for (double t : {two_pi, 7.0, -7.0, 1e3 + 0.25, 12345.678, 1e6 + 0.3, 3e7, 1e12 + 0.7}) {
            __float128 m = fmodq(static_cast<__float128>(t), twopi_q);
            if (m > pi_q) m -= twopi_q;
            if (m < -pi_q) m += twopi_q;
            const double M = dampsym::kepler_mean_anomaly(t);
            CHECK_THAT(M, WithinAbs(static_cast<double>(m), 1e-15));
        }
    }
    SECTION("Kepler's equation solved to round-off") {
        for (double e : {0.0, 0.6, 0.99, 0.999999})
            for (double M : {1e-12, 1e-6, 0.01, 0.5, 2.0, 3.14159, -1.0}) {
                const double E = dampsym::kepler_eccentric_anomaly(e, M);
                CHECK_THAT(E - e * std::sin(E), WithinAbs(M, 4e-16 * std::max(1.0, std::abs(M))));
            }
    }
    SECTION("the exact solution solves q' = p, p' = -q/|q|^3 (4th-order central differences)") {
        const double h = 0.0001220703125; // 2^-13: t ± h exact for the t below
        Vec a(4), b(4), c(4), d(4), f(4);
        double worst = 0.0;
        for (double t : {0.0, 0.7, 2.9, 3.1416, 5.5, 20.0, 10000.125}) {
            k.exact(0.0, k.initial_state(), t - 2 * h, a);
            k.exact(0.0, k.initial_state(), t - h, b);
            k.exact(0.0, k.initial_state(), t + h, c);
            k.exact(0.0, k.initial_state(), t + 2 * h, d);
            const Vec dzdt = (8.0 * (c - b) - (d - a)) / (12.0 * h);
            k.exact(0.0, k.initial_state(), t, z);
            k.rhs(t, z, f);
            worst = std::max(worst, (dzdt - f).cwiseAbs().maxCoeff());
        }
        INFO("max |dz/dt - f(z)| = " << worst);
        CHECK(worst <= 1e-10);
    }
    SECTION("agrees with the certified GSL reference at t = 20 to 1e-9") {
        const auto sol = solve(k, {20.0}, 1e-13, 1e-14);
        REQUIRE(sol.ok);
        k.exact(0.0, k.initial_state(), 20.0, z);
        const double err = (z - sol.states.col(0)).cwiseAbs().maxCoeff();
        INFO("|exact - GSL| = " << err << ", GSL's own estimate " << sol.error_estimate);
        CHECK(err <= 1e-9);
        CHECK(sol.error_estimate <= 1e-10);
    }
}

TEST_CASE("outer solar system: HLW Table 2.2 data", "[nbody]") {
    const OuterSolarSystem p;
    REQUIRE(p.n() == 18);
    REQUIRE(p.sys.bodies() == 6);
    const Vec z0 = p.initial_state();
    // The Sun at rest at the origin; the planets' distances from the Sun are those of the table
    // and fall in each planet's perihelion–aphelion range [AU] (independent sanity check), and
    // the velocities q' = M⁻¹p are the table's and satisfy vis-viva v² = G m0 (2/r − 1/a) with the
    // planets' semi-major axes a to 2% (checks AU/day units, G and p = m v).
    CHECK(z0.head(3).norm() == 0.0);
    CHECK(z0.segment(18, 3).norm() == 0.0);
    struct Range {
        double rmin, rmax, a;
    };
    const std::array<Range, 5> known{{{4.95, 5.46, 5.203},
                                      {9.04, 10.12, 9.537},
                                      {18.3, 20.1, 19.19},
                                      {29.8, 30.4, 30.07},
                                      {29.6, 49.3, 39.48}}};
    Vec v(18);
    p.grad_T(z0.tail(18), v);
    for (std::size_t i = 0; i < 5; ++i) {
        const auto b = static_cast<Eigen::Index>(3 * (i + 1));
        const auto& tq = OuterSolarSystem::planet_position[i];
        const auto& tv = OuterSolarSystem::planet_velocity[i];
        const double r = z0.segment(b, 3).norm();
        CHECK_THAT(r, WithinRel(std::sqrt(tq[0] * tq[0] + tq[1] * tq[1] + tq[2] * tq[2]), 1e-15));
        CHECK(r >= known[i].rmin);
        CHECK(r <= known[i].rmax);
        for (int k = 0; k < 3; ++k)
            CHECK_THAT(v[b + k], WithinRel(tv[static_cast<std::size_t>(k)], 1e-14));
        const double vv =
            OuterSolarSystem::G_hlw * OuterSolarSystem::sun_mass * (2.0 / r - 1.0 / known[i].a);
        CHECK_THAT(v.segment(b, 3).squaredNorm(), WithinRel(vv, 0.02));
    }
    // H0 per HLW(2.10): negative, and close to virial equilibrium 2T + V ≈ 0 (near-circular
    // orbits).
    const double T = p.kinetic_energy(z0), V = p.potential_energy(z0), H0 = p.energy(z0);
    INFO("H0 = " << H0 << ", T = " << T << ", V = " << V);
    CHECK(H0 < 0.0);
    CHECK(std::abs(2.0 * T + V) < 0.1 * std::abs(V));
    // Independent estimate: the sum of the planets' two-body Kepler energies −G m0 m_i/(2 a_i)
    // (≈ −3.22e−8; planet–planet terms and the Sun's recoil are below 1%).
    double kepler_sum = 0.0;
    for (std::size_t i = 0; i < 5; ++i)
        kepler_sum -= OuterSolarSystem::G_hlw * OuterSolarSystem::sun_mass *
                      OuterSolarSystem::planet_mass[i] / (2.0 * known[i].a);
    INFO("sum of two-body energies " << kepler_sum);
    CHECK_THAT(H0, WithinRel(kepler_sum, 0.01));
    Vec L;
    p.angular_momentum(z0, L);
    CHECK(L.size() == 3);
    CHECK(L[2] > 0.0); // prograde orbits
}

TEST_CASE("argon: HLW Table 3.1, temperature HLW(3.8), Lennard-Jones minimum", "[nbody]") {
    const Argon p;
    REQUIRE(p.space_dim() == 2);
    REQUIRE(p.sys.bodies() == 7);
    const Vec z0 = p.initial_state();
    // HLW I.3: T0 ≈ 22.72 K and H(p0, q0) ≈ −1260.2 k_B [J]; total momentum zero.
    INFO("T0 = " << p.temperature(z0) << " K, H0/k_B = " << p.energy(z0) / Argon::k_B);
    CHECK_THAT(p.temperature(z0), WithinAbs(22.72, 0.005));
    CHECK_THAT(p.energy(z0) / Argon::k_B, WithinAbs(-1260.2, 0.05));
    Vec P;
    p.linear_momentum(z0, P);
    CHECK(P.cwiseAbs().maxCoeff() <= 1e-15 * Argon::mass * 100.0);
    // HLW(3.2): minimum of φ at r = 2^{1/6}σ with φ = −ε; zero pair force there.
    const double rmin = std::pow(2.0, 1.0 / 6.0) * Argon::sigma;
    CHECK_THAT(p.sys.phi(0, 1, rmin), WithinRel(-Argon::epsilon, 1e-14));
    double a = 0.0, b = 0.0;
    p.sys.pair_terms(0, 1, rmin * rmin, a, b);
    CHECK(std::abs(a) <= 1e-14 * Argon::epsilon / (rmin * rmin));
    CHECK(b > 0.0); // φ'' > 0: a minimum
    CHECK(p.sys.phi(0, 1, 0.99 * rmin) > -Argon::epsilon);
    CHECK(p.sys.phi(0, 1, 1.01 * rmin) > -Argon::epsilon);
    // A damped argon crystal loses temperature: the exact flow with γ > 0 (kg, nm, ns units;
    // epsabs scaled to the O(1e−24) momenta) keeps Σp = 0 and shrinks L like e^{−2γt}.
    Argon damped;
    damped.gamma = 5.0; // per ns
    const auto sol = solve(damped, {0.0, 0.02, 0.04}, 1e-11, 1e-36);
    REQUIRE(sol.ok);
    Vec L0, L2;
    damped.angular_momentum(z0, L0);
    damped.angular_momentum(Vec(sol.states.col(2)), L2);
    CHECK_THAT(L2[0], WithinRel(std::exp(-2.0 * 5.0 * 0.04) * L0[0], 1e-9));
    CHECK(damped.temperature(Vec(sol.states.col(2))) < damped.temperature(z0));
}

TEST_CASE("nbody: parameters are validated with std::invalid_argument", "[nbody]") {
    const ParamMap good = defaults<NBody>();
    REQUIRE_NOTHROW(NBody::from_params(good));
    auto with = [&](auto edit) {
        ParamMap m = good;
        edit(m);
        return m;
    };
    CHECK_THROWS_AS(NBody::from_params(with([](ParamMap& m) { m["dim"] = 4.0; })),
                    std::invalid_argument);
    CHECK_THROWS_AS(NBody::from_params(with([](ParamMap& m) { m["dim"] = 2.5; })),
                    std::invalid_argument);
    CHECK_THROWS_AS(NBody::from_params(with([](ParamMap& m) { m["potential"] = 2.0; })),
                    std::invalid_argument);
    CHECK_THROWS_AS(NBody::from_params(with([](ParamMap& m) { m.arrays["q"].pop_back(); })),
                    std::invalid_argument);
    CHECK_THROWS_AS(NBody::from_params(with([](ParamMap& m) { m.arrays["p"].push_back(0.0); })),
                    std::invalid_argument);
    CHECK_THROWS_AS(NBody::from_params(with([](ParamMap& m) { m.arrays["masses"] = {1.0}; })),
                    std::invalid_argument);
    CHECK_THROWS_AS(NBody::from_params(with([](ParamMap& m) { m["dim"] = 2.0; })),
                    std::invalid_argument); // 9 numbers for 3 bodies in 2-D
    CHECK_THROWS_AS(
        NBody::from_params(with([](ParamMap& m) { m.arrays["q"] = {0, 0, 0, 1, 0, 0, 0, 0, 0}; })),
        std::invalid_argument); // bodies 1 and 3 coincide
    try {
        NBody::from_params(with([](ParamMap& m) { m.arrays["q"].pop_back(); }));
    } catch (const std::invalid_argument& e) {
        CHECK(std::string(e.what()) ==
              "nbody: q has 8 entries, expected dim*N = 9 (dim = 3, N = 3 masses)");
    }
    ParamMap k = defaults<Kepler>();
    k["e"] = 1.0;
    CHECK_THROWS_AS(Kepler::from_params(k), std::invalid_argument);
    k["e"] = 0.6;
    CHECK(Kepler::from_params(k).e == 0.6);
    ParamMap o = defaults<OuterSolarSystem>();
    o["gamma"] = 1e-5;
    CHECK(OuterSolarSystem::from_params(o).gamma == 1e-5);
    CHECK(Argon::from_params(defaults<Argon>()).gamma == 0.0);
}

TEST_CASE("nbody: the four problems are registered with the momentum hooks", "[nbody]") {
    for (const char* id : {"nbody", "kepler", "outer-solar-system", "argon"}) {
        const dampsym::ProblemInfo* info = dampsym::find_problem(id);
        REQUIRE(info != nullptr);
        CHECK(info->has_energy);
        CHECK(info->constant_gamma);
        CHECK(info->supports("momentum"));
    }
    CHECK(dampsym::find_problem("kepler")->has_exact);
    CHECK(dampsym::find_problem("kepler")->invariants ==
          std::vector<std::string>{"angular_momentum"});
    CHECK(dampsym::find_problem("nbody")->invariants.empty());
    CHECK(dampsym::find_problem("argon")->supports("temperature"));
    STATIC_REQUIRE(NBody::linear_momentum_law);
    STATIC_REQUIRE_FALSE(Kepler::linear_momentum_law);
}
