// B's own fully discrete schemes for the modified Burgers equation u_t + u u_x = −2γu (B (4.5),
// §5.2) as dampsym methods, each applicable only to the Burgers problem whose semi-discretisation
// it tends to as Δt → 0 (src/pde/burgers/problem.hpp), so that its time error is measured against
// a reference of its own semi-discrete system:
//
//  burgers-csv  (5.10) on `burgers` (central (5.9), even M): the conformal splitting on the
//  even–odd
//               split, w^{i+½} = e^{−γΔt}w^i − (Δt/2)∂⁻(v²)/2…, B's "CSV2" (docs/pde.md item 3:
//               the (2.20)-type Strang splitting, damping on both halves). Explicit.
//  burgers-box  (5.12) on `burgers-box` (odd M): D_t^γ A_x u + ½ D_x (A_t^γ u)² = 0, Newton with
//               the cyclic bidiagonal Jacobian (O(M)).
//  burgers-nsfd (4.18) on `burgers-upwind`: (u^{i+1} − u^i)/φ + u^i δ⁻u^{i+1} = −2γu^i,
//               φ = (1 − e^{−2γΔt})/(2γ); one cyclic bidiagonal solve. First order; does not keep
//               the Casimir law (B Theorem 5.2's negative control).
//
// The arithmetic is pde::BurgersStepper's (src/pde/burgers/schemes.cpp, which quotes the equations
// and is unit-tested against them); the kernel only adapts it. A failed step (box Newton singular
// or not converged, NSFD singular) is StepStatus::solve_failed. Time does not enter the schemes
// (autonomous, constant γ). Counters: burgers-csv evaluates the flux in three half-grid sweeps (1.5
// evaluations of N; counted as 2 rhs evaluations, the count of the Störmer–Verlet-type schemes),
// burgers-box one residual and one Jacobian per Newton iteration, burgers-nsfd one (linear) solve,
// counted as 1.
#pragma once

#include "core/method.hpp"
#include "methods/hand_written.hpp"
#include "pde/burgers/problem.hpp"
#include "pde/burgers/schemes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string_view>

namespace dampsym {

// B's Burgers schemes: the method row, the kernel and the semi-discretisation each is written on.
inline constexpr std::array<PdeSchemeRow<pde::BurgersScheme, BurgersSpace>, 3> burgers_schemes{{
    {pde::BurgersScheme::csv_split, Scheme::burgers_csv, "burgers-csv", BurgersSpace::central},
    {pde::BurgersScheme::box, Scheme::burgers_box, "burgers-box", BurgersSpace::box},
    {pde::BurgersScheme::nsfd, Scheme::burgers_nsfd, "burgers-nsfd", BurgersSpace::upwind},
}};

template <class P, pde::BurgersScheme S>
class BurgersB : public PdeSchemeKernel<burgers_schemes, S> {
public:
    // (5.10)'s exact step Jacobian (E_n against B's D, docs/pde.md); the implicit schemes have
    // none.
    static constexpr bool has_step_jacobian = S == pde::BurgersScheme::csv_split;

    BurgersB(const P& problem, const MethodInfo&, double h, Counters& counters)
        : stepper_(problem.grid, problem.gamma, h, S), c_(counters), grid_(problem.grid),
          gamma_(problem.gamma), h_(h), u_(problem.grid.M) {}

    StepStatus step(double, Vec& z) {
        const int before = stepper_.stats().newton_iterations;
        const bool ok = stepper_.step(z);
        if constexpr (S == pde::BurgersScheme::box) {
            c_.step_iterated(stepper_.stats().newton_iterations - before, true);
        } else {
            c_.rhs_evals += S == pde::BurgersScheme::csv_split ? 2 : 1;
        }
        return ok ? StepStatus::ok : StepStatus::solve_failed;
    }

    // (5.10): Ψ by the chain rule through its three sweeps. Each sweep changes one parity class
    // of u, u_j ← a u_j − b (u_{j+1}² − u_{j−1}²)/(4Δx) with (a, b) = (e, h/2), (e², e h),
    // (e, e h/2), e = e^{−γh}, from neighbours of the other class that it leaves unchanged, so
    // its Jacobian is the identity but for rows j: a at j, ∓b u_{j±1}/(2Δx) at j ± 1. z itself
    // is advanced by step() (the same arithmetic as without a Jacobian).
    StepStatus step_jacobian(double t, Vec& z,
                             Mat& Psi) requires(S == pde::BurgersScheme::csv_split) {
        const pde::PeriodicGrid& g = grid_;
        const int M = g.M;
        if (M % 2 != 0) return step(t, z);
        const double e = std::exp(-gamma_ * h_), s = 0.25 / g.dx;
        u_ = z;
        Psi = Mat::Identity(M, M);
        auto sweep = [&](int first, double a, double b) {
            for (int j = first; j < M; j += 2) {
                const int r = g.wrap(j + 1), l = g.wrap(j - 1);
                Psi.row(j) = a * Psi.row(j) - (2.0 * b * s * u_[r]) * Psi.row(r) +
                             (2.0 * b * s * u_[l]) * Psi.row(l);
                u_[j] = a * u_[j] - b * (u_[r] * u_[r] - u_[l] * u_[l]) * s;
            }
        };
        sweep(1, e, 0.5 * h_);
        sweep(0, e * e, e * h_);
        sweep(1, e, 0.5 * e * h_);
        return step(t, z);
    }

private:
    pde::BurgersStepper stepper_;
    Counters& c_;
    pde::PeriodicGrid grid_;
    double gamma_, h_;
    Vec u_; // the sweeps' states for the Jacobian
};

template <class P>
using BurgersCsv = BurgersB<P, pde::BurgersScheme::csv_split>;
template <class P>
using BurgersBoxScheme = BurgersB<P, pde::BurgersScheme::box>;
template <class P>
using BurgersNsfd = BurgersB<P, pde::BurgersScheme::nsfd>;

} // namespace dampsym
