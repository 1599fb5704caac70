// Conformal symplecticness of the discrete step map (conventions §5 "conformal-symplectic",
// B(2.42), B(3.2)). For every step n → n+1 the kernel returns Ψ = ∂z_{n+1}/∂z_n, the exact
// derivative of the scheme itself (step_jacobian(): chain rule through explicit stages,
// implicit-function theorem at converged implicit solves; never finite differences, except for a
// C plugin's method without a Jacobian of its own: central differences of its step,
// methods/plugin_kernel.hpp, reported as "jacobian": "central-differences"), and the
// diagnostic measures
//   E_n = ‖Ψᵀ J⁻¹ Ψ − e^{−2ΔΓ_n} J⁻¹‖_F,   ΔΓ_n = Γ(t_{n+1}) − Γ(t_n) = problem.dGamma(t_n, h),
// in the Frobenius norm, and the relative defect E_n / (e^{−2ΔΓ_n} ‖J⁻¹‖_F), ‖J⁻¹‖_F = √d.
// J⁻¹ is the canonical structure for z = [q; p] with z' = J⁻¹∇H: J⁻¹ = [0 I; −I 0] (the defect is
// the same for the opposite sign convention). Each step's defect is that of one step: Ψ is not
// accumulated over steps.
//
// Applicability: only problems in canonical coordinates z = [q; p] have a J. A problem is
// canonical if it declares `static constexpr bool is_canonical` (true), or else if it offers the
// separable Rayleigh form (has_separable). A problem that instead declares a constant Poisson
// structure matrix D (structure_matrix(D), e.g. B's Burgers (5.9), possibly singular) is measured
// against ΨDΨᵀ = e^{−2ΔΓ}D, relative to e^{−2ΔΓ}‖D‖_F (docs/pde.md). Poisson problems such as the
// rigid body (odd dimension, no q/p split) are reported as not applicable; so is a kernel without
// step_jacobian. In both cases nothing is integrated (z is left unchanged, steps_done = 0).
//
// E_n verifies nothing about the step if Ψ is not the step's derivative (a kick's (h/2)F' scaled
// by 1 + 1e-7 in Ψ only is still symplectic), so the pass also checks Ψ against central
// differences of step() at the first step, the middle one and the last (diagnostics/
// jacobian_check.hpp: Richardson-extrapolated, tolerance from the scheme's truncation and
// rounding and, for a step that solves, the Newton solve's stopping test), with a second stepper
// of the method (StepChecker) so that the pass's own steps and numbers are untouched. A plugin
// method whose Ψ is itself central differences of its step is not checked ("not-needed").
#pragma once

#include "core/any_stepper.hpp"
#include "core/integrate.hpp"
#include "core/types.hpp"
#include "diagnostics/jacobian_check.hpp"
#include "diagnostics/series.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace dampsym {

enum class ConformalSymplecticApplicability {
    applicable,
    not_canonical,   // no q/p split, no canonical J (e.g. the rigid body, a Poisson system)
    no_step_jacobian // the kernel does not provide step_jacobian()
};

inline const char* to_string(ConformalSymplecticApplicability a) {
    switch (a) {
    case ConformalSymplecticApplicability::applicable:
        return "applicable";
    case ConformalSymplecticApplicability::not_canonical:
        return "not-applicable: no canonical symplectic structure (Poisson problem)";
    case ConformalSymplecticApplicability::no_step_jacobian:
        return "not-applicable: method has no exact step Jacobian";
    }
    return "?";
}

