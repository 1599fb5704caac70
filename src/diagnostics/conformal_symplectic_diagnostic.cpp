#include "diagnostics/conformal_symplectic_diagnostic.hpp"

namespace dampsym {

DiagnosticInfo ConformalSymplecticDiagnostic::info() {
    return {.name = "conformal-symplectic",
            .what = "defect of the exact step Jacobian against the conformal symplectic law",
            .needs = {.jacobian_pass = true},
            .metrics = {"max_rel", "last_rel", "max_abs", "last_abs", "max_rel_step",
                        "steps_measured", "rel_undefined_steps"}};
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
                {"jacobian", st.jacobian},
                {"status", to_string(st.status)}};
    if (st.status != RunStatus::ok) out["failed_at_step"] = st.failed_step;
    if (st.rel_undefined_steps > 0) {
        out["rel_undefined_steps"] = st.rel_undefined_steps;
        if (st.max_rel_step == 0)
            for (const char* key : {"max_rel", "last_rel"})
                set_undefined(out, key,
                              "e^{-2 dGamma} per step is below the double range "
                              "(dGamma > ~354 per step) at every measured step");
    }
    return out;
}

} // namespace dampsym
