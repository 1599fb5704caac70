#include "diagnostics/stability_sweep_diagnostic.hpp"

#include "reference/oscillator_exact.hpp"

#include <algorithm>
#include <cmath>

namespace dampsym {

DiagnosticInfo StabilitySweepDiagnostic::info() {
    return {.name = std::string(name),
            .level = DiagnosticLevel::method,
            .what = "F's condition and power-boundedness over a (gamma, h) grid (F Figs 3.1-3.3)",
            .requirement = "the linear oscillator form",
            .metrics = {"max_boundary_mismatch_cells", "mismatch_points",
                        "violations_omega_gt_gamma", "F_violations", "power_bounded_violations",
                        "max_power_boundary_mismatch_cells", "power_mismatch_points",
                        "first_row.gamma", "first_row.h_F_empirical",
                        "first_row.h_power_unbounded"}};
}

SweepRow sweep_row(const MethodInfo& info, double omega, double g, const std::vector<double>& hs,
                   const OneStepAt& one_step) {
    const OscillatorFormulas f_of = oscillator_formulas(info.id);
    const bool has_formula = f_of.F_condition != nullptr;
    // analytic power-boundedness from the stability function R(z), for RK methods on the full
    // vector field (M = R(hA) on the linear oscillator)
    const ButcherTableau* tableau = plain_tableau(info);
    const auto nh = static_cast<std::int64_t>(hs.size());
    SweepRow row;
    row.first_emp = row.first_formula = row.first_pb = row.first_pb_formula = nh;
    for (std::int64_t i = 0; i < nh; ++i) {
        const double h = hs[static_cast<std::size_t>(i)];
        const OneStepAnalysis a = one_step(omega, g, h);
        row.max_trace_err = std::max(row.max_trace_err,
                                     std::abs(a.half_trace - oscillator_damped_cs(omega, g, h).c));
        if (!a.F_condition) {
            row.first_emp = std::min(row.first_emp, i);
            ++row.f_viol;
            if (omega > g) ++row.violations_inside;
        }
        if (!a.power_bounded) {
            row.first_pb = std::min(row.first_pb, i);
            ++row.pb_viol;
        }
        if (has_formula) {
            const bool fc = f_of.F_condition(omega, g, h);
            if (!fc) row.first_formula = std::min(row.first_formula, i);
            if (fc != a.F_condition) ++row.mismatch;
        }
        if (tableau) {
            const bool pb = rk_power_analysis(*tableau, omega, g, h).power_bounded;
            if (!pb) row.first_pb_formula = std::min(row.first_pb_formula, i);
            if (pb != a.power_bounded) ++row.pb_mismatch;
        }
    }
    return row;
}

json sweep_json(const MethodInfo& info, double omega, const std::vector<double>& gammas,
                const std::vector<double>& hs, const std::vector<SweepRow>& sweep_rows) {
    const OscillatorFormulas f_of = oscillator_formulas(info.id);
    const bool has_formula = f_of.F_condition != nullptr;
    const bool has_pb_formula = plain_tableau(info) != nullptr;
    const auto nh = static_cast<std::int64_t>(hs.size());
    auto h_at = [&](std::int64_t i) {
        return i < nh ? json(hs[static_cast<std::size_t>(i)]) : json(nullptr);
    };
    json rows = json::array();
    std::int64_t mismatch_points = 0, violations_inside = 0, f_viol = 0, pb_viol = 0;
    std::int64_t pb_mismatch_points = 0, max_cells = 0, max_pb_cells = 0;
    for (std::size_t r = 0; r < sweep_rows.size(); ++r) {
        const SweepRow& s = sweep_rows[r];
        f_viol += s.f_viol;
        pb_viol += s.pb_viol;
        violations_inside += s.violations_inside;
        mismatch_points += s.mismatch;
        pb_mismatch_points += s.pb_mismatch;
        json row = {{"gamma", gammas[r]},
                    {"h_F_empirical", h_at(s.first_emp)},
                    {"h_power_unbounded", h_at(s.first_pb)},
                    {"max_half_trace_err", s.max_trace_err}};
        if (has_formula) {
            row["h_F_formula"] = h_at(s.first_formula);
            max_cells = std::max(max_cells, std::abs(s.first_emp - s.first_formula));
        }
        if (has_pb_formula) {
            row["h_power_formula"] = h_at(s.first_pb_formula);
            max_pb_cells = std::max(max_pb_cells, std::abs(s.first_pb - s.first_pb_formula));
        }
        rows.push_back(row);
    }
    json out = {{"omega", omega},
                {"rows", rows},
                {"F_violations", f_viol},
                {"power_bounded_violations", pb_viol},
                {"violations_omega_gt_gamma", violations_inside},
                {"grid", {{"gamma", gammas.size()}, {"h", hs.size()}}}};
    if (!rows.empty()) {
        // the smallest γ of the grid (γ = 0 in the stress maps): where the classical
        // absolute-stability limits (hω < 2, √3, 2√2) can be compared with the grid
        const json& r0 = rows[0];
        out["first_row"] = {{"gamma", r0["gamma"]},
                            {"h_F_empirical", r0["h_F_empirical"]},
                            {"h_power_unbounded", r0["h_power_unbounded"]}};
    }
    if (has_formula) {
        out["max_boundary_mismatch_cells"] = max_cells;
        out["mismatch_points"] = mismatch_points;
        out["formula_source"] = f_of.source;
    }
    if (has_pb_formula) {
        out["max_power_boundary_mismatch_cells"] = max_pb_cells;
        out["power_mismatch_points"] = pb_mismatch_points;
        out["power_formula_source"] = "stability function R(z) of the tableau at h*lambda";
    }
    return out;
}

} // namespace dampsym
