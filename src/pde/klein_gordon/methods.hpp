// B's MCS box scheme (5.5) for the damped Klein–Gordon equation (B (4.3), §5.1) as the dampsym
// method kg-box, applicable only to the problem whose semi-discretisation it tends to as Δt → 0,
// `klein-gordon-box` (src/pde/klein_gordon/problem.hpp), so that its error against that problem's
// exact solution is its time error alone (as burgers-box on burgers-box, docs/pde.md).
//
// The arithmetic is pde::KGBox's (src/pde/klein_gordon/schemes.cpp, B's u-form, unit-tested
// against the scheme's own exact discrete plane wave); the kernel only adapts it.
//
// Two levels. (5.5) steps (u^i, u^{i+1}), while the problem's state is z = (u, v). The kernel holds
// the levels internally, the convention of the general linear kernel (methods/general_linear.hpp):
// on its first call (a kernel is constructed fresh for every run) it starts from z = (u0, v0) with
// KGBox::start (u^1 from the scheme's own equation at i = 0); on later calls the incoming z's u is
// used as u^{i+1} together with the stored u^i, so a caller that passes back what it got continues
// (5.5) exactly. It returns z = (u^{i+1}, v^{i+1}) with v^{i+1} a second-order estimate of u_t at
// t_{i+1}, so that the error of the whole state is of order 2 like that of u. In y = e^{γt}u
// (where (5.5) is the undamped box scheme and u_t = e^{−γt}y' − γu), with E = e^{γΔt}:
//   first step  (trapezoidal rule y^1 − y^0 = (Δt/2)(y'^0 + y'^1) + O(Δt³), y'^0 = v0 + γu0):
//       v^1 = E⁻¹[2(E u^1 − u^0)/Δt − (v0 + γu0)] − γu^1,
//   later steps (one-sided second-order difference over three levels, written at t_{i+1}):
//       v^{i+1} = (3u^{i+1} − 4E⁻¹u^i + E⁻²u^{i−1})/(2Δt) − γu^{i+1}.
// Both are O(Δt²): the levels carry a global error Δt²g(t) + O(Δt³) that is smooth in t ((5.5) is
// a two-level scheme for a second-order equation: both roots of its recurrence are physical, no
// parasitic one), whose difference quotient is O(Δt²) again. v is an output only: (5.5) itself
// never reads it after the start.
//
// No step Jacobian: the step map acts on two levels, so ∂z_{i+1}/∂z_i alone is not the derivative
// of the scheme (as for glm4). The momentum P^i of §5.1.2 is a function of (u^i, u^{i+1}), not of
// z; the problem's momentum I = Δx Σ v δ_x u of z is not kept exactly (v is an estimate).
// Counters: one cyclic tridiagonal solve per step (the start's included), counted as 1 rhs
// evaluation.
#pragma once

#include "core/method.hpp"
#include "methods/hand_written.hpp"
#include "pde/klein_gordon/problem.hpp"
#include "pde/klein_gordon/schemes.hpp"

#include <array>
#include <cmath>
#include <string_view>

namespace dampsym {

// B's Klein–Gordon scheme: the box scheme, on the box semi-discretisation.
inline constexpr std::array<PdeSchemeRow<Scheme, KGSpace>, 1> kg_schemes{{
    {Scheme::kg_box, Scheme::kg_box, "kg-box", KGSpace::box},
}};

template <class P>
class KGBoxScheme : public PdeSchemeKernel<kg_schemes, Scheme::kg_box> {
public:
    static constexpr bool has_step_jacobian = false;

    KGBoxScheme(const P& problem, const MethodInfo&, double h, Counters& counters)
        : box_(problem.grid, problem.c, problem.gamma, h), c_(counters), M_(problem.grid.M),
          gamma_(problem.gamma), h_(h), ie_(std::exp(-problem.gamma * h)), ui_(M_), uim_(M_),
          in_(M_) {}

    StepStatus step(double, Vec& z) {
        const int M = M_;
        if (!started_) {
            ui_ = z.head(M); // u^0
            in_ = z.tail(M); // v0
            box_.start(ui_, in_);
            const Vec& u1 = box_.u_curr();
            for (int n = 0; n < M; ++n)
                z[M + n] = ie_ * (2.0 * (u1[n] / ie_ - ui_[n]) / h_ - (in_[n] + gamma_ * ui_[n])) -
                           gamma_ * u1[n];
            z.head(M) = u1;
            started_ = true;
        } else {
            in_ = z.head(M); // u^{i+1}
            box_.set_state(ui_, in_);
            box_.step();
            uim_.swap(ui_); // u^i
            ui_ = in_;      // u^{i+1}
            const Vec& u2 = box_.u_curr();
            for (int n = 0; n < M; ++n)
                z[M + n] = (3.0 * u2[n] - 4.0 * ie_ * ui_[n] + ie_ * ie_ * uim_[n]) / (2.0 * h_) -
                           gamma_ * u2[n];
            z.head(M) = u2;
        }
        c_.rhs_evals += 1;
        return StepStatus::ok;
    }

private:
    pde::KGBox box_;
    Counters& c_;
    int M_;
    double gamma_, h_, ie_; // ie_ = E⁻¹ = e^{−γΔt}
    Vec ui_, uim_, in_;     // u^i (after a step: the level before the returned one), u^{i−1}
    bool started_ = false;
};

} // namespace dampsym
