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

// The state at time t for the initial values HLW(2.9) at t = 0.
KeplerState kepler_exact(double e, double t);

// The state at time t0 + dt of the orbit through z0 = (q1, q2, p1, p2) at t0, for any z0 on an
// elliptic orbit (H = ½|p|² − 1/|q| < 0 and eccentricity < 1; NaN components otherwise), by
// Lagrange's f and g functions in the eccentric anomaly difference ΔE = E − E0 (mu = 1):
//   a = −1/(2H),  n = a^{−3/2},  r0 = |q0|,  σ0 = q0·p0,  e cos E0 = 1 − r0/a,  e sin E0 = σ0/√a,
//   E − e sin E = M0 + n dt with M0 = E0 − e sin E0 (solved by kepler_eccentric_anomaly),
//   f = 1 − (a/r0)(1 − cos ΔE),   g = √a r0 sin ΔE + a σ0 (1 − cos ΔE),
//   r = r0 + (a − r0)(1 − cos ΔE) + σ0 √a sin ΔE,
//   f' = −√a sin ΔE/(r r0),   g' = 1 − (a/r)(1 − cos ΔE),
//   q = f q0 + g p0,   p = f' q0 + g' p0.
// (g follows from Kepler's equation: n dt − (ΔE − sin ΔE) = (r0/a) sin ΔE + (σ0/√a)(1 − cos ΔE),
// so it needs ΔE only modulo 2π.) 1 − cos ΔE is formed as 2 sin²(ΔE/2). dt = 0 returns z0 exactly.
KeplerState kepler_propagate(const KeplerState& z0, double dt);

} // namespace dampsym
