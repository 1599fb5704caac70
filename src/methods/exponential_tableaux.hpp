// Coefficient data of the exponential Runge–Kutta families of B §2.1: coefficient FUNCTIONS of the
// damping argument, evaluated once per (γ, h) by the generic kernels (exponential_rk.hpp,
// partitioned_exponential_rk.hpp) and by the coefficient-level conditions
// (exponential_conditions.hpp): functions of the damping argument x (γh, or the step's
// x_n = Γ(t_n + h) − Γ(t_n) for a time-dependent γ, see exponential_rk.hpp).
//
// ERK, B(2.7) with tableau B(2.10), on the conformal form z' = N(z, t) − γz (conventions §1,
// B(1.1)):
//   Z_i     = φ_i(x) z_n + h Σ_j a_ij(x) N(Z_j, t_n + c_j h),
//   z_{n+1} = φ_0(x) z_n + h Σ_i b_i(x) N(Z_i, t_n + c_i h),          x = γh (OUR γ: B(1.1),
//   (2.5), (2.13) use the conformal γ, which is ours; no conversion for ERK data).
// Two constructions (B §2.1):
//   integrating factor (IFRK) B(2.5), constant γ, from an underlying RK tableau (α, β, c):
//     a_ij = α_ij e^{−(c_i − c_j)x},  φ_i = e^{−c_i x},  b_i = β_i e^{−(1 − c_i)x},  φ_0 = e^{−x};
//   exponential time differencing (ETDRK) B(2.6): quadrature of the variation-of-constants
//     integral. etdrk2 = B(2.13), the ETD form of the implicit midpoint rule:
//       c = ½,  a_11 = (e^{x/2} − e^{−x/2})/(2x),  φ_1 = e^{−x/2},
//       b_1 = (1 − e^{−x})/x,  φ_0 = e^{−x};
//     a_11 is evaluated as 2 sinh(x/2)/(2x) (as B says) and b_1 as −expm1(−x)/x, with the Taylor
//     series below |x| = 1e−7 (and at x = 0: a_11 = ½, b_1 = 1, the underlying midpoint rule,
//     B(2.8)), so no difference of nearly equal exponentials is ever formed.
//
// PERK, B(2.14)/(2.15), for the separable Rayleigh form written as B(2.17):
//   q' = ∇T(p),  p' = F(q, t) − γ_B p,   γ_B = 2γ   (F = −∇V; γ^1 = 0, γ^2 = γ_B in B(1.2))
//   Q_i = φ̂_i q_n + h Σ_j â_ij ∇T(P_j),        P_i = φ̃_i p_n + h Σ_j ã_ij F(Q_j, t_n + ĉ_j h),
//   q_{n+1} = φ̂_0 q_n + h Σ_i b̂_i ∇T(P_i),    p_{n+1} = φ̃_0 p_n + h Σ_i b̃_i F(Q_i, t_n + ĉ_i h),
// the "hat" tableau for q and the "tilde" tableau for p, both functions of B's argument x_B = γ_B
// h.
// *** B's γ in (2.17)–(2.22) is TWICE ours (conventions §1). The PERK data functions below are
// written
// *** exactly as B prints them, in x_B; perk_coefficients() is the ONE place that converts:
// ***   x_B = γ_B h = 2γh.
// Rows (B Example 2.2; all written in x_B):
//   cse-if   B(2.18)  q_{n+1} = q_n + h∇T(p_{n+1}),  p_{n+1} = e^{−x_B} p_n − h∇V(q_n):
//            hat: c=0, â=0, φ̂=1, b̂=1, φ̂_0=1;  tilde: ã=1, φ̃=e^{−x_B}, b̃=1, φ̃_0=e^{−x_B}.
//   cse-etd  B(2.19)  p_{n+1} = e^{−x_B} p_n + (1/γ_B)(e^{−x_B} − 1)∇V(q_n): as cse-if with
//            ã = b̃ = (1 − e^{−x_B})/x_B (= −expm1(−x_B)/x_B).
//   csv1-perk B(2.20) (IF Lobatto IIIA–IIIB = csv1 F(2.12)):
//            hat:   c=(0,1), Â=[0 0; ½ ½], φ̂=(1,1), b̂=(½,½), φ̂_0=1;
//            tilde: Ã=[½ 0; ½ 0], φ̃=(e^{−x_B/2}, e^{−x_B/2}), b̃=(½e^{−x_B/2}, ½e^{−x_B/2}),
//                   φ̃_0=e^{−x_B}.
//   csv2-perk B(2.21) (= csv2 F(2.16)):
//            hat:   c=(0,1), Â=[0 0; κ κ], φ̂=(1, ρ), b̂=(κ, κ), φ̂_0=ρ,
//                   κ = 2e^{−x_B/4}/(4 − x_B), ρ = (4 + x_B)/(4 − x_B) e^{−x_B/2};
//            tilde: Ã=[2/(4+x_B) 0; 2/(4+x_B) 0], φ̃_i = 4e^{−x_B/4}/(4 + x_B),
//                   b̃=((4−x_B)/(4+x_B) e^{−x_B/4}/2, e^{−x_B/4}/2), φ̃_0=(4−x_B)/(4+x_B) e^{−x_B/2}.
//            NOTE: B(2.21) prints Â_21 = Â_22 = b̂_1 = b̂_2 = 2/(4 − γ_B h) without the factor
//            e^{−γ_B h/4}. As printed the q update would be q_{n+1} = ρ q_n + h(1 + x_B/4 +
//            …)∇T(p½), which is only first order and is not F(2.16); with κ as above the pair
//            reproduces F(2.16) and B(2.46) exactly (tests/test_exponential_rk.cpp compares it with
//            csv2 per step).
//   etdprk2  B(2.22) (ETD Lobatto IIIA–IIIB): hat as csv1-perk; tilde:
//            Ã=[α 0; α 0], α = (1 − e^{−x_B/2})/x_B (= −expm1(−x_B/2)/x_B), φ̃=(e^{−x_B/2},
//            e^{−x_B/2}), b̃=(½e^{−x_B/2}, ½e^{−x_B/2}), φ̃_0=e^{−x_B}. Not conformal symplectic (B
//            after Thm 2.11): on the oscillator det Ψ = e^{−2γh}(1 + h²ω²(½ − α)) = e^{−2γh}(1 +
//            γω²h³/4 + O(h⁴)).
// Stage times use ĉ (time is a position variable, as in partitioned_rk.hpp); c̃ is B's printed
// column and is used only as data.
#pragma once

