// The method registry: the kernels that step each family's coefficient sets, and with_kernel, which
// chooses the kernel of a row for a problem type (the problems are harness/problem_list.hpp).
// Adding a family = its coefficient type in MethodFamilies (core/method.hpp), its kernel header(s)
// and its Family<D> traits (src/methods/families.hpp), from which the kernel list here is
// generated; adding a method of an existing family = one row in src/methods/catalog.cpp. Nothing
// in the runner changes. Only the kernel shards (harness/run/kernel_ops_impl.hpp) and programs that
// step a kernel of their own (bench/, a test's planted defect) instantiate with_kernel with code
// that steps; the rest of the library and the tests call the compiled pairs (kernel_ops<P>).
#pragma once

#include "core/method.hpp"
#include "core/problem.hpp"
#include "core/problem_concepts.hpp"
#include "harness/problem_info.hpp"
#include "harness/problem_list.hpp"
#include "harness/run/kernel_ops.hpp" // KernelMatch
#include "methods/families.hpp"       // the families and their kernels

#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

namespace dampsym {

// Every kernel of every family (Family<D>::kernels, methods/families.hpp).
using Kernels = AllKernels;

// Each family's kernels step that family's coefficient set (Kernel::Data; the problem type only
// chooses the instantiation, so the oscillator stands for all).
template <class D, template <class> class... Ks>
constexpr bool kernels_step(KernelList<Ks...>) {
    return (std::is_same_v<typename Ks<Oscillator>::Data, D> && ...);
}
template <class... Ds>
constexpr bool kernels_step_their_family(TypeList<Ds...>) {
    return (kernels_step<Ds>(typename Family<Ds>::kernels{}) && ...);
}
static_assert(kernels_step_their_family(MethodFamilies{}),
              "a kernel in Family<D>::kernels must have Data = D (methods/families.hpp)");

namespace registry_detail {
// One kernel Kt of the list (function templates rather than a lambda folded over the pack: clang
// 14, which builds the fuzz targets (ci/fuzz.sh), crashes on the nested generic lambda).
template <class P, template <class> class Kt, class D, class F>
void with_kernel_if(const D& data, F& f, KernelMatch& result) {
    using K = Kt<P>;
    if constexpr (std::is_same_v<typename K::Data, D>) {
        if (result == KernelMatch::unknown_kernel && K::accepts(data)) {
            if constexpr (K::template applies<P>) {
                f.template operator()<K>();
                result = KernelMatch::applied;
            } else {
                result = KernelMatch::not_applicable;
            }
        }
    }
}
template <class P, class D, class F, template <class> class... Ks>
KernelMatch with_kernel_in(KernelList<Ks...>, const D& data, F& f) {
    KernelMatch result = KernelMatch::unknown_kernel;
    (with_kernel_if<P, Ks>(data, f, result), ...);
    return result;
}
// with_kernel_among's call: f for kernel K if K is the kernel with_kernel chooses (a class, not
// a generic lambda inside the visitor: see with_kernel_if).
template <class F>
struct CheckedKernelCall {
    const MethodInfo& info;
    F& f;
    template <class K>
    void operator()() {
        if (K::kernel_id != kernel_name(info))
            throw std::logic_error("with_kernel_among: " + std::string(info.id) +
                                   " is stepped by " + std::string(kernel_name(info)) + ", not " +
                                   std::string(K::kernel_id));
        f.template operator()<K>();
    }
};
} // namespace registry_detail

// Calls f.template operator()<K<P>>() for the kernel that steps `info` on problem type P: the type
// of the row's coefficient set (std::visit on MethodInfo::data) selects the kernels whose Data is
// that type, and the first of them that accepts the data steps it.
template <class P, class F>
KernelMatch with_kernel(const MethodInfo& info, F&& f) {
    return std::visit(
        [&](const auto& data) { return registry_detail::with_kernel_in<P>(Kernels{}, data, f); },
        info.data);
}

// with_kernel among the kernels of List only (a KernelList): f is instantiated for those alone,
// which keeps the compile time of a test that steps a few methods small. unknown_kernel if the
// method's kernel is not in List; std::logic_error if the kernel chosen is not the one with_kernel
// would choose (kernel_name), so a short list never steps a method by another kernel.
template <class P, class List, class F>
KernelMatch with_kernel_among(const MethodInfo& info, F&& f) {
    registry_detail::CheckedKernelCall<std::remove_reference_t<F>> checked{info, f};
    return std::visit(
        [&](const auto& data) { return registry_detail::with_kernel_in<P>(List{}, data, checked); },
        info.data);
}

} // namespace dampsym
