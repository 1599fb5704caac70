// Exact solution of Kepler's problem HLW(2.1)–(2.2), q'' = −q/|q|³ in the plane, with HLW's initial
// values (2.9): q(0) = (1 − e, 0), p(0) = (0, √((1+e)/(1−e))), 0 ≤ e < 1. Then H0 = −½, L0 =
// √(1−e²), the orbit is the ellipse (2.7) with semi-major axis 1, φ* = 0 and period 2π (HLW I.2),
// and the implicit equation (2.8) for φ(t) becomes Kepler's equation in the eccentric anomaly E:
//   E − e sin E = M,   M = t (mod 2π)  (the mean anomaly; mean motion 1),
//   q1 = cos E − e,  q2 = √(1−e²) sin E,
//   p1 = −sin E / (1 − e cos E),  p2 = √(1−e²) cos E / (1 − e cos E)   (p = dq/dt, dE/dt = 1/r),
//   r = |q| = 1 − e cos E.
// t is reduced modulo 2π with a two-constant (Cody–Waite) reduction, 2π = C1 + C2 with C1 = fl(2π),
// and a fused multiply-add, so M is correct to about one ulp of π for any t (t ≫ 2π included).
// Kepler's equation is solved by Newton's method from above (monotone convergence: f is increasing
// and convex on [0, π]) to round-off; E − e sin E is formed as (1−e)E + e(E − sin E) with a series
// for E − sin E, and 1 − e cos E, cos E − e through sin²(E/2), so nothing cancels for e near 1.
#pragma once

namespace dampsym {

struct KeplerState {
    double q1, q2, p1, p2;
};

// t reduced to M ∈ [−π, π] with t − M an integer multiple of 2π (to ~1 ulp of π).
double kepler_mean_anomaly(double t);

// Solution E of E − e sin E = M for 0 ≤ e < 1 and any M (M is reduced modulo 2π first; the
// returned E lies in [−π, π]).
double kepler_eccentric_anomaly(double e, double M);

// The state at time t for the initial values HLW(2.9).
KeplerState kepler_exact(double e, double t);

} // namespace dampsym
