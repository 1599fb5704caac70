#include "diagnostics/diagnostic.hpp"

#include "diagnostics/diagnostic_list.hpp"

#include <algorithm>

namespace dampsym {

const std::vector<DiagnosticInfo>& diagnostic_registry() {
    static const std::vector<DiagnosticInfo> registry = [] {
        std::vector<DiagnosticInfo> out;
        for_each_type(DiagnosticList{}, [&]<class D>() { out.push_back(D::info()); });
        return out;
    }();
    return registry;
}

const DiagnosticInfo* find_diagnostic(std::string_view name) {
    for (const auto& d : diagnostic_registry())
        if (d.name == name) return &d;
    return nullptr;
}

const std::vector<std::string>& run_record_fields() {
    static const std::vector<std::string> fields{"steps",     "steps_planned", "rhs_evals",
                                                 "jac_evals", "newton_iters",  "final_time",
                                                 "ok",        "diverged",      "failed_at_step"};
    return fields;
}

std::vector<std::string> diagnostic_metrics(std::string_view d,
                                            const std::vector<std::string>& invariants,
                                            bool placeholder) {
    if (d == "run") return run_record_fields();
    const DiagnosticInfo* info = find_diagnostic(d);
    if (!info) return {};
    if (!info->per_invariant) return info->metrics;
    std::vector<std::string> out;
    const std::vector<std::string> names =
        invariants.empty() && placeholder ? std::vector<std::string>{"<invariant>"} : invariants;
    for (const auto& inv : names)
        for (const auto& m : info->metrics) out.push_back(inv + "." + m);
    return out;
}

} // namespace dampsym
