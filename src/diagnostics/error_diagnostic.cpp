#include "diagnostics/error_diagnostic.hpp"

#include <algorithm>
#include <limits>
#include <string>

namespace dampsym {

DiagnosticInfo ErrorDiagnostic::info() {
    return {.name = std::string(name),
            .what = "global error against the reference on the output grid and at t_end",
            .needs = {.grid_if_points = true,
                      .streams = true,
                      .reference = true,
                      .ok_run = true,
                      .reference_ok = true},
            .metrics = {"final_abs", "final_rel", "max_abs", "max_rel", "mean_abs",
                        "reference_error_estimate"},
            .reads_reference = true};
}

// Relative errors e_n / ‖z_ref(t_n)‖ are defined only where the reference's norm is a normal
// number above 100× its certified error estimate (below that the reference cannot resolve a
// relative error; a solution decayed to ~0 makes the ratio meaningless): one such point makes
// final_rel / max_rel undefined (null, with the reason), never a huge or a zero ratio.
double ErrorAccumulator::rel_of(double e, double ref_norm, double t, std::string& undefined) const {
    const double ref_floor = 100.0 * ref_error_;
    if (ref_norm >= std::numeric_limits<double>::min() && ref_norm > ref_floor) return e / ref_norm;
    if (undefined.empty())
        undefined = "reference norm " + json(ref_norm).dump() + " at t = " + json(t).dump() +
                    " is below max(DBL_MIN, 100 x its error estimate)";
    return 0.0;
}

void ErrorAccumulator::add(const Eigen::Ref<const Vec>& z, const Eigen::Ref<const Vec>& ref,
                           double t) {
    const double e = (z - ref).norm();
    max_abs_ = std::max(max_abs_, e);
    max_rel_ = std::max(max_rel_, rel_of(e, ref.norm(), t, rel_undefined_));
    sum_abs_ += e;
    ++count_;
}

json ErrorAccumulator::finish(const Eigen::Ref<const Vec>& z_final,
                              const Eigen::Ref<const Vec>& ref_final, double t_end) const {
    const double final_abs = (z_final - ref_final).norm();
    const std::string& grid_undefined = rel_undefined_;
    std::string final_undefined;
    const double final_rel = rel_of(final_abs, ref_final.norm(), t_end, final_undefined);
    const double max_abs = std::max(max_abs_, final_abs);
    const double max_rel = std::max(max_rel_, final_rel);
    // mean over the output grid t_1..t_end: B Fig 3.1's "average absolute error"
    const double mean_abs = count_ ? sum_abs_ / static_cast<double>(count_) : final_abs;
    json out = {{"final_abs", final_abs}, {"final_rel", final_rel},
                {"max_abs", max_abs},     {"mean_abs", mean_abs},
                {"max_rel", max_rel},     {"reference_error_estimate", ref_error_}};
    if (!final_undefined.empty()) set_undefined(out, "final_rel", final_undefined);
    if (!final_undefined.empty() || !grid_undefined.empty())
        set_undefined(out, "max_rel", grid_undefined.empty() ? final_undefined : grid_undefined);
    return out;
}

json error_metrics(const CaseFacts& c, const Mat* grid, const Vec& z_final) {
    ErrorAccumulator acc(c.ref_error);
    const Mat& ref = c.ref;
    if (c.needs_grid && grid) {
        const Mat& g = *grid;
        for (Eigen::Index i = 1; i < g.cols(); ++i) // the initial point is exact
            acc.add(g.col(i), ref.col(i), c.grid_time(i));
    }
    return acc.finish(z_final, ref.col(ref.cols() - 1), c.t_end);
}

} // namespace dampsym
