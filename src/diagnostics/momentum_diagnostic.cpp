#include "diagnostics/momentum_diagnostic.hpp"

#include "core/method.hpp"

#include <cmath>

namespace dampsym {

DiagnosticInfo MomentumDiagnostic::info() {
    return {.name = std::string(name),
            .what = "per-step laws of the linear and angular momentum (B Ex. 1.3, Table 3.1)",
            .requirement = "linear and angular momentum",
            .needs = {.observer = true, .ok_run = true},
            .observed_key = "momentum",
            .metrics =
                [] {
                    std::vector<std::string> out;
                    for (const char* part : {"linear", "angular"})
                        for (const char* stat :
                             {"max_law_res", "last_law_res", "max_law_abs", "scale_initial",
                              "scale_at_max_law_res", "first_factor", "max_factor_dev",
                              "max_table_res", "initial_norm", "undefined_points",
                              "factor_undefined_points"})
                            out.push_back(std::string(part) + "." + stat);
                    return out;
                }(),
            .report_columns = {{.key = "max_law_res",
                                .label = "momentum max law residual / scale (scale)",
                                .per_part = true,
                                .parts = {"linear", "angular"},
                                .scale_key = "scale_at_max_law_res"}}};
}

double table_momentum_factor(unsigned claims, bool constant_gamma, double gh) {
    if (!constant_gamma) return std::numeric_limits<double>::quiet_NaN();
    if (claims & claim_linear_momentum_cayley) return std::exp(-gh) * (2.0 - gh) / (2.0 + gh);
    if (claims & claim_linear_momentum) return std::exp(-2.0 * gh);
    return std::numeric_limits<double>::quiet_NaN();
}

namespace {
json one(const VectorLawStats& s, bool with_table, const char* scale) {
    json o = {{"scale", scale},
              {"scale_initial", s.scale_initial},
              {"max_law_res", s.max_law_res},
              {"last_law_res", s.last_law_res},
              {"max_law_abs", s.max_law_abs},
              {"scale_at_max_law_res", s.scale_at_max},
              {"first_factor", s.first_factor},
              {"max_factor_dev", s.max_factor_dev},
              {"initial_norm", s.initial_norm},
              {"undefined_points", s.undefined_steps},
              {"factor_undefined_points", s.factor_undefined_steps}};
    if (with_table) o["max_table_res"] = s.max_table_res;
    if (s.undefined_steps > 0) {
        const std::string why =
            "scale not a positive normal number at step " + std::to_string(s.first_undefined_step);
        for (const char* key : {"max_law_res", "last_law_res", "max_table_res"})
            if (o.contains(key)) set_undefined(o, key, why);
    }
    if (s.factor_undefined_steps > 0) {
        const std::string why = "|X_n| < 1e-8 x scale at step " +
                                std::to_string(s.first_factor_undefined_step) + " (" +
                                std::to_string(s.factor_undefined_steps) +
                                " steps): the factor X_{n+1}.X_n/|X_n|^2 is round-off there";
        set_undefined(o, "max_factor_dev", why);
        if (s.first_factor_undefined_step == 0) set_undefined(o, "first_factor", why);
    }
    return o;
}
} // namespace

json momentum_metrics(const VectorLawStats& linear, const VectorLawStats& angular, bool linear_law,
                      double table, double law_factor) {
    json ang = one(angular, false, "sum_i |q_i| |p_i|");
    // e.g. Kepler's fixed centre: Σp has no law, only the angular momentum is reported.
    if (!linear_law) return {{"angular", ang}, {"linear", {{"reason", "no linear momentum law"}}}};
    json lin = one(linear, !std::isnan(table), "sum_i |p_i|");
    lin["law_factor"] = law_factor;
    if (!std::isnan(table)) {
        lin["table_factor"] = table;
        lin["table_source"] = "B Table 3.1";
    }
    return {{"linear", lin}, {"angular", ang}};
}

} // namespace dampsym
