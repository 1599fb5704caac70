#include "diagnostics/order_fit.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

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

namespace {

// Mean and largest deviation from it of local_orders[i, j).
struct Spread {
    double mean, spread;
};
Spread spread_of(const std::vector<double>& lo, std::size_t i, std::size_t j) {
    double mean = 0.0;
    for (std::size_t k = i; k < j; ++k) mean += lo[k];
    mean /= static_cast<double>(j - i);
    double spread = 0.0;
    for (std::size_t k = i; k < j; ++k) spread = std::max(spread, std::abs(lo[k] - mean));
    return {mean, spread};
}

bool consistent(const Spread& s) {
    return s.spread <= std::max(0.1 * std::abs(s.mean), 0.05) && s.mean >= 0.5;
}

std::string local_orders_text(const std::vector<double>& lo) {
    std::string out;
    char buf[32];
    for (double v : lo) {
        std::snprintf(buf, sizeof buf, "%.3g", v);
        out += (out.empty() ? "" : ", ") + std::string(buf);
    }
    return out;
}

// Why no window of >= 3 points ends at the finest usable step (n >= 3 usable points).
void fail_at_finest(OrderFit& fit) {
    const auto& lo = fit.local_orders;
    const double finest = lo.back(), before = lo[lo.size() - 2];
    fit.status = finest < 0.5      ? "no convergence at the finest steps"
                 : finest < before ? "order drops at small h"
                                   : "order rises at small h";
    fit.reason = "the local orders (coarse to fine) " + local_orders_text(lo) +
                 " do not agree at the finest steps above the floor";
}

} // namespace

std::string finest_steps_disagree(double slope, double finest_local_order, double tol) {
    if (!(std::abs(finest_local_order - slope) > tol)) return {};
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "order %s at small h: local order %.3g between the two finest steps against the "
                  "fitted slope %.3g, beyond the tolerance %.3g",
                  finest_local_order < slope ? "drops" : "rises", finest_local_order, slope, tol);
    return buf;
}

OrderFit fit_order(std::vector<OrderPoint> points, double floor, double solution_scale) {
    OrderFit fit;
    std::sort(points.begin(), points.end(),
              [](const OrderPoint& a, const OrderPoint& b) { return a.h > b.h; });
    const double large = order_fit_large_fraction * solution_scale;
    std::vector<OrderPoint> usable;
    for (const auto& p : points) {
        if (!std::isfinite(p.error) || !(p.error > 0.0))
            fit.dropped.push_back({p.h, p.error, "error not finite and positive"});
        else if (!(p.error > floor))
            fit.dropped.push_back({p.h, p.error, "at or below the floor"});
        else if (p.error >= large)
            fit.dropped.push_back({p.h, p.error, "error not small against the solution"});
        else
            usable.push_back(p);
    }
    const std::size_t n = usable.size();
    for (std::size_t i = 0; i + 1 < n; ++i)
        fit.local_orders.push_back(std::log(usable[i].error / usable[i + 1].error) /
                                   std::log(usable[i].h / usable[i + 1].h));
    if (n < 3) {
        fit.status = "too few points";
        fit.reason = "fewer than 3 usable points (" + std::to_string(n) + ")";
        return fit;
    }
    // The longest consistent window [first, n − 1] ending at the finest usable step.
    std::size_t first = n;
    for (std::size_t i = n - 2; i-- > 0;)
        if (consistent(spread_of(fit.local_orders, i, n - 1))) first = i;
    if (first == n) {
        fail_at_finest(fit);
        return fit;
    }
    std::vector<double> x, y;
    for (std::size_t k = 0; k < n; ++k) {
        if (k < first) {
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
