#include "diagnostics/dissipation_drift_diagnostic.hpp"

#include "diagnostics/order_fit.hpp"

#include <algorithm>
#include <cmath>

namespace dampsym {

DiagnosticInfo DissipationDriftDiagnostic::info() {
    return {.name = std::string(name),
            .what = "d(t) = ln(max q) + Gamma(t) at the maxima of q (F(4.4)), and its reference",
            .requirement = "one degree of freedom in separable form",
            .needs = {.reference_grid = true, .observer = true, .ok_run = true},
            .observed_key = "maxima",
            .metrics = {"slope", "range", "maxima", "maxima_nonpositive", "slope_minus_reference",
                        "max_abs_diff_reference", "maxima_count_diff", "reference.slope"},
            .report_columns = {{.key = "slope", .label = "d(t) slope"},
                               {.key = "maxima", .label = "maxima"}}};
}

namespace {
// d(t) at the positive maxima; a maximum of q at or below 0 has no d(t) (over-damped motion):
// then every d(t) metric is undefined, with the count as the reason.
json drift_of(const std::vector<Maximum>& mx, std::int64_t nonpositive) {
    json out = {{"maxima", mx.size()}, {"maxima_nonpositive", nonpositive}};
    if (nonpositive > 0) {
        const std::string why =
            std::to_string(nonpositive) + " maxima of q are <= 0, where ln(max q) is undefined";
        for (const char* key : {"slope", "range"}) set_undefined(out, key, why);
        return out;
    }
    if (mx.size() < 3) return out; // slope missing: a check on it fails with that reason
    std::vector<double> t, d;
    double lo = mx[0].d, hi = mx[0].d;
    for (const auto& m : mx) {
        t.push_back(m.t);
        d.push_back(m.d);
        lo = std::min(lo, m.d);
        hi = std::max(hi, m.d);
    }
    out["slope"] = least_squares(t, d).slope;
    out["range"] = hi - lo;
    out["first"] = {mx.front().t, mx.front().d};
    out["last"] = {mx.back().t, mx.back().d};
    return out;
}
} // namespace

json drift_metrics(const MaximaSeries& run, const std::optional<MaximaSeries>& ref_series) {
    const std::vector<Maximum>& mx = run.maxima;
    json out = drift_of(mx, run.nonpositive);
    if (ref_series) {
        const auto& rm = ref_series->maxima;
        const json ref = drift_of(rm, ref_series->nonpositive);
        out["reference"] = ref;
        if (ref.contains("slope") && out.contains("slope") && ref["slope"].is_number() &&
            out["slope"].is_number())
            out["slope_minus_reference"] = out["slope"].get<double>() - ref["slope"].get<double>();
        double max_diff = 0.0;
        const std::size_t k = std::min(mx.size(), rm.size());
        for (std::size_t i = 0; i < k; ++i)
            max_diff = std::max(max_diff, std::abs(mx[i].d - rm[i].d));
        out["max_abs_diff_reference"] = max_diff;
        out["maxima_count_diff"] =
            static_cast<std::int64_t>(mx.size()) - static_cast<std::int64_t>(rm.size());
    }
    return out;
}

} // namespace dampsym
