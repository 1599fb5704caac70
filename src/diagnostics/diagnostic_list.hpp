// The diagnostic registry: DiagnosticList, every diagnostic type that its own header
// src/diagnostics/<name>_diagnostic.hpp registers with a `DAMPSYM_DIAGNOSTIC(Type, order);` line
// (diagnostic.hpp), by ascending order: the order of `dampsym list`, of the "known:" list in
// validation messages and of the report's metrics-table columns. The build generates the list
// (cmake/diagnostic_registry.cmake writes diagnostic_registry_generated.hpp from those lines).
#pragma once

#include "core/types.hpp"
#include "diagnostic_registry_generated.hpp"

#include <string>
#include <vector>

namespace dampsym {

using DiagnosticList = TypeList<DAMPSYM_REGISTERED_DIAGNOSTICS>;

// The names of the diagnostics problem type P supports (each diagnostic's `supports<P>` concept),
// for ProblemInfo (harness/registry.cpp).
template <class P>
std::vector<std::string> supported_diagnostics() {
    std::vector<std::string> out;
    for_each_type(DiagnosticList{}, [&]<class D>() {
        if constexpr (D::template supports<P>) out.push_back(D::info().name);
    });
    return out;
}

} // namespace dampsym
