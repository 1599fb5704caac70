#include "harness/registry.hpp"

#include "diagnostics/diagnostic_list.hpp"

#include <algorithm>

namespace dampsym {

const std::vector<ProblemInfo>& problem_catalog() {
    static const std::vector<ProblemInfo> catalog = [] {
        std::vector<ProblemInfo> out;
        for_each_type(ProblemList{}, [&]<class P>() {
            std::vector<std::string> inv(P::invariant_names.begin(), P::invariant_names.end());
            out.push_back({std::string(P::id), std::string(P::title), P::param_specs(), inv,
                           P::is_linear, P::has_exact, P::has_energy, P::constant_gamma,
                           supported_diagnostics<P>(), [](const ParamMap& m) {
                               const P p = P::from_params(m);
                               ProblemFacts f;
                               f.dim = p.dim();
                               if constexpr (requires { p.n(); }) f.dof = p.n();
                               if constexpr (HasForcingPeriod<P>)
                                   f.forcing_period = p.forcing_period();
                               return f;
                           }});
            if constexpr (requires { P::figure_orbit; }) out.back().figure_orbit = P::figure_orbit;
            out.back().probe_plane = HasProbePlane<P>;
        });
        return out;
    }();
    return catalog;
}

bool ProblemInfo::supports(std::string_view d) const {
    return std::find(diagnostics.begin(), diagnostics.end(), d) != diagnostics.end();
}

const ProblemInfo* find_problem(std::string_view id) {
    for (const auto& p : problem_catalog())
        if (p.id == id) return &p;
    return nullptr;
}

namespace {
template <class First, class... Rest>
First first_type(TypeList<First, Rest...>);
// Any registered problem type: kernel_name asks only what does not depend on it.
using AnyProblem = decltype(first_type(ProblemList{}));

// One kernel K of the list: its name if it takes this method's data and accepts it. (A function
// template rather than a lambda folded over the pack: clang 14, which builds the fuzz targets
// (ci/fuzz.sh), crashes on the nested generic lambda.)
template <template <class> class Kt, class D>
void kernel_name_if(const D& data, std::string_view& name) {
    using K = Kt<AnyProblem>; // Data, accepts and kernel_id do not depend on the problem type
    if constexpr (std::is_same_v<typename K::Data, D>)
        if (name.empty() && K::accepts(data)) name = K::kernel_id;
}
template <class D, template <class> class... Ks>
void kernel_name_in(KernelList<Ks...>, const D& data, std::string_view& name) {
    (kernel_name_if<Ks>(data, name), ...);
}
} // namespace

std::string_view kernel_name(const MethodInfo& info) {
    std::string_view name;
    std::visit([&](const auto& data) { kernel_name_in(Kernels{}, data, name); }, info.data);
    return name;
}

bool method_applies(std::string_view method_id, std::string_view problem_id) {
    const MethodInfo* m = find_method(method_id);
    if (!m) return false;
    bool ok = false;
    with_problem_type(problem_id, [&]<class P>() {
        KernelMatch match = KernelMatch::unknown_kernel;
        kernel_ops<P>(*m, match); // compiled in the kernel shards
        ok = match == KernelMatch::applied;
    });
    return ok;
}

} // namespace dampsym