struct ConformalSymplecticStats {
    ConformalSymplecticApplicability applicability = ConformalSymplecticApplicability::applicable;
    bool applicable() const {
        return applicability == ConformalSymplecticApplicability::applicable;
    }
    // Same meaning as in IntegrateOutcome: a diverged step counts in steps_done (z holds the
    // diverged state), a failed nonlinear solve does not (z is the last good state). A step whose
    // state or defect is not finite is "diverged". Defects are recorded only for good steps.
    RunStatus status = RunStatus::ok;
    std::int64_t steps_done = 0;
    std::int64_t failed_step = 0;    // 1-based index of the step that diverged or failed; 0 if ok
    std::int64_t steps_measured = 0; // steps whose defect is in the statistics
    // Absolute defect E_n (Frobenius norm).
    double max_abs = 0.0, last_abs = 0.0;
    std::int64_t max_abs_step = 0; // 1-based index n+1 of the step n → n+1 with the largest E_n
    // Relative defect E_n / (e^{−2ΔΓ_n} √d), over the steps where it is representable (see
    // relative_defect()); rel_undefined_steps counts the others (their E_n is in max_abs).
    double max_rel = 0.0, last_rel = 0.0;
    std::int64_t max_rel_step = 0;
    std::int64_t rel_undefined_steps = 0;
    static constexpr const char* norm = "frobenius";
    // How Ψ was obtained: "exact" (the kernel's step_jacobian), or for a C plugin's method
    // "plugin-jacobian" / "central-differences" (methods/plugin_kernel.hpp, docs/plugins.md).
    const char* jacobian = "exact";
    // The check of Ψ against central differences of step() (jacobian_check.hpp): how it was done
    // ("central-differences"; "not-run" without a StepChecker; "not-needed: ..." for a Ψ that is
    // itself central differences) and its outcome.
    const char* jacobian_check_mode = "not-run";
    DerivativeCheck jacobian_check;
};

// A second stepper of the pass's method, with its own state and counters, that evaluates step()
// at the perturbed states of the Jacobian check (the pass's stepper is never perturbed).
struct StepChecker {
    AnyStepper& stepper;
    const Counters& counters; // newton_iters tells whether the step solves a nonlinear system
};

// Checks Ψ = ∂z₁/∂z₀ (the pass's step_jacobian at (t, z0)) against central differences of
// checker.stepper.step() at z0 and merges the outcome into `out`. `k`: the step's index (the
// seed of the random directions).
inline void check_step_jacobian(StepChecker& checker, double t, const Vec& z0, const Mat& Psi,
                                std::int64_t k, DerivativeCheck& out) {
    auto g = [&](const Vec& x, Vec& y) {
        y = x;
        return checker.stepper.step(t, y) == StepStatus::ok;
    };
    const std::int64_t iters = checker.counters.newton_iters;
    Vec g0(z0.size());
    if (!g(z0, g0) || !g0.allFinite()) {
        out.skipped += 1;
        return;
    }
    const bool solves = checker.counters.newton_iters > iters;
    out.merge(check_derivative(g, z0, g0, Psi, solves, static_cast<std::uint64_t>(k)));
}

// Whether the problem is in canonical coordinates z = [q; p] (see the header comment).
template <class P>
constexpr bool is_canonical_problem() {
    if constexpr (requires { P::is_canonical; })
        return P::is_canonical;
    else if constexpr (requires { P::has_separable; })
        return P::has_separable;
    else
        return false;
}

// Whether the problem declares a (constant, possibly singular) Poisson structure matrix D,
// z' = D∇H − γ_c z: then the law is ΨDΨᵀ = e^{−2ΔΓ}D (B's Burgers (5.9), docs/pde.md).
template <class P>
constexpr bool has_structure_matrix() {
    return requires(const P& p, Mat& D) {
        p.structure_matrix(D);
    };
}

// Whether E_n is defined for the problem: canonical coordinates, or a structure matrix.
template <class P>
constexpr bool has_conformal_structure() {
    return is_canonical_problem<P>() || has_structure_matrix<P>();
}

// J⁻¹ = [0 I; −I 0] for z = [q; p] of dimension d = 2n.
inline Mat canonical_J_inverse(int d) {
    const int n = d / 2;
    Mat Jinv = Mat::Zero(d, d);
    Jinv.block(0, n, n, n).setIdentity();
    Jinv.block(n, 0, n, n).diagonal().setConstant(-1.0);
    return Jinv;
}

// The relative defect E_n / (e^{−2ΔΓ_n} √d), or NaN (reported as undefined, never as a
// divergence: the step itself is fine) when e^{−2ΔΓ_n} is below the smallest normal double
// (ΔΓ_n > ~354 in one step). There the products that make up ΨᵀJ⁻¹Ψ (of size e^{−2ΔΓ_n}) have
// underflowed in the kernel's own double arithmetic (e.g. csv1's ∂p_{n+1}/∂p_n = e^{−2ΔΓ_n}),
// so no rescaling of Ψ can recover the ratio; E_n itself stays reported.
inline double relative_defect(double c, double e_abs, double jinv_norm) {
    if (c >= std::numeric_limits<double>::min()) return e_abs / (c * jinv_norm);
    return std::numeric_limits<double>::quiet_NaN();
}

