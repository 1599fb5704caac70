// B's own fully discrete schemes for the damped (driven) NLS iψ_t + ψ_xx + V'(|ψ|²)ψ + 2iγψ = F(t)
// (B (4.7), §5.3) as dampsym methods, applicable to the problems on B (1.14)'s central δ_x²
// (`pde_space` NLSSpace::central: schrodinger, nls, nls-driven; src/pde/nls/problem.hpp):
//
//  nls-if   (4.15): i D_t^γψ + A_t^γ δ_x²ψ + V'(|A_t^γψ|²) A_t^γψ = F(A_t t)
//  nls-etd  (5.27): the same with i D_t^γψ multiplied by γΔt / sinh(γΔt)
//  nls-imp  (5.28): i D_tψ + A_t δ_x²ψ + V'(|A_tψ|²) A_tψ + 2iγ A_tψ = F(A_t t)
//
// They are the same maps as cimp, etdrk2 and implicit-midpoint on these problems (docs/pde.md;
// tests/test_attractor.cpp compares them), solved differently: a fixed-point iteration on the
// nonlinear term with the linear operator inverted exactly by FFT (diagonal in Fourier), O(M log M)
// per iteration instead of a dense Newton solve of size 2M. The arithmetic is pde::NLSStepper's
// (src/pde/nls/schemes.cpp); the kernel only adapts it: z = [Re ψ; Im ψ]. A step whose iteration
// does not converge is StepStatus::solve_failed. Counters: one evaluation of N per iteration
// (rhs_evals and newton_iters count the iterations). No step Jacobian (E_n of these maps: cimp,
// etdrk2).
#pragma once

#include "core/method.hpp"
#include "methods/hand_written.hpp"
#include "pde/nls/problem.hpp"
#include "pde/nls/schemes.hpp"

#include <algorithm>
#include <array>
#include <complex>
#include <string_view>

namespace dampsym {

// B's NLS schemes: the method row and the kernel of each, all on the central δ_x² (B (1.14)).
inline constexpr std::array<PdeSchemeRow<pde::NLSScheme, NLSSpace>, 3> nls_schemes{{
    {pde::NLSScheme::integrating_factor, Scheme::nls_if, "nls-if", NLSSpace::central},
    {pde::NLSScheme::etd, Scheme::nls_etd, "nls-etd", NLSSpace::central},
    {pde::NLSScheme::implicit_midpoint, Scheme::nls_imp, "nls-imp", NLSSpace::central},
}};

template <class P, pde::NLSScheme S>
class NlsB : public PdeSchemeKernel<nls_schemes, S> {
public:
    static constexpr bool has_step_jacobian = false;

    NlsB(const P& problem, const MethodInfo&, double h, Counters& counters)
        : stepper_(problem.grid, problem.nls_params(), h, S), c_(counters),
          psi_(static_cast<std::size_t>(problem.grid.M)) {}

    StepStatus step(double t, Vec& z) {
        const int M = static_cast<int>(psi_.size());
        for (int n = 0; n < M; ++n) psi_[n] = {z[n], z[M + n]};
        const bool ok = stepper_.step(t, psi_);
        c_.step_iterated(stepper_.last_iterations(), false);
        if (!ok) return StepStatus::solve_failed;
        for (int n = 0; n < M; ++n) {
            z[n] = psi_[n].real();
            z[M + n] = psi_[n].imag();
        }
        return StepStatus::ok;
    }

private:
    pde::NLSStepper stepper_;
    Counters& c_;
    pde::CVec psi_;
};

template <class P>
using NlsIf = NlsB<P, pde::NLSScheme::integrating_factor>;
template <class P>
using NlsEtd = NlsB<P, pde::NLSScheme::etd>;
template <class P>
using NlsImp = NlsB<P, pde::NLSScheme::implicit_midpoint>;

} // namespace dampsym
