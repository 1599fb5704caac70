// The perturbed rigid body B(1.7) (src/problems/rigid_body.hpp) and its exact solution
// (reference/rigid_body_exact.hpp): against the certified GSL reference, the conformal decay of
// the Casimir and the energy (B(3.10)), y(0) = z0, τ(t), the analytic Jacobian, and the
// harness facts (csv1/csv2 not applicable).
#include "harness/registry.hpp"
#include "problems/rigid_body.hpp"
#include "reference/gsl_reference.hpp"
#include "reference/rigid_body_exact.hpp"

#include <catch2/catch.hpp>

#include <gsl/gsl_sf_bessel.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using dampsym::FreeRigidBody;
using dampsym::RigidBody;
using dampsym::Vec;
using dampsym::Vec3;

namespace {

constexpr double kEpsRigid = std::numeric_limits<double>::epsilon();

RigidBody body(const Vec3& I, const Vec3& z0, double epsilon) {
    RigidBody p;
    p.I1 = I[0];
    p.I2 = I[1];
    p.I3 = I[2];
    p.z1 = z0[0];
    p.z2 = z0[1];
    p.z3 = z0[2];
    p.epsilon = epsilon;
    return p;
}

struct Setup {
    Vec3 I, z0;
    const char* what;
};

// Both sides of the separatrix, other orderings of the moments, the separatrix itself (exactly:
// with I = (6, 3, 2), 1/I3 − 1/I2 = 1/I2 − 1/I1 and |z1| = |z3|), symmetric tops, axes.
const std::vector<Setup> kSetups{
    {{4, 3, 2}, {4, 3, 0}, "BS: I = (4,3,2), omega0 = (1,1,0), rotation about the I1 axis"},
    {{4, 3, 2}, {1, 3, 4}, "rotation about the I3 axis"},
    {{4, 3, 2}, {-0.3, 1.2, -2.5}, "negative components"},
    {{2, 5, 3}, {1, -2, 0.5}, "unsorted moments"},
    {{1, 2, 3}, {0.7, 0.1, -0.2}, "increasing moments"},
    {{4, 3, 2}, {0, 2, 1e-3}, "near the middle axis, m = 1 - 7.5e-7"},
    {{4, 3, 2}, {1e-6, 2, 0}, "near the middle axis, other side, m = 1 - 3.8e-13"},
    {{6, 3, 2}, {-1, -0.5, 1}, "on the separatrix, m = 1"},
    {{3, 3, 2}, {1, 2, 3}, "symmetric top I1 = I2"},
    {{2, 3, 3}, {1, 2, 3}, "symmetric top I2 = I3"},
    {{4, 3, 2}, {0, 2, 0}, "middle axis (unstable equilibrium)"},
    {{4, 3, 2}, {0, 0, 2}, "smallest-moment axis"}};

} // namespace

TEST_CASE("rigid body: exact solution matches the certified GSL reference") {
    // rk8pd at epsrel 1e-14 (certifier rk8pd 1e-15) on t in [0, 50], 501 output times.
    // Measured max |exact − GSL| (max norm), ε = 0 / 0.5: BS default 9.1e-14 / 6.9e-13; worst over
    // the setups 9.1e-12 / 3.0e-12, both on the separatrix (where the flow itself is most
    // sensitive: the certified estimate of the GSL solve there is 8.1e-12 / 9.8e-12).
    for (const double epsilon : {0.0, 0.5}) {
        for (const Setup& s : kSetups) {
            const RigidBody p = body(s.I, s.z0, epsilon);
            dampsym::ReferenceRequest r;
            r.dim = 3;
            r.y0 = p.initial_state();
            for (int i = 0; i <= 500; ++i) r.times.push_back(0.1 * i);
            r.rhs = [p](double t, const double* y, double* f) {
                const Vec z = Eigen::Map<const Vec>(y, 3);
                Vec out(3);
                p.rhs(t, z, out);
                Eigen::Map<Vec>(f, 3) = out;
            };
            r.stepper = "rk8pd";
            r.epsrel = 1e-14;
            r.epsabs = 1e-15;
            const dampsym::ReferenceSolution ref = dampsym::certified_reference(r);
            INFO(s.what << ", epsilon " << epsilon << ": " << ref.error);
            REQUIRE(ref.ok);
            double diff = 0.0;
            Vec z(3);
            for (std::size_t k = 0; k < r.times.size(); ++k) {
                p.exact(0.0, p.initial_state(), r.times[k], z);
                diff = std::max(
                    diff, (z - ref.states.col(static_cast<Eigen::Index>(k))).cwiseAbs().maxCoeff());
            }
            INFO("max difference " << diff << ", reference estimate " << ref.error_estimate);
            CHECK(diff <= 1e-10);
        }
    }
}