// The Jacobian check of a pass (st.jacobian_check_mode): none for a Ψ that is itself central
// differences of the step (a plugin's, st.jacobian), else with `checker` when there is one.
inline StepChecker* jacobian_check_plan(ConformalSymplecticStats& st, StepChecker* checker) {
    if (std::strcmp(st.jacobian, "central-differences") == 0) {
        st.jacobian_check_mode = "not-needed: the step Jacobian is central differences of the "
                                 "step itself";
        return nullptr;
    }
    if (checker) st.jacobian_check_mode = "central-differences";
    return checker;
}

// Integrates n steps of size h from t0 (t_k = t0 + k h, never accumulated) with
// stepper.step_jacobian and measures E_k at every step. z is advanced in place (the final state);
// the z arithmetic is the same as integrate()'s with step(). Never throws on a failed solve or a
// divergence: they are reported in status.
// series (figures): when given, receives (t_{k+1}, E_k rel) of every step up to the
// first whose relative defect is undefined.
// checker (when given): Ψ is also checked against central differences of the step at steps 1,
// n/2 + 1 and n (stats.jacobian_check).
template <class P>
ConformalSymplecticStats conformal_symplectic_defect(AnyStepper& stepper, const P& problem, Vec& z,
                                                     double t0, double h, std::int64_t n,
                                                     MinMaxDecimator* series = nullptr,
                                                     StepChecker* checker = nullptr) {
    ConformalSymplecticStats st;
    if constexpr (!has_conformal_structure<P>()) {
        st.applicability = ConformalSymplecticApplicability::not_canonical;
        return st;
    } else {
        if (!stepper.has_step_jacobian()) {
            st.applicability = ConformalSymplecticApplicability::no_step_jacobian;
            return st;
        }
        st.jacobian = stepper.jacobian_source();
        checker = jacobian_check_plan(st, checker);
        const int d = problem.dim();
        constexpr bool poisson = !is_canonical_problem<P>(); // the structure-matrix law
        Mat Jinv;
        double jinv_norm = 0.0;
        if constexpr (poisson) {
            Jinv.resize(d, d);
            problem.structure_matrix(Jinv); // D
            jinv_norm = Jinv.norm();
        } else {
            Jinv = canonical_J_inverse(d);
            jinv_norm = std::sqrt(static_cast<double>(d)); // ‖J⁻¹‖_F
        }
        Mat Psi(d, d), JPsi(d, d), W(d, d);
        Vec z_before;
        for (std::int64_t k = 0; k < n; ++k) {
            const double tk = time_at(t0, h, k);
            const bool check_here = checker && (k == 0 || k == n / 2 || k == n - 1);
            if (check_here) z_before = z;
            if (stepper.step_jacobian(tk, z, Psi) != StepStatus::ok) {
                st.status = RunStatus::solve_failed;
                st.failed_step = k + 1;
                return st;
            }
            st.steps_done = k + 1;
            const double c = std::exp(-2.0 * problem.dGamma(tk, h));
            if constexpr (poisson) { // ΨDΨᵀ − e^{−2ΔΓ}D
                JPsi.noalias() = Jinv * Psi.transpose();
                W.noalias() = Psi * JPsi;
            } else { // ΨᵀJ⁻¹Ψ − e^{−2ΔΓ}J⁻¹
                JPsi.noalias() = Jinv * Psi;
                W.noalias() = Psi.transpose() * JPsi;
            }
            W -= c * Jinv;
            const double e_abs = W.norm();
            if (state_diverged(z) || !std::isfinite(e_abs)) {
                st.status = RunStatus::diverged;
                st.failed_step = k + 1;
                return st;
            }
            st.steps_measured = k + 1;
            if (check_here) check_step_jacobian(*checker, tk, z_before, Psi, k, st.jacobian_check);
            st.last_abs = e_abs;
            if (e_abs > st.max_abs || st.max_abs_step == 0) {
                st.max_abs = e_abs;
                st.max_abs_step = k + 1;
            }
            const double e_rel = relative_defect(c, e_abs, jinv_norm);
            if (!std::isfinite(e_rel)) {
                ++st.rel_undefined_steps; // e^{−2ΔΓ_n} below the double range
                series = nullptr;
                continue;
            }
            if (series) series->push(time_at(t0, h, k + 1), e_rel);
            st.last_rel = e_rel;
            if (e_rel > st.max_rel || st.max_rel_step == 0) {
                st.max_rel = e_rel;
                st.max_rel_step = k + 1;
            }
        }
        return st;
    }
}

} // namespace dampsym
