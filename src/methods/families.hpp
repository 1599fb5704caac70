// The method families, each registered in one place: its Family<D> traits below, D being its
// typed coefficient set (an alternative of MethodData, core/method.hpp, whose list MethodFamilies
// is the one list of families). A family's traits give
//   kernels        the kernel templates that step its rows (KernelList; the registry chooses the
//                  first of them whose Data is D and that accepts the row, harness/registry.hpp);
//   file_family    the "family" key of a method file that holds such rows ("" for none: the
//                  method-file reader and writer, docs/method-files.md, harness/user_methods/);
//   stages(d)      the stage count (--max-memory's memory model, harness/run/memory_limits.cpp);
//   checks(m, d, out)  every coefficient condition of the family (order conditions to the row's
//                  order, the structure its claims assert), for built-in rows and method files
//                  alike (coefficient_checks.hpp, exponential_checks.cpp).
// Everything that dispatches on a row's family folds over MethodFamilies through these traits, and
// the static_asserts below refuse a family without complete traits or without a kernel: adding a
// family is its coefficient type in MethodFamilies, its kernel header(s), and its traits here.
#pragma once

#include "core/method.hpp"
#include "methods/cimp.hpp"
#include "methods/coefficient_checks.hpp"
#include "methods/csv1.hpp"
#include "methods/csv2.hpp"
#include "methods/explicit_rk.hpp"
#include "methods/exponential_rk.hpp"
#include "methods/general_linear.hpp"
#include "methods/ifrk.hpp"
#include "methods/implicit_rk.hpp"
#include "methods/partitioned_exponential_rk.hpp"
#include "methods/partitioned_rk.hpp"
#include "methods/plugin_kernel.hpp" // C plugins (--plugin, docs/plugins.md)
#include "methods/symplectic_euler_partitioned.hpp"
#include "pde/burgers/methods.hpp"      // B's Burgers schemes (5.10), (5.12), (4.18)
#include "pde/klein_gordon/methods.hpp" // B's Klein–Gordon box scheme (5.5)
#include "pde/nls/methods.hpp"          // B's NLS schemes (4.15), (5.27), (5.28) by FFT

#include <algorithm>
#include <string_view>
#include <type_traits>
#include <vector>

