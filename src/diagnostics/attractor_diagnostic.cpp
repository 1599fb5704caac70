#include "diagnostics/attractor_diagnostic.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace dampsym {

DiagnosticInfo AttractorDiagnostic::info() {
    return {.name = std::string(name),
            .what = "statistics of the problem's probe over the second half of the run (B Fig "
                    "5.10): distribution, batch-means error, period of mean crossings",
            .requirement = "a probe of the state (probe(z): the driven NLS's |psi(0, t)|)",
            .needs = {.grid = true, .ok_run = true},
            .metrics = {"probe", "from", "points", "mean", "std", "min", "max", "q10", "q50", "q90",
                        "mean_se", "mean_rse", "crossings", "period", "period_spread"}};
}

namespace {
// The p-quantile of sorted v, linear between order statistics (numpy's default).
double quantile(const std::vector<double>& v, double p) {
    const double pos = p * static_cast<double>(v.size() - 1);
    const auto i = static_cast<std::size_t>(std::floor(pos));
    if (i + 1 >= v.size()) return v.back();
    return v[i] + (pos - static_cast<double>(i)) * (v[i + 1] - v[i]);
}
} // namespace

namespace {

constexpr int attractor_batches = 10;

// The standard error of the mean from batch means: 10 consecutive batches, the first
// (size % 10) one point longer.
double batch_mean_se(const std::vector<double>& s) {
    constexpr int batches = attractor_batches;
    std::vector<double> bm;
    std::size_t start = 0;
    for (int b = 0; b < batches; ++b) {
        const std::size_t len =
            s.size() / batches + (static_cast<std::size_t>(b) < s.size() % batches);
        double bs = 0.0;
        for (std::size_t i = start; i < start + len; ++i) bs += s[i];
        bm.push_back(bs / static_cast<double>(len));
        start += len;
    }
    double bmean = 0.0, bvar = 0.0;
    for (double v : bm) bmean += v / batches;
    for (double v : bm) bvar += (v - bmean) * (v - bmean);
    return std::sqrt(bvar / (batches - 1) / batches);
}

// The period from the upward crossings of the mean level (times t of the samples s) and the
// spread of the crossing intervals; undefined with fewer than three crossings.
void crossing_period(const std::vector<double>& t, const std::vector<double>& s, double mean,
                     json& out) {
    std::vector<double> tc;
    for (std::size_t i = 0; i + 1 < s.size(); ++i)
        if (s[i] < mean && s[i + 1] >= mean)
            tc.push_back(t[i] + (mean - s[i]) / (s[i + 1] - s[i]) * (t[i + 1] - t[i]));
    out["crossings"] = static_cast<std::int64_t>(tc.size());
    if (tc.size() < 3) {
        const char* why = "fewer than three upward crossings of the mean in the window";
        set_undefined(out, "period", why);
        set_undefined(out, "period_spread", why);
        return;
    }
    double lo = tc[1] - tc[0], hi = lo;
    for (std::size_t i = 1; i + 1 < tc.size(); ++i) {
        lo = std::min(lo, tc[i + 1] - tc[i]);
        hi = std::max(hi, tc[i + 1] - tc[i]);
    }
    const double period = (tc.back() - tc.front()) / static_cast<double>(tc.size() - 1);
    out["period"] = period;
    out["period_spread"] = (hi - lo) / period;
}

} // namespace

json attractor_metrics(const CaseFacts& c, const Mat& g, std::string_view probe_name,
                       const std::function<double(const Vec&)>& probe) {
    const double from = c.t0 + 0.5 * (c.t_end - c.t0);
    std::vector<double> t, s;
    for (Eigen::Index i = 1; i < g.cols(); ++i) {
        const double ti = c.grid_time(i);
        if (ti < from) continue;
        t.push_back(ti);
        s.push_back(probe(g.col(i)));
    }
    json out = {{"probe", std::string(probe_name)},
                {"from", from},
                {"points", static_cast<std::int64_t>(s.size())}};
    if (s.size() < 2 * attractor_batches) {
        const char* why = "needs at least 20 output points in the second half of the run";
        for (const char* k : {"mean", "std", "min", "max", "q10", "q50", "q90", "mean_se",
                              "mean_rse", "crossings", "period", "period_spread"})
            set_undefined(out, k, why);
        return out;
    }
    const double n = static_cast<double>(s.size());
    double sum = 0.0;
    for (double v : s) sum += v;
    const double mean = sum / n;
    double var = 0.0;
    for (double v : s) var += (v - mean) * (v - mean);
    const double sd = std::sqrt(var / n);
    std::vector<double> sorted = s;
    std::sort(sorted.begin(), sorted.end());
    out["mean"] = mean;
    out["std"] = sd;
    out["min"] = sorted.front();
    out["max"] = sorted.back();
    out["q10"] = quantile(sorted, 0.1);
    out["q50"] = quantile(sorted, 0.5);
    out["q90"] = quantile(sorted, 0.9);
    const double se = batch_mean_se(s);
    out["mean_se"] = se;
    if (mean != 0.0)
        out["mean_rse"] = se / std::abs(mean);
    else
        set_undefined(out, "mean_rse", "the probe's mean is 0");
    if (!(sd > 1e-12 * std::max(std::abs(mean), 1e-300))) {
        out["crossings"] = 0;
        const char* why = "the probe is constant over the window (std below 1e-12 of the mean)";
        set_undefined(out, "period", why);
        set_undefined(out, "period_spread", why);
        return out;
    }
    crossing_period(t, s, mean, out);
    return out;
}

} // namespace dampsym
