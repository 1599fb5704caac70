#include "diagnostics/conformal_symplectic_diagnostic.hpp"

namespace dampsym {

DiagnosticInfo ConformalSymplecticDiagnostic::info() {
    return {.name = "conformal-symplectic",
            .what = "defect of the exact step Jacobian against the conformal symplectic law",
            .needs = {.jacobian_pass = true},
            .metrics = {"max_rel", "last_rel", "max_abs", "last_abs", "max_rel_step",
                        "steps_measured"}};
}

json conformal_symplectic_json(const ConformalSymplecticStats& st) {
    if (!st.applicable()) return {{"reason", to_string(st.applicability)}};
    json out = {{"max_rel", st.max_rel},
                {"last_rel", st.last_rel},
                {"max_abs", st.max_abs},
                {"last_abs", st.last_abs},
                {"max_rel_step", st.max_rel_step},
                {"steps_measured", st.steps_measured},
                {"norm", ConformalSymplecticStats::norm},
                {"status", to_string(st.status)}};
    if (st.status != RunStatus::ok) out["failed_at_step"] = st.failed_step;
    return out;
}

} // namespace dampsym