namespace dampsym {

template <template <class> class... Ks>
struct KernelList {};

template <class D>
struct Family; // one specialisation per alternative of MethodData

namespace family_detail {
inline bool claims(const MethodInfo& m, unsigned c) {
    return (m.claims & c) != 0;
}
} // namespace family_detail

// Hand-written schemes: the code is the method (cimp, csv1, csv2, B's PDE schemes, HLW (1.8)); no
// coefficients to check — their step Jacobians and orders are checked against their steps
// (diagnostics/jacobian_check.hpp, the order fits).
template <>
struct Family<HandWrittenScheme> {
    using kernels = KernelList<Cimp, Csv1, Csv2, BurgersCsv, BurgersBoxScheme, BurgersNsfd,
                               KGBoxScheme, NlsIf, NlsEtd, NlsImp, SymplecticEulerPartitioned>;
    static constexpr std::string_view file_family = "";
    static int stages(const HandWrittenScheme&) { return 1; }
    static void checks(const MethodInfo&, const HandWrittenScheme&,
                       std::vector<CoefficientCheck>&) {}
};

// An RK tableau on the plain form: symplecticity expected iff claim_symplectic_if_undamped.
template <>
struct Family<RungeKuttaTableau> {
    using kernels = KernelList<ExplicitRK, ImplicitRK>;
    static constexpr std::string_view file_family = "rk";
    static int stages(const RungeKuttaTableau& d) { return d.tableau ? d.tableau->stages : 1; }
    static void checks(const MethodInfo& m, const RungeKuttaTableau& d,
                       std::vector<CoefficientCheck>& out) {
        rk_checks(*d.tableau, m.order, family_detail::claims(m, claim_symplectic_if_undamped),
                  "b_i a_ij + b_j a_ji − b_i b_j = 0 (B(1.18), BS)", out);
    }
};

// An RK tableau under the integrating factor B(2.5): the same checks on the underlying tableau;
// symplecticity expected iff claim_conformal_symplectic (B Thm 2.6: the IFRK method is conformal
// symplectic when its underlying RK method is symplectic). In a method file: family "rk" with
// "integrating_factor": true.
template <>
struct Family<IntegratingFactorTableau> {
    using kernels = KernelList<IFRK>;
    static constexpr std::string_view file_family = "rk";
    static int stages(const IntegratingFactorTableau& d) {
        return d.tableau ? d.tableau->stages : 1;
    }
    static void checks(const MethodInfo& m, const IntegratingFactorTableau& d,
                       std::vector<CoefficientCheck>& out) {
        rk_checks(*d.tableau, m.order, family_detail::claims(m, claim_conformal_symplectic),
                  "underlying RK symplectic, b_i a_ij + b_j a_ji − b_i b_j = 0 "
                  "(B(1.18)); conformal symplectic by B Thm 2.6",
                  out);
    }
};

// A partitioned RK pair on the separable form (HLW II.2, VI.4).
template <>
struct Family<PartitionedTableau> {
    using kernels = KernelList<PartitionedRK>;
    static constexpr std::string_view file_family = "partitioned-rk";
    static int stages(const PartitionedTableau& d) {
        return std::max(d.q ? d.q->stages : 1, d.p ? d.p->stages : 1);
    }
    static void checks(const MethodInfo& m, const PartitionedTableau& d,
                       std::vector<CoefficientCheck>& out) {
        prk_checks(*d.q, *d.p, m.order, family_detail::claims(m, claim_symplectic_if_undamped),
                   out);
    }
};

// Exponential RK, B(2.7): the γh = 0 limit's conditions and B(2.30)/(2.31) for a conformal claim.
template <>
struct Family<ExponentialCoefficients> {
    using kernels = KernelList<ExponentialRK>;
    static constexpr std::string_view file_family = "exponential-rk";
    static int stages(const ExponentialCoefficients& d) { return d.data ? d.data->stages : 1; }
    static void checks(const MethodInfo& m, const ExponentialCoefficients& d,
                       std::vector<CoefficientCheck>& out) {
        erk_checks(*d.data, m.order, m.claims, out);
    }
};

// Partitioned exponential RK, B(2.14): the limit's conditions and B(2.23)/Thm 2.10.
template <>
struct Family<PartitionedExponentialCoefficients> {
    using kernels = KernelList<PartitionedExponentialRK>;
    static constexpr std::string_view file_family = "partitioned-exponential-rk";
    static int stages(const PartitionedExponentialCoefficients& d) {
        return d.data ? d.data->stages : 1;
    }
    static void checks(const MethodInfo& m, const PartitionedExponentialCoefficients& d,
                       std::vector<CoefficientCheck>& out) {
        perk_checks(*d.data, m.order, m.claims, out);
    }
};

// A general linear method with its starting method (BS, BD): G-symplecticity expected iff
// claim_g_symplectic; the order on the linear test and the stage abscissae.
template <>
struct Family<GeneralLinearCoefficients> {
    using kernels = KernelList<GeneralLinear>;
    static constexpr std::string_view file_family = "general-linear";
    static int stages(const GeneralLinearCoefficients& d) {
        return d.glm ? std::max(d.glm->s, d.glm->r) : 1;
    }
    static void checks(const MethodInfo& m, const GeneralLinearCoefficients& d,
                       std::vector<CoefficientCheck>& out) {
        glm_checks(*d.glm, family_detail::claims(m, claim_g_symplectic), out);
        glm_order_checks(*d.glm, m.order, out);
    }
};

// A C plugin's step (docs/plugins.md): its code is the method; E_n and the order fits judge it.
template <>
struct Family<PluginStep> {
    using kernels = KernelList<PluginPlain, PluginConformal, PluginSeparable>;
    static constexpr std::string_view file_family = "";
    static int stages(const PluginStep&) { return 1; }
    static void checks(const MethodInfo&, const PluginStep&, std::vector<CoefficientCheck>&) {}
};

// Complete traits: a family missing one of these does not compile.
template <class D>
concept FamilyTraits = requires(const MethodInfo& m, const D& d, std::vector<CoefficientCheck>& o) {
    typename Family<D>::kernels;
    { Family<D>::file_family } -> std::convertible_to<std::string_view>;
    { Family<D>::stages(d) } -> std::same_as<int>;
    Family<D>::checks(m, d, o);
};

namespace family_detail {
template <template <class> class... Ks>
constexpr bool has_kernels(KernelList<Ks...>) {
    return sizeof...(Ks) > 0;
}
template <class... Ds>
constexpr bool all_families(TypeList<Ds...>) {
    return ((FamilyTraits<Ds> && has_kernels(typename Family<Ds>::kernels{})) && ...);
}
template <class... L>
struct Concat;
template <template <class> class... A>
struct Concat<KernelList<A...>> {
    using type = KernelList<A...>;
};
template <template <class> class... A, template <class> class... B, class... Rest>
struct Concat<KernelList<A...>, KernelList<B...>, Rest...> {
    using type = typename Concat<KernelList<A..., B...>, Rest...>::type;
};
template <class L>
struct KernelsOf;
template <class... Ds>
struct KernelsOf<TypeList<Ds...>> {
    using type = typename Concat<typename Family<Ds>::kernels...>::type;
};
} // namespace family_detail

static_assert(family_detail::all_families(MethodFamilies{}),
              "every family of MethodFamilies (core/method.hpp) needs complete Family<D> traits "
              "(src/methods/families.hpp) and at least one kernel");

// Every kernel, family by family in the order of MethodFamilies (the registry's choice among the
// kernels of one family follows the order of that family's list).
using AllKernels = family_detail::KernelsOf<MethodFamilies>::type;

// Calls f(Family<D>{}, data) for the coefficient set of the row (std::visit on MethodInfo::data).
template <class F>
decltype(auto) visit_family(const MethodInfo& m, F&& f) {
    return std::visit(
        [&](const auto& data) -> decltype(auto) {
            using D = std::decay_t<decltype(data)>;
            return f(Family<D>{}, data);
        },
        m.data);
}

} // namespace dampsym
