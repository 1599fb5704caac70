// The report's case-level "problem_check" (diagnostics/problem_check.hpp) and the failing check
// a mismatch adds to the case.
#pragma once

#include "diagnostics/metric_json.hpp"
#include "diagnostics/problem_check.hpp"

#include <algorithm>
#include <string>

namespace dampsym {

// {"parts", "states", "directions", "rel", "tol", "ratio", "structure_*", "passed"}.
inline json problem_check_json(const ProblemCheck& pc, std::int64_t states) {
    const DerivativeCheck& c = pc.derivative;
    json out = {{"parts", pc.parts}, {"states", states}, {"directions", c.directions},
                {"rel", c.rel},      {"tol", c.tol},     {"ratio", c.ratio}};
    if (c.skipped > 0) out["skipped"] = c.skipped;
    if (pc.structure_vectors > 0) {
        out["structure_vectors"] = pc.structure_vectors;
        out["structure_rel"] = pc.structure_rel;
        out["structure_ratio"] = pc.structure_ratio;
    }
    out["passed"] = pc.passed();
    return out;
}

// The case-level check "problem Jacobian matches its force" that fails the case when pc (from
// problem_check_json) did not pass; null when it passed.
inline json problem_check_failure(const json& pc) {
    if (pc.value("passed", true)) return nullptr;
    const double ratio = pc.value("ratio", 0.0), sratio = pc.value("structure_ratio", 0.0);
    std::string why;
    if (ratio > 1.0)
        why = "the problem's Jacobian is not its force's derivative: it differs from central "
              "differences by " +
              json(pc.value("rel", 0.0)).dump() + " (relative), beyond the tolerance " +
              json(pc.value("tol", 0.0)).dump();
    if (sratio > 1.0)
        why += std::string(why.empty() ? "" : "; ") +
               "N'D + DN'^T = 0 fails (N is not Hamiltonian for the structure matrix E_n uses): " +
               json(pc.value("structure_rel", 0.0)).dump() + " (relative)";
    return {{"name", "problem Jacobian matches its force"},
            {"metric", "problem_check.ratio"},
            {"method", "(all)"},
            {"op", "le"},
            {"expected", 1},
            {"negative_control", false},
            {"passed", false},
            {"value", std::max(ratio, sratio)},
            {"message", why}};
}

} // namespace dampsym
