// The case's "measures" (docs/case-keys.md): the error of the chosen components, or of the energy,
// absolute or relative to the reference pointwise, reduced over the output grid t_1..t_end (the
// initial point is exact) as the paper states it.
#include "diagnostics/order_fit.hpp"
#include "harness/run/case_run.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace dampsym::detail {

namespace {

// The two statistics that are not running sums: "final" (the last point) and "growth" (a fit
// over every point). max, mean and rms are only the running reductions of add() and finish(): they
// need an output grid of >= 2 points (case_expect.cpp parse_over), so every such run feeds them.
double reduce(const MeasureSpec& m, const std::vector<double>& t, const std::vector<double>& v,
              double t0, bool& produced) {
    produced = true;
    if (m.over != MeasureStat::growth) return v.back();
    // log–log slope of the running maximum against t − t0: ≈ 0 for a bounded error, 1 for linear
    // growth (O(th)), 2 for quadratic growth (O(t²h)).
    std::vector<double> lx, ly;
    double running = 0.0;
    for (std::size_t i = 0; i < v.size(); ++i) {
        running = std::max(running, v[i]);
        if (t[i] >= m.growth_from && running > 0.0) {
            lx.push_back(std::log(t[i] - t0));
            ly.push_back(std::log(running));
        }
    }
    if (lx.size() < 3) { // not produced: a check on it fails, naming it
        produced = false;
        return 0.0;
    }
    return least_squares(lx, ly).slope;
}

} // namespace

MeasureAccumulator::MeasureAccumulator(const CaseSpec& c, const CaseFacts& f,
                                       std::function<double(const Vec&)> energy,
                                       std::function<double(const Vec&)> energy_scale)
    : c_(c), f_(f), energy_(std::move(energy)), energy_scale_(std::move(energy_scale)),
      stats_(c.measures.size()) {}

double MeasureAccumulator::pointwise(const MeasureSpec& m, const Vec& u, const Vec& ref) const {
    double e = 0.0, scale = 1.0, floor = 1e-300;
    if (m.quantity == MeasureQuantity::energy_error) {
        if (energy_) {
            const double exact = energy_(ref);
            e = std::abs(energy_(u) - exact);
            scale = std::abs(exact);
            // The paper's |H − H_ref|/|H_ref| is kept, but where |H_ref| is within 100 ulps of its
            // energy scale S_H (T + |V|) of zero, H_ref is round-off and the ratio is undefined
            // (docs/conventions.md, "Law residuals and their scales").
            if (energy_scale_)
                floor = std::max(floor, 100.0 * std::numeric_limits<double>::epsilon() *
                                            energy_scale_(ref));
        }
    } else {
        e = (u.segment(m.first, m.count) - ref.segment(m.first, m.count)).norm();
        scale = ref.segment(m.first, m.count).norm();
        // as error.max_rel: the reference cannot resolve a relative error below 100 times its
        // certified error estimate
        floor = std::max(floor, 100.0 * f_.ref_error);
    }
    // relative to a reference that is not resolved: undefined (never a huge ratio)
    if (m.relative && !(scale > floor)) return std::numeric_limits<double>::quiet_NaN();
    return m.relative ? e / scale : e;
}

// max, mean and rms as running reductions, fed by a streamed or a stored grid alike (the one
// implementation of each); growth keeps its points (never streamed: grid_plan, harness/limits.hpp).
void MeasureAccumulator::add(const Vec& z, const Vec& ref, double t) {
    fed_ = true;
    for (std::size_t k = 0; k < c_.measures.size(); ++k) {
        const MeasureSpec& m = c_.measures[k];
        if (m.over == MeasureStat::final_value) continue;
        Stat& s = stats_[k];
        const double e = pointwise(m, z, ref);
        if (std::isnan(e)) s.undefined = true;
        switch (m.over) {
        case MeasureStat::max:
            if (s.count == 0 || s.max < e) s.max = e; // as std::max_element: the first largest
            break;
        case MeasureStat::mean:
            s.sum += e;
            break;
        case MeasureStat::rms:
            s.sum += e * e;
            break;
        case MeasureStat::growth:
            s.t.push_back(t);
            s.v.push_back(e);
            break;
        case MeasureStat::final_value:
            break;
        }
        ++s.count;
    }
}

json MeasureAccumulator::finish(const Vec& z_final, const Vec& ref_final) const {
    json out = json::object();
    for (std::size_t k = 0; k < c_.measures.size(); ++k) {
        const MeasureSpec& m = c_.measures[k];
        const Stat& s = stats_[k];
        bool produced = true;
        double x = 0.0;
        if (m.over != MeasureStat::final_value && m.over != MeasureStat::growth) {
            if (s.count == 0) // parse_over gives max, mean and rms >= 2 grid points
                throw std::logic_error("measure '" + m.name + "' over an empty output grid");
            // One undefined point makes the whole statistic undefined.
            if (s.undefined) {
                x = std::numeric_limits<double>::quiet_NaN();
            } else if (m.over == MeasureStat::max) {
                x = s.max;
            } else {
                x = s.sum / static_cast<double>(s.count);
                if (m.over == MeasureStat::rms) x = std::sqrt(x);
            }
        } else {
            std::vector<double> t, v;
            if (fed_ && m.over == MeasureStat::growth) {
                t = s.t;
                v = s.v;
            } else {
                t.push_back(c_.t_end);
                v.push_back(pointwise(m, z_final, ref_final));
            }
            // One undefined point makes the whole statistic undefined (max_element and the sums
            // would otherwise skip or propagate it depending on its position).
            const bool any_undefined =
                std::any_of(v.begin(), v.end(), [](double e) { return std::isnan(e); });
            x = any_undefined ? std::numeric_limits<double>::quiet_NaN()
                              : reduce(m, t, v, c_.t0, produced);
        }
        if (!produced) continue;
        if (!std::isfinite(x)) {
            out[m.name] = nullptr;
            out["undefined"][m.name] =
                m.quantity == MeasureQuantity::energy_error
                    ? "relative to a reference energy within round-off of 0 at some point"
                    : "relative to a reference of norm 0 at some point";
            continue;
        }
        out[m.name] = x;
    }
    return out;
}

json measure_metrics(const CaseSpec& c, const CaseFacts& f, const Mat* grid, const Vec& z_final,
                     const std::function<double(const Vec&)>& energy,
                     const std::function<double(const Vec&)>& energy_scale) {
    MeasureAccumulator acc(c, f, energy, energy_scale);
    if (f.needs_grid && grid) {
        const Mat& g = *grid;
        for (Eigen::Index i = 1; i < g.cols(); ++i)
            acc.add(Vec(g.col(i)), Vec(f.ref.col(i)), f.grid_time(i));
    }
    return acc.finish(z_final, Vec(f.ref.col(f.ref.cols() - 1)));
}

} // namespace dampsym::detail
