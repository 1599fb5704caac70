#include "diagnostics/invariants_diagnostic.hpp"

namespace dampsym {

DiagnosticInfo InvariantsDiagnostic::info() {
    return {.name = std::string(name),
            .what = "per-step and global conformal laws of the problem's invariants",
            .requirement = "conformal invariants",
            .needs = {.observer = true, .ok_run = true},
            .observed_key = "invariants",
            .metrics = {"max_step_res", "last_step_res", "max_step_abs", "scale_initial",
                        "scale_at_max_step_res", "max_global_res", "global_res_slope",
                        "max_global_ratio_dev", "ratio_dev_slope", "undefined_points"},
            .per_invariant = true,
            .report_columns = {{.key = "max_step_res",
                                .label = "invariant max step residual / scale (scale)",
                                .per_part = true,
                                .scale_key = "scale_at_max_step_res"}}};
}

json invariant_metrics(const std::vector<InvariantStats>& stats,
                       const std::vector<std::string_view>& names,
                       const std::vector<std::string_view>& scale_defs,
                       const std::vector<double>& initial) {
    json inv = json::object();
    for (std::size_t k = 0; k < names.size(); ++k) {
        const InvariantStats& s = stats[k];
        json o = {
            {"scale", std::string(scale_defs[k])},     {"scale_initial", s.scale_initial},
            {"max_step_res", s.max_step_res},          {"last_step_res", s.last_step_res},
            {"max_step_abs", s.max_step_abs},          {"scale_at_max_step_res", s.scale_at_max},
            {"max_global_res", s.max_global_res},      {"global_res_slope", s.global_res_slope()},
            {"max_global_ratio_dev", s.max_ratio_dev}, {"ratio_dev_slope", s.ratio_dev_slope()},
            {"undefined_points", s.undefined_steps}};
        if (!s.ratio_defined) {
            const std::string why =
                "at step " + std::to_string(s.first_unresolved_ratio) +
                " the round-off eps S(z_n) / |e^{-2 Gamma} I_0| of e^{2 Gamma} I_n / I_0 "
                "exceeds max(1e-8, 1e-2 |ratio - 1|) (I_0 = " +
                json(initial[k]).dump() + ", scale S(z_0) = " + json(s.scale_initial).dump() +
                "); read max_global_res";
            set_undefined(o, "max_global_ratio_dev", why);
            set_undefined(o, "ratio_dev_slope", why);
        }
        if (s.undefined_steps > 0) {
            const std::string why = "scale not a positive normal number (state ~0 or not "
                                    "finite) at step " +
                                    std::to_string(s.first_undefined_step) + " and " +
                                    std::to_string(s.undefined_steps - 1) + " more";
            for (const char* key :
                 {"max_step_res", "last_step_res", "max_global_res", "global_res_slope"})
                set_undefined(o, key, why);
            // no step with a defined residual (its scale is positive when one is): the numerator
            // and the scale "at the maximum" are then those of no step, not 0
            if (s.scale_at_max == 0.0)
                for (const char* key : {"max_step_abs", "scale_at_max_step_res"})
                    set_undefined(o, key, why);
        }
        inv[std::string(names[k])] = o;
    }
    return inv;
}

} // namespace dampsym