TEST_CASE("rigid body: Casimir and energy of the exact solution decay as exp(-2 Gamma)") {
    // Measured worst relative deviation over these setups, ε and times: 1.5e-15 (6.8 ulp).
    for (const double epsilon : {0.0, 0.5, -3.0}) {
        for (const Setup& s : kSetups) {
            const RigidBody p = body(s.I, s.z0, epsilon);
            const Vec z0 = p.initial_state();
            double inv0[2];
            p.invariants(0.0, z0, inv0);
            Vec z(3);
            for (const double t : {0.0, 0.3, 1.0, 2.5, 7.0, 33.3, 100.0, 1234.5}) {
                p.exact(0.0, p.initial_state(), t, z);
                double inv[2];
                p.invariants(t, z, inv);
                const double decay = std::exp(-2.0 * p.Gamma(t));
                INFO(s.what << ", epsilon " << epsilon << ", t " << t);
                CHECK_THAT(inv[0], WithinRel(decay * inv0[0], 16 * kEpsRigid));
                CHECK_THAT(inv[1], WithinRel(decay * inv0[1], 16 * kEpsRigid));
                CHECK(p.energy(z) == inv[1]);
            }
        }
    }
}

TEST_CASE("rigid body: the exact solution starts at z0") {
    for (const Setup& s : kSetups) {
        INFO(s.what);
        const FreeRigidBody free(s.I, s.z0);
        REQUIRE(free.ok());
        const Vec3 y = free.at(0.0);
        const double scale = std::sqrt(s.z0[0] * s.z0[0] + s.z0[1] * s.z0[1] + s.z0[2] * s.z0[2]);
        for (int k = 0; k < 3; ++k) CHECK_THAT(y[k], WithinAbs(s.z0[k], 4 * kEpsRigid * scale));
        for (const double epsilon : {0.0, 0.5}) {
            Vec z(3);
            body(s.I, s.z0, epsilon).exact(0.0, body(s.I, s.z0, epsilon).initial_state(), 0.0, z);
            for (int k = 0; k < 3; ++k) CHECK_THAT(z[k], WithinAbs(s.z0[k], 4 * kEpsRigid * scale));
        }
    }
    CHECK(FreeRigidBody({4, 3, 2}, {4, 3, 0}).kind() == FreeRigidBody::Kind::elliptic);
    CHECK(FreeRigidBody({6, 3, 2}, {1, 0.5, 1}).m() == 1.0);
    CHECK(FreeRigidBody({6, 3, 2}, {1, 0.5, 1}).m1() == 0.0);
    CHECK(FreeRigidBody({3, 3, 2}, {1, 2, 3}).kind() == FreeRigidBody::Kind::symmetric);
    CHECK(FreeRigidBody({4, 3, 2}, {0, 2, 0}).kind() == FreeRigidBody::Kind::constant);
}

