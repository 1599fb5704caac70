// Exact step Jacobians (step_jacobian of cimp, csv1, csv2 and the explicit RK kernel) and the
// conformal-symplecticness defect E_n = ‖ΨᵀJ⁻¹Ψ − e^{−2ΔΓ}J⁻¹‖_F (conventions §5, B(2.42), B(3.2)).
//  - step_jacobian advances z bitwise like step();
//  - Ψ agrees with central differences of the step map (the differences live only here: the
//    diagnostic never uses them);
//  - E_n/(e^{−2ΔΓ}‖J⁻¹‖) ≤ 1e−13 at every one of 1000 steps for the conformal methods and ≥ 1e−8
//    for the explicit RK negative controls, on the damped oscillator, pendulum, driven pendulum
//    and Hill's equation (time-dependent γ);
//  - det Ψ = e^{−2γh} on the oscillator for the conformal methods;
//  - not applicable (rigid body), diverged and failed-solve outcomes are reported, not thrown.
// Steppers come compiled from the library (kernel_ops, harness/run/kernel_ops.hpp), as the
// runner's. Set DAMPSYM_TEST_VERBOSE=1 to print the measured numbers.
#include "diagnostics/conformal_symplectic.hpp"
#include "harness/problem_list.hpp"

#include "support/helpers.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using dampsym::ConformalSymplecticApplicability;
using dampsym::Counters;
using dampsym::Mat;
using dampsym::MethodInfo;
using dampsym::RunStatus;
using dampsym::StepStatus;
using dampsym::Vec;

namespace {

constexpr double h = 0.1;
constexpr std::int64_t n_steps = 1000;
const std::vector<std::string> method_ids{"cimp", "csv1", "csv2", "rk3", "heun", "rk4"};

using dampsym::test::method;
using dampsym::test::stepper;
using dampsym::test::verbose;

bool conformal_method(const std::string& id) {
    return id == "cimp" || id == "csv1" || id == "csv2";
}

// Central differences of one step of `stepper` at (t, z), column by column; the step in z_j is
// rel_delta·max(1, |z_j|) and the quotient uses the difference actually represented.
Mat central_difference_jacobian(dampsym::AnyStepper& stepper, double t, const Vec& z,
                                double rel_delta = 1e-5) {
    const Eigen::Index d = z.size();
    Mat D(d, d);
    for (Eigen::Index j = 0; j < d; ++j) {
        const double delta = rel_delta * std::max(1.0, std::abs(z[j]));
        Vec zp = z, zm = z;
        zp[j] += delta;
        zm[j] -= delta;
        const double width = zp[j] - zm[j];
        if (stepper.step(t, zp) != StepStatus::ok || stepper.step(t, zm) != StepStatus::ok)
            D.col(j).setConstant(std::numeric_limits<double>::quiet_NaN());
        else
            D.col(j) = (zp - zm) / width;
    }
    return D;
}

// Measured numbers over all the cases, printed at the end when verbose.
double worst_fd_difference = 0.0;
std::string worst_fd_case;

template <class P>
void check_problem(const P& prob, const char* label, bool oscillator_gamma_known = false,
                   double oscillator_gamma = 0.0) {
    for (const std::string& id : method_ids) {
        const MethodInfo& info = method(id);
        // Every method applies to these separable problems (csv2 with time-dependent γ freezes γ
        // at its mean over each step, src/methods/csv2.hpp).
        {
            const bool conformal = conformal_method(id);
            const int d = prob.dim();

            // 1. step_jacobian moves z exactly like step(), and Ψ matches central differences
            //    (every 50 steps) and, on the oscillator, has det Ψ = e^{−2γh} (every step).
            Counters c1, c2, c3;
            const auto plain = stepper(prob, info, h, c1), with_jac = stepper(prob, info, h, c2),
                       fd = stepper(prob, info, h, c3);
            REQUIRE(with_jac->has_step_jacobian());
            Vec z1 = prob.initial_state(), z2 = prob.initial_state();
            Mat Psi(d, d);
            std::int64_t mismatches = 0, failures = 0;
            double fd_diff = 0.0, det_diff = 0.0;
            for (std::int64_t k = 0; k < n_steps; ++k) {
                const double t = dampsym::time_at(0.0, h, k);
                Mat D;
                if (k % 50 == 0) D = central_difference_jacobian(*fd, t, z2);
                if (plain->step(t, z1) != StepStatus::ok) ++failures;
                if (with_jac->step_jacobian(t, z2, Psi) != StepStatus::ok) ++failures;
                if (!(z1.array() == z2.array()).all()) ++mismatches;
                if (k % 50 == 0) fd_diff = std::max(fd_diff, (Psi - D).cwiseAbs().maxCoeff());
                if (oscillator_gamma_known && conformal)
                    det_diff = std::max(det_diff, std::abs(Psi.determinant() -
                                                           std::exp(-2.0 * oscillator_gamma * h)));
            }
            INFO(label << " / " << id);
            REQUIRE(failures == 0);
            CHECK(mismatches == 0);
            CHECK(fd_diff <= 1e-7);
            if (fd_diff > worst_fd_difference) {
                worst_fd_difference = fd_diff;
                worst_fd_case = std::string(label) + "/" + id;
            }
            if (oscillator_gamma_known && conformal) CHECK(det_diff <= 1e-13);

            // 2. The diagnostic: conformal methods at round-off, RK negative controls clearly not.
            Counters c4;
            const auto pass = stepper(prob, info, h, c4);
            Vec z = prob.initial_state();
            const auto st = dampsym::conformal_symplectic_defect(*pass, prob, z, 0.0, h, n_steps);
            CHECK(st.applicable());
            CHECK(st.status == RunStatus::ok);
            CHECK(st.steps_done == n_steps);
            CHECK(st.steps_measured == n_steps);
            CHECK(st.failed_step == 0);
            CHECK((z.array() == z1.array()).all()); // same final state as step()
            if (conformal)
                CHECK(st.max_rel <= 1e-13);
            else
                CHECK(st.max_rel >= 1e-8);
            if (verbose()) {
                std::printf("[jacobian] %-16s %-5s max E_rel %.3e (step %lld)  max E_abs %.3e  "
                            "|Psi-FD| %.3e",
                            label, id.c_str(), st.max_rel, static_cast<long long>(st.max_rel_step),
                            st.max_abs, fd_diff);
                if (oscillator_gamma_known && conformal)
                    std::printf("  |det Psi - e^-2gh| %.3e", det_diff);
                std::printf("\n");
            }
        }
    }
}

} // namespace

