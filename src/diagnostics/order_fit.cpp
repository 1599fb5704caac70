#include "diagnostics/order_fit.hpp"

#include <algorithm>
#include <cmath>

namespace dampsym {

LineFit least_squares(const std::vector<double>& x, const std::vector<double>& y) {
    const double n = static_cast<double>(x.size());
    double mx = 0.0, my = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        mx += x[i];
        my += y[i];
    }
    mx /= n;
    my /= n;
    double sxx = 0.0, sxy = 0.0, syy = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        sxx += (x[i] - mx) * (x[i] - mx);
        sxy += (x[i] - mx) * (y[i] - my);
        syy += (y[i] - my) * (y[i] - my);
    }
    const double b = sxx > 0.0 ? sxy / sxx : 0.0;
    const double r2 = (sxx > 0.0 && syy > 0.0) ? (sxy * sxy) / (sxx * syy) : 1.0;
    return {b, my - b * mx, r2};
}

OrderFit fit_order(std::vector<OrderPoint> points, double floor) {
    OrderFit fit;
    std::sort(points.begin(), points.end(),
              [](const OrderPoint& a, const OrderPoint& b) { return a.h > b.h; });
    std::vector<OrderPoint> usable;
    for (const auto& p : points) {
        if (!std::isfinite(p.error) || !(p.error > 0.0))
            fit.dropped.push_back({p.h, p.error, "error not finite and positive"});
        else if (!(p.error > floor))
            fit.dropped.push_back({p.h, p.error, "at or below the floor"});
        else
            usable.push_back(p);
    }
    const std::size_t n = usable.size();
    for (std::size_t i = 0; i + 1 < n; ++i)
        fit.local_orders.push_back(std::log(usable[i].error / usable[i + 1].error) /
                                   std::log(usable[i].h / usable[i + 1].h));
    if (n < 3) {
        fit.reason = "fewer than 3 usable points (" + std::to_string(n) + ")";
        return fit;
    }
    // Longest consistent contiguous window [i, j] (>= 3 points: >= 2 local orders).
    std::size_t best_i = 0, best_j = 0;
    double best_spread = 0.0;
    bool found = false;
    for (std::size_t i = 0; i + 2 < n; ++i) {
        for (std::size_t j = i + 2; j < n; ++j) {
            double mean = 0.0;
            for (std::size_t k = i; k < j; ++k) mean += fit.local_orders[k];
            mean /= static_cast<double>(j - i);
            double spread = 0.0;
            for (std::size_t k = i; k < j; ++k)
                spread = std::max(spread, std::abs(fit.local_orders[k] - mean));
            if (spread > std::max(0.1 * std::abs(mean), 0.05)) continue;
            if (mean < 0.5) continue; // not converging: a round-off or reference plateau
            const std::size_t len = j - i + 1;
            const std::size_t best_len = best_j - best_i + 1;
            if (!found || len > best_len || (len == best_len && spread <= best_spread)) {
                found = true;
                best_i = i;
                best_j = j;
                best_spread = spread;
            }
        }
    }
    if (!found) {
        fit.reason = "no 3 consecutive usable points with consistent local orders";
        return fit;
    }
    std::vector<double> x, y;
    for (std::size_t k = 0; k < n; ++k) {
        if (k < best_i || k > best_j) {
            fit.dropped.push_back({usable[k].h, usable[k].error, "outside the asymptotic window"});
            continue;
        }
        x.push_back(std::log(usable[k].h));
        y.push_back(std::log(usable[k].error));
        fit.window_h.push_back(usable[k].h);
    }
    const LineFit lf = least_squares(x, y);
    fit.ok = true;
    fit.slope = lf.slope;
    fit.intercept = lf.intercept;
    fit.r2 = lf.r2;
    return fit;
}

} // namespace dampsym
