// What a method is: a MethodInfo row (data: id, order, claims, form and one typed coefficient set,
// MethodData) plus one kernel class template per family or hand-written scheme:
//
//   template <class P> struct Kernel {
//       static constexpr std::string_view kernel_id;       // for listings and reports only
//       using Data = ...;                                  // the MethodData alternative it steps
//       static bool accepts(const Data&);                  // which of those rows it steps
//       template <class Q> static constexpr bool applies;   // which problem forms it needs
//       Kernel(const P&, const MethodInfo&, double h, Counters&);
//       StepStatus step(double t, Vec& z);                 // z_n -> z_{n+1} in place
//   };
//
// The registry (src/harness/registry.hpp) chooses the kernel of a row by std::visit on its data.
// Adding a method of an existing family is one MethodInfo row in src/methods/catalog.cpp.
#pragma once

#include "core/types.hpp"

#include <string_view>
#include <variant>
#include <vector>

struct dampsym_method; // a C plugin's method (include/dampsym/plugin.h, docs/plugins.md)

namespace dampsym {

struct GlmCoefficients;

// Structure a method claims (conventions §3); the harness uses it to label checks and negative
// controls.
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

// Whether A is strictly lower triangular (every stage explicit).
inline bool is_explicit_tableau(const ButcherTableau& t) {
    for (int i = 0; i < t.stages; ++i)
        for (int j = i; j < t.stages; ++j)
            if (t.A(i, j) != 0.0) return false;
    return true;
}

// Equation form a method steps (conventions §1): the plain full vector field z' = f(t, z), the
// conformal form z' = N(z, t) − γz, or the separable Rayleigh form q' = ∇T(p), p' = F(q, t) − 2γp.
enum class Form { plain, conformal, separable };
constexpr std::string_view form_name(Form f) {
    switch (f) {
    case Form::plain:
        return "plain";
    case Form::conformal:
        return "conformal";
    case Form::separable:
        return "separable";
    }
    return "";
}

struct ExponentialRKData;            // src/methods/exponential_tableaux.hpp
struct PartitionedExponentialRKData; // src/methods/exponential_tableaux.hpp

// The typed coefficient sets a method row can hold; each names the family engine that steps it
// (src/harness/registry.hpp chooses the kernel by std::visit on the type, see Kernel::Data).
// An RK tableau on the plain form (explicit-rk for an explicit tableau, implicit-rk otherwise).
struct RungeKuttaTableau {
    const ButcherTableau* tableau;
};
// An RK tableau under the integrating factor B(2.5), conformal form (ifrk).
struct IntegratingFactorTableau {
    const ButcherTableau* tableau;
};
// A partitioned RK pair on the separable form: q tableau and p tableau (partitioned-rk).
struct PartitionedTableau {
    const ButcherTableau* q;
    const ButcherTableau* p;
};
// Exponential RK coefficient functions of the damping argument, B(2.7) (exponential-rk).
struct ExponentialCoefficients {
    const ExponentialRKData* data;
};
// Partitioned exponential RK coefficient functions, B(2.14) (partitioned-exponential-rk).
struct PartitionedExponentialCoefficients {
    const PartitionedExponentialRKData* data;
};
// General linear method [A U; B V] with its starting method (general-linear).
struct GeneralLinearCoefficients {
    const GlmCoefficients* glm;
};
// A hand-written scheme: its kernel is the code (src/methods/cimp.hpp, csv1.hpp, csv2.hpp).
// burgers_*: B's Burgers schemes (5.10), (5.12), (4.18) (src/pde/burgers/methods.hpp).
// kg_box: B's Klein–Gordon box scheme (5.5) (src/pde/klein_gordon/methods.hpp).
// nls_*: B's NLS schemes IF (4.15), ETD (5.27), IMP (5.28) by FFT (src/pde/nls/methods.hpp).
// symplectic_euler_partitioned: HLW (1.8) on a partitioned system (1.7)
// (src/methods/symplectic_euler_partitioned.hpp).
enum class Scheme {
    cimp,
    csv1,
    csv2,
    burgers_csv,
    burgers_box,
    burgers_nsfd,
    kg_box,
    nls_if,
    nls_etd,
    nls_imp,
    symplectic_euler_partitioned
};
struct HandWrittenScheme {
    Scheme scheme;
};

// A hand-written step of a C plugin loaded with --plugin (src/methods/plugin_kernel.hpp,
// src/harness/user_methods/plugins.hpp); the row's form says which problem form it steps.
struct PluginStep {
    const dampsym_method* method;
    // The --plugin path (stable storage in harness/user_methods/plugins.cpp).
    const char* library = nullptr;
};

// The method families, one typed coefficient set each. MethodData is generated from this list,
// and each family registers, in one place (its Family<D> traits, src/methods/families.hpp), its
// kernels, stage count and coefficient checks; the registry's kernels, the checks, the method-file
// reader and the memory model are folds over this list, and a family without traits does not
// compile.
using MethodFamilies =
    TypeList<HandWrittenScheme, RungeKuttaTableau, IntegratingFactorTableau, PartitionedTableau,
             ExponentialCoefficients, PartitionedExponentialCoefficients, GeneralLinearCoefficients,
             PluginStep>;
template <class L>
struct VariantOf;
template <class... Ts>
struct VariantOf<TypeList<Ts...>> {
    using type = std::variant<Ts...>;
};
using MethodData = VariantOf<MethodFamilies>::type;

struct MethodInfo {
    std::string_view id;
    int order;
    bool implicit;
    Form form;
    unsigned claims;
    std::string_view citation;
    MethodData data;
};

// The coefficient set of type T of a row, or nullptr if the row holds another type.
template <class T>
const T* method_data(const MethodInfo& m) {
    return std::get_if<T>(&m.data);
}

// The Butcher tableau of a row stepped on the plain form (explicit or implicit RK), else nullptr.
inline const ButcherTableau* plain_tableau(const MethodInfo& m) {
    const auto* rk = method_data<RungeKuttaTableau>(m);
    return rk ? rk->tableau : nullptr;
}

const std::vector<MethodInfo>& method_catalog();
const MethodInfo* find_method(std::string_view id);

} // namespace dampsym