TEST_CASE("step Jacobians and conformal-symplectic defect: damped oscillator", "[jacobian]") {
    dampsym::Oscillator p;
    p.omega = 1.0;
    p.gamma = 0.1;
    p.q0 = 1.0;
    p.p0 = 0.0;
    check_problem(p, "oscillator", true, p.gamma);
}

TEST_CASE("step Jacobians and conformal-symplectic defect: damped pendulum", "[jacobian]") {
    dampsym::Pendulum p;
    p.gamma = 0.1;
    p.q0 = 2.0;
    p.p0 = 0.5;
    check_problem(p, "pendulum");
}

TEST_CASE("step Jacobians and conformal-symplectic defect: driven pendulum", "[jacobian]") {
    dampsym::DrivenPendulum p; // γ = 0.1, λ = 1, f = 1
    p.q0 = 0.5;
    p.p0 = 0.0;
    check_problem(p, "driven-pendulum");
}

TEST_CASE("step Jacobians and conformal-symplectic defect: Hill, time-dependent damping",
          "[jacobian]") {
    dampsym::Hill p;
    p.epsilon = 0.4; // γ(t) = 0.2 cos 2t
    p.kappa = 1.0;
    p.q0 = 1.0;
    p.p0 = 0.0;
    check_problem(p, "hill");
    if (verbose())
        std::printf("[jacobian] worst |Psi - central differences| = %.3e (%s)\n",
                    worst_fd_difference, worst_fd_case.c_str());
}

TEST_CASE("conformal-symplectic defect: rigid body is not applicable", "[jacobian]") {
    const dampsym::RigidBody body;
    const MethodInfo& info = method("cimp");
    Counters c;
    const auto pass = stepper(body, info, h, c);
    Vec z = body.initial_state();
    const Vec z0 = z;
    const auto st = dampsym::conformal_symplectic_defect(*pass, body, z, 0.0, h, 10);
    CHECK_FALSE(st.applicable());
    CHECK(st.applicability == ConformalSymplecticApplicability::not_canonical);
    CHECK(st.steps_done == 0);
    CHECK((z.array() == z0.array()).all());
}

