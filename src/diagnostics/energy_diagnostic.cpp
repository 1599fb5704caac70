#include "diagnostics/energy_diagnostic.hpp"

#include "diagnostics/order_fit.hpp"

#include <algorithm>
#include <cmath>

namespace dampsym {

DiagnosticInfo EnergyDiagnostic::info() {
    return {.name = std::string(name),
            .what = "energy changes and, with a reference, energy errors on the output grid",
            .requirement = "an energy",
            .needs = {.grid = true, .ok_run = true, .reference_ok = true},
            .metrics = {"max_abs_error", "final_abs_error", "drift_slope", "error_res_slope",
                        "max_abs_change", "change_slope", "max_change_res", "change_res_slope",
                        "growth_ratio", "scale_initial"},
            .reads_reference = true,
            .report_columns = {{.key = "max_abs_error", .label = "max |H_exact−H|"},
                               {.key = "drift_slope", .label = "H error slope"},
                               {.key = "max_abs_change", .label = "max |H−H₀|"}}};
}

// Energy changes H_n − H_0 on the scale S_H(z_0) and errors H_exact − H_n on S_H(z_ref(t_n)),
// S_H the problem's energy_scale (T + |V|, or H for a definite energy; docs/conventions.md),
// so that an energy crossing zero does not make a ratio blow up.
json energy_metrics(const CaseFacts& c, const Mat& g, const StateFunction& energy,
                    const StateFunction& energy_scale) {
    std::vector<double> t, err, res, change;
    const double e0 = energy(g.col(0));
    const double s0 = energy_scale(g.col(0));
    const bool with_ref = c.reference_ok && c.ref.cols() == g.cols();
    std::vector<double> change_res;
    double max_err = 0.0, max_change = 0.0, max_change_res = 0.0;
    std::string err_undefined;
    for (Eigen::Index i = 0; i < g.cols(); ++i) {
        const double en = energy(g.col(i));
        t.push_back(c.grid_time(i));
        if (with_ref) {
            const double exact = energy(c.ref.col(i));
            const double scale = energy_scale(c.ref.col(i));
            err.push_back(exact - en); // H_exact − H_approx (F Fig 4.3)
            if (!scale_defined(scale) && err_undefined.empty())
                err_undefined = "energy scale of the reference is " + json(scale).dump() +
                                " at t = " + json(t.back()).dump();
            res.push_back(scale_defined(scale) ? err.back() / scale : 0.0);
            max_err = std::max(max_err, std::abs(err.back()));
        }
        change.push_back(en - e0);
        change_res.push_back(scale_defined(s0) ? (en - e0) / s0 : 0.0);
        max_change = std::max(max_change, std::abs(change.back()));
        max_change_res = std::max(max_change_res, std::abs(change_res.back()));
    }
    // Growth of |H_n − H_0| between the two halves of the run: ≈ 1 when the error is bounded,
    // ≈ 2 when it grows linearly (HLW Table 2.1).
    double first_half = 0.0, second_half = 0.0;
    const Eigen::Index mid = g.cols() / 2;
    for (Eigen::Index i = 0; i < g.cols(); ++i)
        (i <= mid ? first_half : second_half) = std::max(
            i <= mid ? first_half : second_half, std::abs(change[static_cast<std::size_t>(i)]));
    json out = {{"max_abs_change", max_change},
                {"change_slope", least_squares(t, change).slope},
                {"scale_initial", s0},
                {"max_change_res", max_change_res},
                {"change_res_slope", least_squares(t, change_res).slope}};
    if (first_half > 0.0)
        out["growth_ratio"] = second_half / first_half;
    else
        set_undefined(out, "growth_ratio", "|H_n - H_0| = 0 on the first half");
    if (!scale_defined(s0)) {
        const std::string why = "energy scale at t0 is " + json(s0).dump();
        set_undefined(out, "max_change_res", why);
        set_undefined(out, "change_res_slope", why);
    }
    if (with_ref) {
        out["max_abs_error"] = max_err;
        out["final_abs_error"] = std::abs(err.back());
        out["drift_slope"] = least_squares(t, err).slope;
        if (err_undefined.empty())
            out["error_res_slope"] = least_squares(t, res).slope;
        else
            set_undefined(out, "error_res_slope", err_undefined);
    }
    return out;
}

} // namespace dampsym