TEST_CASE("rigid body: tau(t) is the integral of exp(-Gamma)") {
    CHECK(dampsym::rigid_body_tau(0.0, 12.3) == 12.3);
    for (const double epsilon : {0.5, -2.0, 4.0, 40.0}) {
        INFO("epsilon " << epsilon);
        const double x = 0.25 * epsilon;
        const double period = dampsym::rigid_body_tau(epsilon, M_PI);
        // ∫₀^π e^{−x sin 2s} ds = π I0(x)
        CHECK_THAT(period, WithinRel(M_PI * gsl_sf_bessel_I0(x), 4 * kEpsRigid));
        for (const double t : {0.2, 1.0, 2.9, 10.0, -1.3}) {
            const double tau = dampsym::rigid_body_tau(epsilon, t);
            CHECK_THAT(dampsym::rigid_body_tau(epsilon, t + M_PI),
                       WithinAbs(tau + period, 8 * kEpsRigid * (std::abs(tau) + period)));
            if (std::abs(epsilon) > 4.0) continue; // the difference quotient below is too coarse
            // τ' = e^{−Γ}: 4th-order central difference
            const double d = 1e-3;
            const double deriv = (8.0 * (dampsym::rigid_body_tau(epsilon, t + d) -
                                         dampsym::rigid_body_tau(epsilon, t - d)) -
                                  (dampsym::rigid_body_tau(epsilon, t + 2 * d) -
                                   dampsym::rigid_body_tau(epsilon, t - 2 * d))) /
                                 (12.0 * d);
            CHECK_THAT(deriv, WithinRel(std::exp(-x * std::sin(2.0 * t)), 1e-9));
        }
    }
}

TEST_CASE("rigid body: vector field, Jacobians and Gamma") {
    const RigidBody p = body({4, 3, 2}, {4, 3, 0}, 0.5);
    Vec z(3);
    z << 0.3, -1.1, 0.7;
    // B(1.7): z1' = (1/I3 − 1/I2) z2 z3, z2' = (1/I1 − 1/I3) z3 z1, z3' = (1/I2 − 1/I1) z1 z2.
    Vec n(3);
    p.N(0.0, z, n);
    CHECK_THAT(n[0], WithinAbs((1.0 / 2 - 1.0 / 3) * z[1] * z[2], 1e-15));
    CHECK_THAT(n[1], WithinAbs((1.0 / 4 - 1.0 / 2) * z[2] * z[0], 1e-15));
    CHECK_THAT(n[2], WithinAbs((1.0 / 3 - 1.0 / 4) * z[0] * z[1], 1e-15));
    const double t = 0.4;
    Vec f(3);
    p.rhs(t, z, f);
    for (int k = 0; k < 3; ++k) CHECK_THAT(f[k], WithinAbs(n[k] - p.gamma_at(t) * z[k], 1e-15));

    dampsym::Mat J(3, 3), Jf(3, 3);
    p.N_jacobian(t, z, J);
    p.rhs_jacobian(t, z, Jf);
    const double d = 1e-6;
    for (int k = 0; k < 3; ++k) {
        Vec zp = z, zm = z, np(3), nm(3), fp(3), fm(3);
        zp[k] += d;
        zm[k] -= d;
        p.N(t, zp, np);
        p.N(t, zm, nm);
        p.rhs(t, zp, fp);
        p.rhs(t, zm, fm);
        for (int i = 0; i < 3; ++i) {
            CHECK_THAT(J(i, k), WithinAbs((np[i] - nm[i]) / (2 * d), 1e-9));
            CHECK_THAT(Jf(i, k), WithinAbs((fp[i] - fm[i]) / (2 * d), 1e-9));
        }
    }
    for (const double s : {0.0, 0.7, 3.0, 100.0})
        for (const double h : {1e-3, 0.01, 0.1})
            CHECK_THAT(p.dGamma(s, h), WithinAbs(p.Gamma(s + h) - p.Gamma(s), 1e-15));
}

TEST_CASE("rigid body: registered, conformal form only") {
    const dampsym::ProblemInfo* info = dampsym::find_problem("rigid-body");
    REQUIRE(info != nullptr);
    CHECK(info->has_exact);
    CHECK(info->has_energy);
    CHECK_FALSE(info->constant_gamma);
    CHECK(info->invariants == std::vector<std::string>{"casimir", "energy"});
    CHECK(dampsym::method_applies("cimp", "rigid-body"));
    CHECK(dampsym::method_applies("rk3", "rigid-body"));
    CHECK_FALSE(dampsym::method_applies("csv1", "rigid-body"));
    CHECK_FALSE(dampsym::method_applies("csv2", "rigid-body"));
}
