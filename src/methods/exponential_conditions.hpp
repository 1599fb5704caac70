// Coefficient-level structure conditions of the exponential RK families (no problem needed),
// evaluated at a given γh (our γ, conventions §1) on the data of
// src/methods/exponential_tableaux.hpp.
//
// ERK, B Thm 2.6 / Thm 2.11: an ERK method B(2.7) maps dz∧J dz to φ_0² dz∧J dz (and a quadratic
// invariant zᵀWz to φ_0² zᵀWz) when, for all i, j,
//   b_i a_ij φ_0/φ_i + b_j a_ji φ_0/φ_j − b_i b_j = 0,                                   B(2.30)
// and is conformal symplectic when moreover φ_0 = e^{−∫γ} = e^{−γh}.                     B(2.31)
//
// PERK, B Thm 2.4 / Thm 2.10: a PERK method B(2.14) maps dq∧dp to φ̂_0 φ̃_0 dq∧dp when, for all i, j,
//   b̂_i φ̃_0/φ̃_i = b̃_i φ̂_0/φ̂_i,   b̂_i ã_ij φ̃_0/φ̃_i + b̃_j â_ji φ̂_0/φ̂_j − b̂_i b̃_j = 0,     B(2.23)
// and is conformal symplectic when moreover φ̂_0 φ̃_0 = e^{−∫(γ^1+γ^2)} = e^{−γ_B h}, which in our γ
// (γ_B = 2γ, conventions §1; the conversion is done by perk_coefficients) is e^{−2γh}.
//
// The conditions are sufficient, not necessary: B (after Thm 2.11) notes that cse-etd B(2.19) and
// csv2 B(2.21) violate B(2.23) and are nevertheless conformal symplectic (their step maps are
// compositions of damped shears; tests/test_exponential_rk.cpp checks this on Ψ), while etdprk2
// B(2.22) violates B(2.23) and is not conformal symplectic.
//
// Every function returns the largest absolute residual over all i (and j).
#pragma once

#include "methods/exponential_tableaux.hpp"

namespace dampsym {

// B(2.30) on one ERK tableau / on ERK data at γh.
double erk_condition_residual(const ExponentialTableau& t);
double erk_condition_residual(const ExponentialRKData& data, double gamma_h);
// B(2.31): |φ_0 − e^{−γh}|.
double erk_phi0_residual(const ExponentialRKData& data, double gamma_h);

// B(2.23) (both families of equations) on one PERK pair / on PERK data at γh.
double perk_condition_residual(const ExponentialTableau& hat_q, const ExponentialTableau& tilde_p);
double perk_condition_residual(const PartitionedExponentialRKData& data, double gamma_h);
// B Thm 2.10: |φ̂_0 φ̃_0 − e^{−2γh}| (= e^{−γ_B h} in B's γ).
double perk_phi0_residual(const PartitionedExponentialRKData& data, double gamma_h);

} // namespace dampsym
