// What a diagnostic's producer reads of one finished run (the `produce` and `produce_pass` members
// of the diagnostics, src/diagnostics/*_diagnostic.hpp): the typed case fills it once per run and
// folds over the diagnostic list, so that the runner names no diagnostic.
#pragma once

#include "core/any_stepper.hpp"
#include "core/method.hpp"
#include "core/types.hpp"
#include "diagnostics/metric_json.hpp"
#include "diagnostics/recorder.hpp"
#include "diagnostics/series.hpp"
#include "harness/run/grid_stream.hpp"

#include <cstdint>
#include <optional>

namespace dampsym::detail {

template <class P>
struct RunView {
    using Problem = P;
    const P& problem;
    const CaseFacts& facts;
    const Recorder<P>& rec;
    const Mat* stored_grid;      // the run's stored output grid, or null (streamed or none)
    const GridStream<P>* stream; // the error and measures reduced on the fly, or null
    const MethodInfo& info;
    double t0;
    double h;
    std::int64_t n; // steps planned
    const Vec& z;   // the final state
    const Counters& counters;
    std::int64_t steps_done;
    double wall;         // seconds of the run's step loop
    double table_factor; // B Table 3.1's momentum factor per step the method declares
    std::optional<MinMaxDecimator>* cs_series; // figures: the E_n series of the kernel pass
    StepperMaker<P> stepper; // fresh steppers of the run's kernel, for separate passes

    const Mat& grid() const { return rec.grid(); }
};

} // namespace dampsym::detail
