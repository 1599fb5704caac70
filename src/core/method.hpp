// What a method is: a MethodInfo row (data: id, order, claims, the kernel that steps it and the
// kernel's coefficient data) plus one kernel class template per family or hand-written scheme:
//
//   template <class P> struct Kernel {
//       static constexpr std::string_view kernel_id;
//       template <class Q> static constexpr bool applies;   // which problem forms it needs
//       Kernel(const P&, const MethodInfo&, double h, Counters&);
//       StepStatus step(double t, Vec& z);                 // z_n -> z_{n+1} in place
//   };
//
// Adding a method of an existing family is one MethodInfo row in src/methods/catalog.cpp.
#pragma once

#include "core/types.hpp"

#include <string_view>
#include <vector>

namespace dampsym {

struct GlmCoefficients;

// Structure a method claims (SPEC §3); the harness uses it to label checks and negative controls.
enum Claim : unsigned {
    claim_none = 0,
    claim_conformal_symplectic = 1u << 0,
    claim_conformal_quadratic = 1u << 1,
    claim_angular_momentum = 1u << 2,
    claim_linear_momentum = 1u << 3,
    claim_symplectic_if_undamped = 1u << 4,
    // Total linear momentum of a pair-potential system decays per step by the factor
    // e^{−γh}(2−γh)/(2+γh) instead of the exact e^{−2γh} (B Table 3.1: CSV2, CIMP).
    claim_linear_momentum_cayley = 1u << 5,
    // G-symplectic general linear method (BS, BD §3): for γ = 0 and every quadratic invariant
    // yᵀMy, Σ g_ij y_iᵀ M y_j of the r values is conserved.
    claim_g_symplectic = 1u << 6,
};

// Butcher tableau of an explicit or implicit RK method, row-major A (s×s).
struct ButcherTableau {
    int stages;
    std::vector<double> a;
    std::vector<double> b;
    std::vector<double> c;
    double A(int i, int j) const { return a[static_cast<std::size_t>(i * stages + j)]; }
};

// Closed forms of F ch. 3 for the one-step matrix M of a method on the oscillator, when known.
struct OscillatorFormulas {
    // ½ tr M as a function of (ω, γ, h): F(3.10), (3.15), (3.20).
    double (*half_trace)(double omega, double gamma, double h) = nullptr;
    // F's "stability" condition |½ tr M| < e^{-γh} in closed form: F(3.12), (3.17), (3.22).
    bool (*F_condition)(double omega, double gamma, double h) = nullptr;
    // Leading coefficient c of ½tr M − e^{-γh}cos(βh) = c h⁴ + O(h⁵), up to sign (SPEC §5 gives
    // them up to sign; F's (3.13), (3.18), (3.23) are typos). Checks compare magnitudes.
    double (*h4_coefficient)(double omega, double gamma) = nullptr;
    const char* source = "";
};

struct MethodInfo {
    std::string_view id;
    std::string_view kernel; // kernel_id of the family kernel that steps it
    int order;
    bool implicit;
    std::string_view form; // "separable", "conformal" or "plain"
    unsigned claims;
    std::string_view citation;
    const ButcherTableau* tableau = nullptr;
    OscillatorFormulas oscillator{};
    // Partitioned RK (kernel "partitioned-rk"): the p tableau; `tableau` is then the q tableau.
    const ButcherTableau* tableau_p = nullptr;
    // General linear method (kernel "general-linear", src/methods/glm_coefficients.hpp).
    const GlmCoefficients* glm = nullptr;
    // Coefficient data of the exponential RK kernels (src/methods/exponential_tableaux.hpp):
    // const ExponentialRKData* for "exponential-rk", const PartitionedExponentialRKData* for
    // "partitioned-exponential-rk"; the kernel named by `kernel` casts it back.
    const void* family_data = nullptr;
};

const std::vector<MethodInfo>& method_catalog();
const MethodInfo* find_method(std::string_view id);

} // namespace dampsym
