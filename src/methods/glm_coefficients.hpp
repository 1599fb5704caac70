// Coefficient data of a general linear method (GLM), BD §2, BS "A symplectic general linear
// method": r input values y^{[n−1]} = (y_1, …, y_r), s stages Y, stage derivatives F_i = f(Y_i),
//   Y       = h (A ⊗ I) F + (U ⊗ I) y^{[n−1]},
//   y^{[n]} = h (B ⊗ I) F + (V ⊗ I) y^{[n−1]}              (BD(2.3), BS),
// written [A U; B V] with A s×s, U s×r, B r×s, V r×r. y_1 approximates the solution itself.
//
// Since the method carries r values but a problem has one initial value, a starting method
// [A₀ U₀; B₀ V₀] (s₀ stages, one input value z₀) produces y^{[0]} = h (B₀ ⊗ I) F + (V₀ ⊗ I) z₀
// with Y = h (A₀ ⊗ I) F + (U₀ ⊗ I) z₀ (BS "This requires a starting method"). s₀ = 0 means
// y^{[0]} = V₀ z₀ (no stage).
//
// Stage times: stage i is evaluated at t + c_i h, with c = A e + U q₁ for a consistency vector q₁
// (BD Def 2.3); the data carries c explicitly (for glm4 c = A e, BS: Y_1 ≈ y(x₀ + h(3+√3)/6),
// Y_2 ≈ y(x₀ + h(3−√3)/6)), and c₀ for the starting stages.
//
// G-symplecticity certificate (BS, BD §3): a symmetric positive definite G (r×r) and a diagonal
// positive definite D (s×s) with
//   DA + AᵀD = BᵀGB,   G = VᵀGV,   DU = BᵀGV,
// under which Σ g_ij y_iᵀ M y_j is conserved for every quadratic invariant yᵀMy of the ODE. G and D
// are empty for a method without such a certificate. src/methods/coefficient_checks.hpp verifies
// them (and stability, pre-consistency and consistency, BD Defs 2.1–2.3).
#pragma once

#include "core/types.hpp"

#include <string_view>

namespace dampsym {

struct GlmCoefficients {
    std::string_view name;
    int s = 0, r = 0;
    Mat A, U, B, V; // s×s, s×r, r×s, r×r
    Vec c;          // stage abscissae, s
    Mat G, D;       // G-symplecticity certificate (r×r, s×s), or empty
    // Starting method: s₀ stages, one input value.
    int s0 = 0;
    Mat A0; // s₀×s₀
    Vec U0; // s₀
    Mat B0; // r×s₀
    Vec V0; // r
    Vec c0; // s₀
    std::string_view citation;
};

// Butcher's 2-stage, 2-value G-symplectic method of order 4 with its starting method (BS;
// conventions §3):
//   A = [ (3+√3)/6  0 ; −√3/3  (3+√3)/6 ],   U = [ 1  −(3+2√3)/3 ; 1  (3+2√3)/3 ],
//   B = [ ½  ½ ; ½  −½ ],                    V = [ 1  0 ; 0  −1 ],
//   G = diag(1, 1 + 2√3/3),  D = diag(½, ½),  c = A e = ((3+√3)/6, (3−√3)/6);
// starting method A₀ = [ (3+√3)/6  0 ; −(3+√3)/3  (3+√3)/6 ], U₀ = [1; 1], c₀ = A₀ e = ±(3+√3)/6,
//   y₁ = z₀,   y₂ = h((√3−1)/8 F₁ + (1−√3)/8 F₂)  (≈ (√3/12) h² y'', BS Theorem 3 (1)).
// Every entry is an exact expression in √3, with √3 = std::sqrt(3.0) computed once (correctly
// rounded), so each coefficient is within a few ulps of its exact value.
const GlmCoefficients& butcher_glm4();

} // namespace dampsym
