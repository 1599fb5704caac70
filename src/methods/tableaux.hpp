// Runge–Kutta coefficient data that is generated rather than typed (DESIGN "Habits": coefficients
// as exact fractions or generated in high precision, never retyped decimals), plus the few small
// tableaux the implicit and partitioned families need. Every function returns a reference to
// static storage, so a MethodInfo row can point at it.
//
// Gauss–Legendre, s stages (HLW II.1, BS; the underlying method of B(2.11), B(2.12)):
//   c_1 < ... < c_s: the roots of the shifted Legendre polynomial P_s(2x − 1),
//   A from the collocation conditions C(s):   Σ_j a_ij c_j^{k−1} = c_i^k / k,   k = 1..s,
//   b from the quadrature conditions B(s):    Σ_j b_j  c_j^{k−1} = 1 / k,       k = 1..s.
// The roots are found by Newton's method on P_s (three-term recurrence) and the two Vandermonde
// systems are solved by Gaussian elimination, all in __float128 (≈ 34 digits), then rounded once
// to double. The result is symplectic, b_i a_ij + b_j a_ji − b_i b_j = 0 (B(1.18)), and of order
// 2s; gauss_tableau(1) is the implicit midpoint rule (c = a = ½, b = 1, exactly).
#pragma once

#include "core/method.hpp"

namespace dampsym {

inline constexpr int max_gauss_stages = 8;

// s-stage Gauss–Legendre tableau, 1 ≤ s ≤ max_gauss_stages (otherwise std::out_of_range).
const ButcherTableau& gauss_tableau(int s);

// Implicit Euler HLW(1.5) as a one-stage RK method: A = 1, b = 1, c = 1 (1-stage Radau IIA).
const ButcherTableau& implicit_euler_tableau();
// Explicit Euler HLW(1.4): A = 0, b = 1, c = 0 (the q part of symplectic Euler HLW(1.8)).
const ButcherTableau& explicit_euler_tableau();
// 2-stage Lobatto IIIA (trapezoidal rule): A = [0 0; ½ ½], b = (½, ½), c = (0, 1).
const ButcherTableau& lobatto_iiia2_tableau();
// 2-stage Lobatto IIIB: A = [½ 0; ½ 0], b = (½, ½), c = (0, 1). With IIIA for q and IIIB for p
// the pair is the Störmer–Verlet method HLW(3.6) (HLW II.2).
const ButcherTableau& lobatto_iiib2_tableau();

} // namespace dampsym