TEST_CASE("conformal-symplectic defect: divergence and failed solves are reported", "[jacobian]") {
    SECTION("csv2 at γh = 2 divides by 1 − γh/2 = 0: diverged at step 1") {
        dampsym::Oscillator p;
        p.gamma = 1.0;
        const MethodInfo& info = method("csv2");
        Counters c;
        const auto pass = stepper(p, info, 2.0, c);
        Vec z = p.initial_state();
        const auto st = dampsym::conformal_symplectic_defect(*pass, p, z, 0.0, 2.0, 5);
        CHECK(st.applicable());
        CHECK(st.status == RunStatus::diverged);
        CHECK(st.failed_step == 1);
        CHECK(st.steps_done == 1);
        CHECK(st.steps_measured == 0);
    }
    SECTION("cimp whose Newton solve fails: solve_failed, z is the last good state") {
        // ω = NaN: N and its Jacobian are NaN everywhere, so no Newton iterate converges (the
        // library's cimp kernel on the oscillator, as a case would run it)
        dampsym::Oscillator p;
        p.gamma = 0.1;
        p.omega = std::numeric_limits<double>::quiet_NaN();
        Counters c;
        const auto pass = stepper(p, method("cimp"), h, c);
        Vec z{{1.0, 0.0}};
        const auto st = dampsym::conformal_symplectic_defect(*pass, p, z, 0.0, h, 5);
        CHECK(st.applicable());
        CHECK(st.status == RunStatus::solve_failed);
        CHECK(st.failed_step == 1);
        CHECK(st.steps_done == 0);
        CHECK(z[0] == 1.0);
        CHECK(z[1] == 0.0);
    }
}

TEST_CASE("canonical J⁻¹ and the defect of an exactly conformal map", "[jacobian]") {
    // Ψ = e^{−γh} R(θ) for the flow of a damped rotation: ΨᵀJ⁻¹Ψ = e^{−2γh}J⁻¹ exactly in exact
    // arithmetic, and a matrix with det ≠ e^{−2γh} has defect |det Ψ − e^{−2γh}|·‖J⁻¹‖_F.
    const Mat Jinv = dampsym::canonical_J_inverse(4);
    CHECK(Jinv(0, 2) == 1.0);
    CHECK(Jinv(2, 0) == -1.0);
    CHECK((Jinv * Jinv + Mat::Identity(4, 4)).cwiseAbs().maxCoeff() == 0.0);
    const Mat J2 = dampsym::canonical_J_inverse(2);
    Mat Psi(2, 2);
    Psi << 2.0, 0.0, 0.0, 1.0; // det 2
    const Mat W = Psi.transpose() * J2 * Psi - 0.5 * J2;
    CHECK_THAT(W.norm(), WithinRel(1.5 * std::sqrt(2.0), 1e-15));
    CHECK_THAT(W(0, 0), WithinAbs(0.0, 0.0));
}

TEST_CASE("conformal-symplectic defect: one-step damping beyond the double range of e^{-2ΔΓ}",
          "[jacobian]") {
    // ΔΓ = γh = 500 per step: e^{−2ΔΓ} = e^{−1000} underflows to 0 and so do the products that
    // make up ΨᵀJ⁻¹Ψ; the relative defect is undefined at every step, the run is not diverged
    // and the absolute defect is still measured. At ΔΓ = 300 (e^{−600} is a normal double) the
    // conformal methods are at round-off on the relative scale.
    for (const char* id : {"cimp", "csv1"}) {
        for (const double gamma : {300.0, 1000.0}) {
            dampsym::Oscillator p;
            p.gamma = gamma;
            const double hh = 1.0;
            const MethodInfo& info = method(id);
            Counters c;
            const auto pass = stepper(p, info, hh, c);
            Vec z = p.initial_state();
            const auto st = dampsym::conformal_symplectic_defect(*pass, p, z, 0.0, hh, 3);
            INFO(id << " gamma h = " << gamma * hh);
            CHECK(st.status == RunStatus::ok);
            CHECK(st.steps_measured == 3);
            CHECK(std::isfinite(st.max_abs));
            if (gamma * hh < 354.0) {
                CHECK(st.rel_undefined_steps == 0);
                CHECK(st.max_rel_step > 0);
                CHECK(st.max_rel <= 1e-13);
            } else {
                CHECK(st.rel_undefined_steps == 3);
                CHECK(st.max_rel_step == 0);
            }
            if (verbose())
                std::printf("[jacobian] gamma h = %g %-5s max E_rel %.3e, %lld undefined\n",
                            gamma * hh, id, st.max_rel,
                            static_cast<long long>(st.rel_undefined_steps));
        }
    }
    CHECK(std::isnan(dampsym::relative_defect(0.0, 1e-300, 1.0)));
    CHECK(dampsym::relative_defect(0.5, 1e-16, 2.0) == 1e-16);
}
