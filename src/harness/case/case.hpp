// A case ("scene"): one problem instance, methods, a step or step ladder, the diagnostics it asks
// for and the checks it expects. Cases are JSON files in verify/cases/ (conventions §7); this is
// their parsed and validated form. Every validation error names the file and the key (exit status
// 2).
#pragma once

#include "core/problem.hpp"
#include "diagnostics/diagnostic.hpp"

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace dampsym {

// Bad input: the message already names the file and the key.
struct InputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Limits on what a case may ask for; beyond them a case is rejected (exit 2) before anything
// runs. docs/case-keys.md states them.
namespace limits {
inline constexpr std::uintmax_t max_file_bytes = 16u << 20; // case file size (16 MiB)
inline constexpr int max_depth = 16;                        // JSON nesting of a case or --set value
inline constexpr std::size_t max_id_length = 100;           // case id: [A-Za-z0-9._-], first alnum
inline constexpr std::size_t max_ladder = 32;               // entries of dt_ladder
inline constexpr double max_steps_per_run = 1e9;            // (t_end − t0)/dt for every dt
// (t_end − t0)/output_dt: at most the steps of a run (output_dt is a multiple of dt); the memory
// its grid needs is bounded by `run --max-memory` (limits.hpp: a streamed grid needs none).
inline constexpr double max_output_points = max_steps_per_run;
inline constexpr double max_abs_time = 1e9;        // |t0|, |t_end|
inline constexpr double max_sweep_cells = 1e6;     // stability_sweep γ × h grid points
inline constexpr double min_reference_tol = 1e-15; // reference.epsrel, reference.epsabs
inline constexpr double max_reference_tol = 1e-2;
inline constexpr std::size_t max_message_value = 80; // characters of a bad value quoted in errors
} // namespace limits

enum class CheckOp { near, le, ge, lt, gt };

// What one check compares (docs/case-keys.md): each listed method's metric, the ratio of two
// methods' metrics ("ratio": [A, B] -> metric(A) / metric(B)), or the spread of several methods'
// metrics ("spread": max over the methods / min over the methods), at each step size.
enum class CheckForm { per_method, ratio, spread };

struct CheckSpec {
    std::string name;
    std::string metric;               // "<diagnostic>.<path>"
    std::vector<std::string> methods; // per_method: each; ratio: {A, B}; spread: the set
    CheckForm form = CheckForm::per_method;
    // "across_dt": "loglog-slope": the values at the ladder's step sizes are reduced to the
    // least-squares slope of log(value) against log(dt) (e.g. "the ratio falls as h falls": > 0).
    bool across_dt_slope = false;
    // Passing shows that the paper's claim does not hold (docs/claims.md: "not reproduced").
    bool refutes = false;
    CheckOp op = CheckOp::near;
    double value = 0.0;
    double tol = 0.0;     // for near
    bool use_abs = false; // compare |metric|
    bool negative_control = false;
    std::optional<double> dt; // run-level metrics: only runs at this dt
    std::string note;
};

// An error measure as a paper states it (docs/case-keys.md, key "measures"), reported by
// the error diagnostic as the metric "measure.<name>" of each run.
enum class MeasureQuantity {
    state_error, // ‖U_n − u(t_n)‖₂ over the chosen components
    energy_error // |H(U_n) − H(u(t_n))|
};
enum class MeasureStat {
    final_value, // at t_end
    max,         // max over the output grid t_1..t_end
    mean,        // mean over the output grid t_1..t_end
    rms,         // root mean square over the output grid t_1..t_end
    growth // slope of log(running max) against log(t − t0) over the output grid (t ≥ from)
};
struct MeasureSpec {
    std::string name;
    MeasureQuantity quantity = MeasureQuantity::state_error;
    std::string component = "state"; // "state", "q", "p", "q[i]", "p[i]", "z[i]"
    int first = 0, count = 0;        // the components as a slice of the state z
    bool relative = false;           // divide pointwise by the reference's |u(t_n)| (or |H|)
    MeasureStat over = MeasureStat::max;
    double growth_from = 0.0; // growth: fit the grid points with t ≥ this time
};

struct Range3 {
    double from, to, step;
    std::vector<double> values() const;
};

struct SweepSpec {
    double omega = 1.0;
    Range3 gamma{0.0, 0.0, 1.0};
    Range3 h{0.1, 0.1, 1.0};
};

// Numerical reference settings (conventions §4); ignored for problems with an exact solution.
struct ReferenceSpec {
    std::string stepper = "rkf45";
    double epsrel = 1e-13;
    double epsabs = 1e-14;
};

// A check the selection left without one of its methods (`--method`): not run, with the reason —
// a third verdict beside pass and fail that never changes the exit status (a comparison whose
// partner did not run measured nothing).
struct NotRunCheck {
    CheckSpec spec;
    std::string reason;
};

struct CaseSpec {
    std::string id, title, source, file;
    std::vector<std::string> suites;
    std::string problem_id;
    ParamMap params;
    std::vector<std::string> methods;
    double t0 = 0.0, t_end = 0.0;
    std::vector<double> dts;
    std::vector<std::int64_t> steps; // per dt
    int dim = 0;                     // state dimension of the problem instance
    bool ladder = false;
    std::vector<std::string> diagnostics;
    std::optional<double> output_dt;
    std::vector<CheckSpec> checks;
    std::vector<NotRunCheck> checks_not_run; // left without a method by the selection
    std::vector<MeasureSpec> measures;
    std::string no_checks_because; // required (and only allowed) when the case has no check
    std::optional<SweepSpec> sweep;
    ReferenceSpec reference;
    nlohmann::json overrides = nlohmann::json::object();
    nlohmann::json raw; // the case JSON after overrides

    bool wants(std::string_view diagnostic) const;
};

// The diagnostics dampsym knows, and the metric names each one produces.
const std::vector<std::string>& known_diagnostics();
struct ProblemInfo;
// Whether a case on problem `p` may request diagnostic `d` (energy, momentum, poincare, ... need
// the problem's hooks; the stability diagnostics are the oscillator's).
bool diagnostic_applies(const std::string& d, const ProblemInfo& p);
bool diagnostic_is_method_level(const std::string& diagnostic);

// Parses "KEY=VALUE" overrides; VALUE is JSON if it parses as JSON, else a number (nan/inf
// included, so that validation can name the key) or a string.
std::pair<std::string, nlohmann::json> parse_override(const std::string& text);

// Reads, overrides and validates one case file. Throws InputError naming file and key.
CaseSpec load_case(const std::string& path, const std::vector<std::string>& overrides);
CaseSpec parse_case(const nlohmann::json& j, const std::string& file,
                    const std::vector<std::string>& overrides);

// Parses JSON text from `source` (a file name, or "--set KEY"), rejecting before any value is
// built: nesting deeper than limits::max_depth, duplicate keys in an object, numbers that
// overflow a double, control characters in strings. Errors name the source and the key path.
nlohmann::json parse_json_checked(const std::string& text, const std::string& source);

// Reads a case file: it must be a regular file (not a directory, FIFO or device) of at most
// limits::max_file_bytes, checked before reading; then parse_json_checked.
nlohmann::json read_case_json(const std::string& path);

// Whether `id` is a valid case id (limits::max_id_length characters of [A-Za-z0-9._-], the first
// a letter or digit).
bool valid_case_id(const std::string& id);

// Throws InputError if two cases share an id (the same file twice, two files with one id, or an
// id made equal by --set).
void check_unique_ids(const std::vector<CaseSpec>& cases);

// Steps of the whole case (every method at every step size) and a rough duration estimate in
// seconds (about 30 ns per step and state component for explicit methods, 300 for implicit
// ones, measured on the default suite; diagnostics and references come on top).
double case_total_steps(const CaseSpec& c);
double case_predicted_seconds(const CaseSpec& c);

// The metric names of a diagnostic (invariant metrics for `invariant_names`; with none given,
// the pattern "<invariant>.<stat>"), for validation and `dampsym list`.
std::vector<std::string> diagnostic_metric_names(const std::string& diagnostic,
                                                 const std::vector<std::string>& invariant_names);

// A value or string shortened for an error message (limits::max_message_value characters, then
// "… (N more characters)"), control characters escaped.
std::string brief(const nlohmann::json& v);
std::string brief(const std::string& s);

} // namespace dampsym
