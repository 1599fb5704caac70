// A case ("scene"): one problem instance, methods, a step or step ladder, the diagnostics it asks
// for and the checks it expects. Cases are JSON files in verify/cases/ (SPEC §7); this is their
// parsed and validated form. Every validation error names the file and the key (exit status 2).
#pragma once

#include "core/problem.hpp"

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

enum class CheckOp { near, le, ge, lt, gt };

// What one check compares (README "Adding a case"): each listed method's metric, the ratio of two
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

// An error measure as a paper states it (README "Adding a case", key "measures"), reported by
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

// Numerical reference settings (SPEC §4); ignored for problems with an exact solution.
struct ReferenceSpec {
    std::string stepper = "rkf45";
    double epsrel = 1e-13;
    double epsabs = 1e-14;
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
    bool ladder = false;
    std::vector<std::string> diagnostics;
    std::optional<double> output_dt;
    std::vector<CheckSpec> checks;
    std::vector<MeasureSpec> measures;
    std::string no_checks_because; // required (and only allowed) when the case has no check
    std::optional<SweepSpec> sweep;
    ReferenceSpec reference;
    nlohmann::json overrides = nlohmann::json::object();
    nlohmann::json raw; // the case JSON after overrides

    bool wants(const std::string& diagnostic) const;
};

// The diagnostics dampsym knows, and the metric names each one produces.
const std::vector<std::string>& known_diagnostics();
bool diagnostic_is_method_level(const std::string& diagnostic);

// Parses "KEY=VALUE" overrides; VALUE is JSON if it parses as JSON, else a number (nan/inf
// included, so that validation can name the key) or a string.
std::pair<std::string, nlohmann::json> parse_override(const std::string& text);

// Reads, overrides and validates one case file. Throws InputError naming file and key.
CaseSpec load_case(const std::string& path, const std::vector<std::string>& overrides);
CaseSpec parse_case(const nlohmann::json& j, const std::string& file,
                    const std::vector<std::string>& overrides);

} // namespace dampsym
