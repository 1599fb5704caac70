#include "diagnostics/local_error_diagnostic.hpp"

namespace dampsym {

DiagnosticInfo LocalErrorDiagnostic::info() {
    return {.name = std::string(name),
            .what = "one-step error against the exact solution at t0 + h (B Fig 3.2)",
            .requirement = "an exact solution",
            .metrics = {"abs", "rel"}};
}

json local_error_json(const Vec* z, const Vec& exact) {
    if (!z) return {{"reason", "solve failed"}};
    const double e = (*z - exact).norm();
    json out = {{"abs", e}};
    if (scale_defined(exact.norm()))
        out["rel"] = e / exact.norm();
    else
        set_undefined(out, "rel", "exact solution at t0 + h has norm 0");
    return out;
}

} // namespace dampsym
