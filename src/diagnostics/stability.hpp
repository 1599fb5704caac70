// Linear stability on the oscillator (conventions §5 "stability", F ch.3). The one-step matrix M of
// a method is obtained by stepping the unit vectors (the step map is linear on a linear problem),
// so it is the method's own M, not a formula. F calls a method "stable" when |½ tr M| < e^{−γh}
// (both eigenvalues on the circle of radius e^{−γh}); power-boundedness (spectral radius ≤ 1, with
// a defective eigenvalue on the unit circle counted as unbounded) is reported beside it.
#pragma once

#include "core/any_stepper.hpp"
#include "core/method.hpp"
#include "core/types.hpp"

#include <complex>
#include <limits>
#include <memory>
#include <string_view>

namespace dampsym {

struct OneStepAnalysis {
    double det = 0.0, half_trace = 0.0;
    std::complex<double> eig[2];
    double spectral_radius = 0.0;
    bool finite = true;
    bool F_condition = false;   // |½ tr M| < e^{−γh}
    bool power_bounded = false; // ρ(M) ≤ 1 (and not defective on |λ| = 1)
};

OneStepAnalysis analyse_one_step(const Mat& M, double gamma, double h);

// Closed forms of F ch. 3 for the one-step matrix M of a method on the oscillator, when known
// (problem-specific data of this diagnostic, not of the method rows).
struct OscillatorFormulas {
    // ½ tr M as a function of (ω, γ, h): F(3.10), (3.15), (3.20).
    double (*half_trace)(double omega, double gamma, double h) = nullptr;
    // F's "stability" condition |½ tr M| < e^{-γh} in closed form: F(3.12), (3.17), (3.22).
    bool (*F_condition)(double omega, double gamma, double h) = nullptr;
    // Leading coefficient c of ½tr M − e^{-γh}cos(βh) = c h⁴ + O(h⁵), up to sign (conventions §5
    // gives them up to sign; F's (3.13), (3.18), (3.23) are typos). Checks compare magnitudes.
    double (*h4_coefficient)(double omega, double gamma) = nullptr;
    const char* source = "";
};

// The closed forms of the method with this id: cimp F(3.10), (3.12); csv1 and csv1-perk (the same
// scheme, B(2.20)) F(3.15), (3.17); csv2 and csv2-perk (B(2.21)) F(3.20), (3.22). Empty (null
// functions) for every other method.
OscillatorFormulas oscillator_formulas(std::string_view method_id);

// Stability function of an RK method, R(z) = 1 + z bᵀ(I − zA)⁻¹1 (explicit or implicit tableau).
std::complex<double> rk_stability_function(const ButcherTableau& t, std::complex<double> z);

// Power-boundedness of an RK method on the oscillator q'' + 2γq' + ω²q = 0 from its stability
// function alone: on a linear problem M = R(hA), A = [[0, 1], [−ω², −2γ]], so the eigenvalues of M
// are R(hλ±), λ± = −γ ± sqrt(γ² − ω²). Same rule and tolerance as analyse_one_step (ρ ≤ 1, and a
// double eigenvalue on |λ| = 1 counts as unbounded). An analytic counterpart of the measured
// power_bounded, computed without stepping the kernel (the stress suite's absolute-stability maps).
struct RKPowerAnalysis {
    double spectral_radius = 0.0;
    bool power_bounded = false;
};
RKPowerAnalysis rk_power_analysis(const ButcherTableau& t, double omega, double gamma, double h);

// Steps each unit vector once from t = 0 with a fresh stepper of the method's kernel (`make`).
template <class P>
Mat one_step_matrix(const P& problem, const MethodInfo& info, double h,
                    const StepperMaker<P>& make) {
    const int d = problem.dim();
    Mat M(d, d);
    Counters scratch;
    for (int i = 0; i < d; ++i) {
        const std::unique_ptr<AnyStepper> stepper = make(problem, info, h, scratch);
        Vec z = Vec::Unit(d, i);
        if (stepper->step(0.0, z) != StepStatus::ok)
            z.setConstant(std::numeric_limits<double>::quiet_NaN());
        M.col(i) = z;
    }
    return M;
}

} // namespace dampsym
