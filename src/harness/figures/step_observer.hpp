// The orbit samples of a run's figures (harness/figures/series.hpp; the per-step law series come
// from the diagnostics' own parts in the Recorder, diagnostics/observer_part.hpp). Observes the
// measured run beside its Recorder (RunObserver), only with `dampsym run --figures`.
#pragma once

#include "core/integrate.hpp"
#include "core/problem_concepts.hpp"
#include "diagnostics/capabilities.hpp"
#include "diagnostics/metric_json.hpp"
#include "diagnostics/recorder.hpp"
#include "diagnostics/series.hpp"
#include "harness/case/case.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace dampsym::detail {

// Problems whose figures can draw the orbit (state samples over time) declare
// `static constexpr OrbitFigure figure_orbit` (core/problem.hpp; the others' states are too large
// or not drawn). Whether a case draws it is case_draws_orbit (harness/case/figures_key.hpp).
template <class P>
constexpr OrbitFigure figure_orbit_of() {
    if constexpr (requires { P::figure_orbit; })
        return P::figure_orbit;
    else
        return OrbitFigure::none;
}
template <class P>
constexpr bool figure_wants_orbit() {
    return figure_orbit_of<P>() != OrbitFigure::none;
}

template <class P>
class FigureStepObserver {
public:
    FigureStepObserver(const P& p, const CaseSpec& c, double, std::int64_t n, bool orbit)
        : p_(p), t0_(c.t0), orbit_on_(orbit), orbit_(n + 1, orbit_samples(p.dim())) {}
    bool needed() const { return orbit_on_; }

    void start(const Vec& z0) {
        z0_ = z0;
        sample(0, t0_, z0);
    }

    void operator()(std::int64_t n, double t, const Vec& z) { sample(n, t, z); }

    nlohmann::json to_json() {
        using json = nlohmann::json;
        json s = json::object();
        if (!orbit_t_.empty()) {
            s["orbit"] = {{"t", orbit_t_}, {"states", orbit_z_}, {"stride", orbit_.stride()}};
            if (!orbit_ref_.empty())
                s["orbit_reference"] = {{"t", orbit_t_},
                                        {"states", orbit_ref_},
                                        {"stride", orbit_.stride()},
                                        {"exact", true}};
        }
        return s;
    }

private:
    void sample(std::int64_t n, double t, const Vec& z) {
        if constexpr (figure_wants_orbit<P>()) {
            if (!orbit_on_ || !orbit_.wants(n)) return;
            orbit_t_.push_back(t);
            orbit_z_.push_back(drawn(z));
            // the exact solution at the same times (a smooth reference orbit: the output grid's
            // reference may have few points per revolution)
            if constexpr (HasExactSolution<P>) {
                if (ref_.size() != z0_.size()) ref_.resize(z0_.size());
                p_.exact(t0_, z0_, t, ref_);
                orbit_ref_.push_back(drawn(ref_));
            }
        } else {
            (void)n, (void)t, (void)z;
        }
    }

    // A state as the figure draws it (drawn_value: 7 significant digits).
    static std::vector<double> drawn(const Vec& z) {
        std::vector<double> v(static_cast<std::size_t>(z.size()));
        for (Eigen::Index i = 0; i < z.size(); ++i)
            v[static_cast<std::size_t>(i)] = drawn_value(z[i]);
        return v;
    }

    const P& p_;
    double t0_;
    bool orbit_on_ = false;
    StrideSampler orbit_;
    std::vector<double> orbit_t_;
    std::vector<std::vector<double>> orbit_z_, orbit_ref_;
    Vec z0_, ref_;
};

// The observer of a measured run that observes its steps: the Recorder of its diagnostics and,
// with --figures, the figure series, each only if present. Compiled once per problem: each
// kernel's observed loop (kernel_ops.hpp) calls it through StepSink, with or without figures.
template <class P>
struct RunObserver final : StepSink {
    RunObserver(Recorder<P>* r, FigureStepObserver<P>* f) : recorder(r), figures(f) {}
    Recorder<P>* recorder;
    FigureStepObserver<P>* figures;
    void operator()(std::int64_t n, double t, const Vec& z) override {
        if (recorder) (*recorder)(n, t, z);
        if (figures) (*figures)(n, t, z);
    }
};

} // namespace dampsym::detail
