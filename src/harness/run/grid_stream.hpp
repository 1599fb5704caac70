// The output grid streamed (harness/run/limits.hpp grid_plan): when only the error
// diagnostic and the case's measures read the grid, each run feeds them every grid point on the
// fly through the Recorder's grid sink, so no trajectory is stored; against an exact solution the
// reference is evaluated at each grid time here (the same call, at the same time, as the stored
// reference of TypedCase::prepare) instead of stored. The reductions are those of the stored path
// (ErrorAccumulator, MeasureAccumulator), so the metrics are bitwise the same.
#pragma once

#include "core/problem_concepts.hpp"
#include "diagnostics/capabilities.hpp"
#include "diagnostics/error_diagnostic.hpp"
#include "diagnostics/recorder.hpp"
#include "harness/run/case_run.hpp"

#include <optional>

namespace dampsym::detail {

template <class P>
class GridStream final : public GridSink {
public:
    // exact_on_the_fly: the reference is P's exact solution, evaluated at each grid time (else
    // facts.ref holds it on the grid). error / measures: which reductions the case wants.
    GridStream(const P& problem, const CaseSpec& c, const CaseFacts& facts, bool exact_on_the_fly,
               bool error, bool measures)
        : p_(problem), facts_(facts), exact_(exact_on_the_fly), z0_(problem.initial_state()),
          ref_(problem.dim()) {
        if (error) error_.emplace(facts.ref_error);
        if (measures) {
            std::function<double(const Vec&)> energy, energy_scale;
            if constexpr (HasEnergy<P>) {
                energy = [this](const Vec& v) { return p_.energy(v); };
                energy_scale = [this](const Vec& v) { return p_.energy_scale(v); };
            }
            measures_.emplace(c, facts, std::move(energy), std::move(energy_scale));
        }
    }
    GridStream(const GridStream&) = delete;
    GridStream& operator=(const GridStream&) = delete;

    void point(Eigen::Index i, const Vec& z) override {
        const double t = facts_.grid_time(i); // = reference_times(...)[i] (runner.cpp)
        if (exact_) {
            if constexpr (HasExactSolution<P>) p_.exact(facts_.t0, z0_, t, ref_);
        } else {
            ref_ = facts_.ref.col(i);
        }
        if (error_) error_->add(z, ref_, t);
        if (measures_) measures_->add(z, ref_, t);
    }

    // The metrics after the run (z: its final state; the reference at t_end is facts.ref's last
    // column either way).
    json error_metrics(const Vec& z) const {
        return error_->finish(z, facts_.ref.col(facts_.ref.cols() - 1), facts_.t_end);
    }
    json measure_metrics(const Vec& z) const {
        return measures_->finish(z, Vec(facts_.ref.col(facts_.ref.cols() - 1)));
    }

private:
    const P& p_;
    const CaseFacts& facts_;
    bool exact_;
    Vec z0_, ref_;
    std::optional<ErrorAccumulator> error_;
    std::optional<MeasureAccumulator> measures_;
};

} // namespace dampsym::detail
