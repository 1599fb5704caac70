#include "diagnostics/conformal_symplectic_diagnostic.hpp"

#include <string>

namespace dampsym {

DiagnosticInfo ConformalSymplecticDiagnostic::info() {
    return {.name = std::string(name),
            .what = "defect of the exact step Jacobian against the conformal symplectic law",
            .needs = {.jacobian_pass = true},
            .metrics = {"max_rel", "last_rel", "max_abs", "last_abs", "max_rel_step",
                        "steps_measured", "rel_undefined_steps", "jacobian_check_rel",
                        "jacobian_check_tol", "jacobian_check_ratio", "jacobian_check_states"}};
}

namespace {

// The check of Ψ against central differences of the step (conformal_symplectic.hpp). A mismatch
// makes the pass's status "jacobian-mismatch" (E_n of a Ψ that is not the step's derivative
// verifies nothing): every check on these metrics then fails with it. A pass that diverged or
// failed keeps that status.
void jacobian_check_json(const ConformalSymplecticStats& st, json& out) {
    out["jacobian_check"] = st.jacobian_check_mode;
    if (std::string(st.jacobian_check_mode) != "central-differences") return;
    const DerivativeCheck& c = st.jacobian_check;
    out["jacobian_check_states"] = c.states;
    out["jacobian_check_directions"] = c.directions;
    if (c.skipped > 0) out["jacobian_check_skipped"] = c.skipped;
    if (c.directions == 0) return;
    out["jacobian_check_rel"] = c.rel;
    out["jacobian_check_tol"] = c.tol;
    out["jacobian_check_ratio"] = c.ratio;
    if (c.mismatch() && st.status == RunStatus::ok) {
        out["status"] = "jacobian-mismatch";
        out["message"] = "the step Jacobian is not the step's derivative: it differs from central "
                         "differences of the step by " +
                         json(c.rel).dump() + " (relative), beyond the tolerance " +
                         json(c.tol).dump();
    }
}

} // namespace

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
    jacobian_check_json(st, out);
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