#include "core/method.hpp"
#include "core/types.hpp"

#include <string_view>

namespace dampsym {

// One Butcher-like tableau B(2.10) [c | A | φ ; b | φ_0] evaluated at one argument.
struct ExponentialTableau {
    int stages = 0;
    Mat A;
    Vec b, c, phi;
    double phi0 = 1.0;
    void resize(int s) {
        stages = s;
        A = Mat::Zero(s, s);
        b = Vec::Zero(s);
        c = Vec::Zero(s);
        phi = Vec::Ones(s);
        phi0 = 1.0;
    }
    double a(int i, int j) const { return A(i, j); }
};

// ERK data: coefficient functions of x = γh (our γ), B(2.7).
struct ExponentialRKData {
    std::string_view name;
    std::string_view source;
    std::string_view construction; // "integrating-factor" (B(2.5)) or "etd" (B(2.6))
    int stages;
    const ButcherTableau* underlying; // integrating factor: the RK tableau (α, β, c); else null
    void (*coefficients)(const ExponentialRKData& self, double x, ExponentialTableau& out);
};

// PERK data: both tableaux as functions of B's argument x_B = γ_B h = 2γh (see above).
struct PartitionedExponentialRKData {
    std::string_view name;
    std::string_view source;
    std::string_view construction; // "integrating-factor" or "etd" (IFPRK / ETDPRK, B after (2.17))
    int stages;
    void (*coefficients_B)(double x_B, ExponentialTableau& hat_q, ExponentialTableau& tilde_p);
};

// The ERK tableau at γh (our γ = the conformal γ of B(1.1); no conversion).
void erk_coefficients(const ExponentialRKData& data, double gamma_h, ExponentialTableau& out);
// The PERK pair at γh (our γ): calls data.coefficients_B at x_B = 2γh. The only conversion of
// B's γ in the code base's exponential families.
void perk_coefficients(const PartitionedExponentialRKData& data, double gamma_h,
                       ExponentialTableau& hat_q, ExponentialTableau& tilde_p);

// Cancellation-free scalar functions (exact limits at x = 0, Taylor series for |x| < 1e−7):
double exprel(double x);         // (e^x − 1)/x = expm1(x)/x
double sinh_half_over(double x); // sinh(x/2)/x  (= (e^{x/2} − e^{−x/2})/(2x))

// ---- ERK rows (kernel "exponential-rk") ----
const ExponentialRKData& etdrk2_data(); // B(2.13)
// GL-IFRK B(2.11) (s = 1), B(2.12) (s = 2), 3-stage (s = 3) as ERK data (integrating-factor
// construction on gauss_tableau(s)); the catalog steps glifrk1..3 with the ifrk kernel, these rows
// cross-check the ERK kernel and the conditions against them.
const ExponentialRKData& if_gauss_data(int s);

// ---- PERK rows (kernel "partitioned-exponential-rk") ----
const PartitionedExponentialRKData& cse_if_data();    // B(2.18)
const PartitionedExponentialRKData& cse_etd_data();   // B(2.19)
const PartitionedExponentialRKData& csv1_perk_data(); // B(2.20)
const PartitionedExponentialRKData& csv2_perk_data(); // B(2.21) (corrected, see above)
const PartitionedExponentialRKData& etdprk2_data();   // B(2.22)

} // namespace dampsym
