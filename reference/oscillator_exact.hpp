// Exact solution of the damped oscillator q'' + 2γq' + ω²q = 0 (F(2.5), conventions §2), p = q'.
//
//   q(t) = e^{-γt} [ q0 C(t) + (p0 + γ q0) S(t) ]
//   p(t) = e^{-γt} [ p0 C(t) − (γ p0 + ω² q0) S(t) ]
//
// with β² = ω² − γ² (any sign), C(t) = cos(βt) and S(t) = sin(βt)/β. For β² < 0 these are
// cosh(κt) and sinh(κt)/κ with κ² = −β², and at β = 0 they are 1 and t. C and S are evaluated by
// their power series in x = β²t² when |x| is small, so the formula is continuous through ω = γ with
// no 0/0 and no loss of digits nearby; β² itself is formed as (ω−γ)(ω+γ).
#pragma once

namespace dampsym {

struct OscillatorState {
    double q;
    double p;
};

OscillatorState oscillator_exact(double omega, double gamma, double q0, double p0, double t);

// e^{-γt} C(t) and e^{-γt} S(t) (the "damped" cos and sin/β), overflow-free in the over-damped
// regime where e^{-γt} cosh(κt) is formed as ½(e^{-(γ−κ)t} + e^{-(γ+κ)t}).
struct DampedCS {
    double c;
    double s;
};
DampedCS oscillator_damped_cs(double omega, double gamma, double t);

} // namespace dampsym
