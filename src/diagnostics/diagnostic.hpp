// What a diagnostic is, for everything that does not run it: the case validator (case.cpp), the
// runner's "needs a trajectory / a reference / an observer / a Jacobian pass" logic, the check
// evaluation, the report and `dampsym list`. Each diagnostic declares one DiagnosticInfo in its own
// file (src/diagnostics/<name>_diagnostic.{hpp,cpp}) next to the C++20 concept a problem must
// satisfy and the code that produces its metrics, and registers itself there with a
// `DAMPSYM_DIAGNOSTIC(Type, order);` line (below; DiagnosticList in diagnostic_list.hpp is
// generated from those lines). No list of diagnostic or metric names is written anywhere else.
#pragma once

#include <concepts>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace dampsym {

enum class DiagnosticLevel {
    run,   // metrics per (method, dt) run, under runs[].metrics
    method // metrics per method (over the dt ladder or a parameter grid), under method_metrics
};

// What a diagnostic asks of the runner.
struct DiagnosticNeeds {
    bool grid = false;           // the states on the output grid, whatever the grid's size
    bool grid_if_points = false; // ... only when the grid has more than one point (error)
    // Its pass over the grid is a running reduction: the runner feeds it each grid point on the
    // fly and stores no trajectory when nothing else reads the grid (error;
    // harness/run/limits.hpp grid_plan).
    bool streams = false;
    // Reads the reference on the output grid when the case has one (dissipation-drift's reference
    // maxima): the reference is then stored, never evaluated on the fly.
    bool reference_grid = false;
    bool reference = false;     // a reference solution (exact, or certified GSL) on that grid
    bool observer = false;      // a hook in the step loop (its Part<P>, observer_part.hpp)
    bool jacobian_pass = false; // a separate pass with the exact step Jacobian
    bool ok_run = false;        // metrics only for a run that finished ("status": "ok")
    bool reference_ok = false;  // ... and only when the reference did not fail
    std::size_t min_dts = 0;    // the dt ladder needs at least this many step sizes
};

// A column of the report's per-run metrics table (harness/report/report.cpp): the metric `key` of
// the diagnostic, or, per part, "<part> <key> (scale <scale_key>)" for each of `parts` (every
// sub-object of the diagnostic's metrics when `parts` is empty).
struct ReportColumn {
    std::string key{};
    std::string label{};
    bool per_part = false;
    std::vector<std::string> parts{};
    std::string scale_key{};
};

struct DiagnosticInfo {
    std::string name{};
    DiagnosticLevel level = DiagnosticLevel::run;
    std::string what{};        // one line for `dampsym list`
    std::string requirement{}; // what the problem must provide ("" = any problem)
    DiagnosticNeeds needs{};
    // Its key under a run's "observed" in report.json (whether its per-step part ran; "" = none).
    std::string observed_key{};
    // Metric names, as "<diagnostic>.<metric>" without the prefix. With per_invariant, each name is
    // repeated under every invariant of the problem ("<invariant>.<metric>").
    std::vector<std::string> metrics{};
    bool per_invariant = false;
    std::vector<std::string> implies{}; // diagnostics it adds to the case (order adds error)
    // Checks on it are evaluated whatever the run's status (the metric describes the method, not
    // the trajectory: stability's one-step matrix).
    bool any_status = false;
    // A missing value is explained by a failed reference (the check message names it).
    bool reads_reference = false;
    // Its columns in the report's per-run metrics table (none: not in the table).
    std::vector<ReportColumn> report_columns{};
};

// What every registered diagnostic type declares (the rest, its producers, hooks and series, is
// optional and found by the typed case's requires-expressions).
template <class D>
concept DiagnosticType = requires {
    { D::name } -> std::convertible_to<std::string_view>;
    { D::info() } -> std::same_as<DiagnosticInfo>;
};

// Every diagnostic, in registration order (diagnostic_list.hpp).
const std::vector<DiagnosticInfo>& diagnostic_registry();
const DiagnosticInfo* find_diagnostic(std::string_view name);

// The checkable metric names of `d` for a problem with these invariants (every metric of a
// per-invariant diagnostic under "<invariant>"; "<invariant>" itself when `invariants` is empty
// and `placeholder` is set, for listings). "run" is the run record (any case, any status).
std::vector<std::string> diagnostic_metrics(std::string_view d,
                                            const std::vector<std::string>& invariants,
                                            bool placeholder = false);

// The run record's own fields, checkable as "run.<field>" in every case (not a diagnostic).
const std::vector<std::string>& run_record_fields();

} // namespace dampsym

// Registers the diagnostic type T, written on a line of its own at namespace scope in
// src/diagnostics/<name>_diagnostic.hpp: cmake/diagnostic_registry.cmake finds the line and lists T
// in DiagnosticList (diagnostic_list.hpp), by ascending `order` (the order of `dampsym list` and of
// the report's metrics-table columns). Here it checks that T is one.
#define DAMPSYM_DIAGNOSTIC(T, order)                                                               \
    static_assert(::dampsym::DiagnosticType<T> && (order) >= 0,                                    \
                  #T " does not declare a diagnostic's name and info() (diagnostic.hpp)")
