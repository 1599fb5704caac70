#include "diagnostics/error_diagnostic.hpp"

#include <algorithm>

namespace dampsym {

DiagnosticInfo ErrorDiagnostic::info() {
    return {
        .name = "error",
        .what = "global error against the reference on the output grid and at t_end",
        .needs = {.grid_if_points = true, .reference = true, .ok_run = true, .reference_ok = true},
        .observer_part = "grid",
        .metrics = {"final_abs", "final_rel", "max_abs", "max_rel", "mean_abs",
                    "reference_error_estimate"},
        .reads_reference = true};
}

// Relative errors e_n / ‖z_ref(t_n)‖ are defined only where the reference's norm is a normal
// number above 100× its certified error estimate (below that the reference cannot resolve a
// relative error; a solution decayed to ~0 makes the ratio meaningless): one such point makes
// final_rel / max_rel undefined (null, with the reason), never a huge or a zero ratio.
json error_metrics(const CaseFacts& c, const Mat* grid, const Vec& z_final) {
    double max_abs = 0.0, max_rel = 0.0, sum_abs = 0.0;
    Eigen::Index count = 0;
    const double ref_floor = 100.0 * c.ref_error;
    std::string rel_undefined;
    auto rel_of = [&](double e, double ref_norm, double t) {
        if (ref_norm >= std::numeric_limits<double>::min() && ref_norm > ref_floor)
            return e / ref_norm;
        if (rel_undefined.empty())
            rel_undefined = "reference norm " + json(ref_norm).dump() +
                            " at t = " + json(t).dump() +
                            " is below max(DBL_MIN, 100 x its error estimate)";
        return 0.0;
    };
    const Mat& ref = c.ref;
    if (c.needs_grid && grid) {
        const Mat& g = *grid;
        for (Eigen::Index i = 1; i < g.cols(); ++i) { // the initial point is exact
            const double e = (g.col(i) - ref.col(i)).norm();
            max_abs = std::max(max_abs, e);
            max_rel = std::max(max_rel, rel_of(e, ref.col(i).norm(), c.grid_time(i)));
            sum_abs += e;
            ++count;
        }
    }
    const Vec ref_final = ref.col(ref.cols() - 1);
    const double final_abs = (z_final - ref_final).norm();
    const std::string grid_undefined = rel_undefined;
    rel_undefined.clear();
    const double final_rel = rel_of(final_abs, ref_final.norm(), c.t_end);
    const std::string final_undefined = rel_undefined;
    max_abs = std::max(max_abs, final_abs);
    max_rel = std::max(max_rel, final_rel);
    // mean over the output grid t_1..t_end: B Fig 3.1's "average absolute error"
    const double mean_abs = count ? sum_abs / static_cast<double>(count) : final_abs;
    json out = {{"final_abs", final_abs}, {"final_rel", final_rel},
                {"max_abs", max_abs},     {"mean_abs", mean_abs},
                {"max_rel", max_rel},     {"reference_error_estimate", c.ref_error}};
    if (!final_undefined.empty()) set_undefined(out, "final_rel", final_undefined);
    if (!final_undefined.empty() || !grid_undefined.empty())
        set_undefined(out, "max_rel", grid_undefined.empty() ? final_undefined : grid_undefined);
    return out;
}

} // namespace dampsym
