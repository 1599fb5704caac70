// The case file's keys, one parser per group ("problem", "methods", the time grid,
// "diagnostics" and "reference", "stability_sweep", "no_checks"; "expect" and "measures" in
// case/expect.cpp), and the case as a whole (docs/case-keys.md).
#include "diagnostics/error_diagnostic.hpp"
#include "diagnostics/poincare_diagnostic.hpp"
#include "diagnostics/stability_sweep_diagnostic.hpp"
#include "harness/case/case.hpp"
#include "harness/case/figures_key.hpp"
#include "harness/case/util.hpp"
#include "harness/problem_info.hpp"
#include "harness/run/case_job.hpp"
#include "harness/run/limits.hpp"
#include "harness/suggest.hpp"
#include "harness/user_methods/method_files.hpp"
#include "methods/runtime_methods.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

namespace dampsym::case_detail {
namespace {

// An unknown problem id: the error names the known ones and the closest.
[[noreturn]] void unknown_problem(const std::string& file, const std::string& id) {
    std::string list;
    std::vector<std::string> ids;
    for (const auto& p : problem_catalog()) {
        list += (list.empty() ? "" : ", ") + p.id;
        ids.push_back(p.id);
    }
    const std::string hint = did_you_mean(id, ids);
    fail(file, "problem.id",
         "unknown problem '" + brief(id) + "'" + (hint.empty() ? "" : "; " + hint) +
             " (known: " + list + ")");
}

// "problem": the id and the parameters, each in its range; then the problem checks the whole.
const ProblemInfo* parse_problem(const json& j, const std::string& file, CaseSpec& c,
                                 std::optional<double>& forcing_period) {
    const json& pj = j["problem"];
    if (!pj.is_object()) fail(file, "problem", "must be an object with an \"id\"");
    if (!pj.contains("id")) fail(file, "problem.id", "missing required key");
    c.problem_id = string_of(pj["id"], file, "problem.id");
    const ProblemInfo* prob = find_problem(c.problem_id);
    if (!prob) unknown_problem(file, c.problem_id);
    std::set<std::string> allowed{"id"};
    for (const auto& ps : prob->params) {
        allowed.insert(ps.name);
        if (ps.is_array)
            c.params.arrays[ps.name] = ps.default_array;
        else
            c.params.scalars[ps.name] = ps.default_value;
    }
    only_keys(pj, allowed, file, "problem.");
    auto in_range = [&](const ParamSpec& ps, double x, const std::string& key) {
        if (!ps.range.contains(x))
            fail(file, key,
                 "must be in " + describe(ps.range) + " (the range where " + c.problem_id +
                     "'s formulas are valid), got " + format_number(x));
        if (ps.integer && x != std::floor(x))
            fail(file, key, "must be a whole number, got " + format_number(x));
    };
    for (const auto& ps : prob->params) {
        if (!pj.contains(ps.name)) continue;
        const std::string key = "problem." + ps.name;
        if (!ps.choices.empty()) {
            std::string list;
            for (const auto& ch : ps.choices) list += (list.empty() ? "\"" : ", \"") + ch + "\"";
            const json& v = pj[ps.name];
            if (!v.is_string()) fail(file, key, "must be one of " + list + ", got " + brief(v));
            const auto it = std::find(ps.choices.begin(), ps.choices.end(), v.get<std::string>());
            if (it == ps.choices.end())
                fail(file, key, "must be one of " + list + ", got " + brief(v));
            c.params.scalars[ps.name] = static_cast<double>(it - ps.choices.begin());
        } else if (ps.is_array) {
            const json& a = pj[ps.name];
            if (!a.is_array() || a.empty())
                fail(file, key, "must be a non-empty array of numbers, got " + brief(a));
            if (ps.max_size > 0 && a.size() > static_cast<std::size_t>(ps.max_size))
                fail(file, key,
                     "has " + std::to_string(a.size()) + " entries (at most " +
                         std::to_string(ps.max_size) + ")");
            if (a.size() % static_cast<std::size_t>(ps.size_multiple) != 0)
                fail(file, key,
                     "length " + std::to_string(a.size()) + " is not a multiple of " +
                         std::to_string(ps.size_multiple));
            std::vector<double> v;
            for (std::size_t i = 0; i < a.size(); ++i) {
                const std::string ki = key + "[" + std::to_string(i) + "]";
                v.push_back(number(a[i], file, ki));
                in_range(ps, v.back(), ki);
            }
            c.params.arrays[ps.name] = std::move(v);
        } else {
            const double x = number(pj[ps.name], file, key);
            in_range(ps, x, key);
            c.params.scalars[ps.name] = x;
        }
    }

    // Problem-level consistency (array lengths, ...) is checked by the problem itself.
    try {
        const ProblemFacts facts = prob->facts(c.params);
        c.dim = facts.dim;
        forcing_period = facts.forcing_period;
    } catch (const std::invalid_argument& e) {
        fail(file, "problem", e.what());
    }
    return prob;
}

// "method_files": method files (paths relative to the case file) loaded before "methods" is read.
void parse_method_files(const json& j, const std::string& file) {
    if (!j.contains("method_files")) return;
    const json& a = j["method_files"];
    if (!a.is_array()) fail(file, "method_files", "must be an array of method file paths");
    for (std::size_t i = 0; i < a.size(); ++i) {
        const std::string key = "method_files[" + std::to_string(i) + "]";
        const std::string rel = string_of(a[i], file, key);
        const std::filesystem::path p = std::filesystem::path(rel).is_absolute()
                                            ? std::filesystem::path(rel)
                                            : std::filesystem::path(file).parent_path() / rel;
        std::error_code ec;
        if (!std::filesystem::is_regular_file(p, ec))
            fail(file, key,
                 "method file " + p.string() + " not found (paths are relative to the case file)");
        load_method_file(p.string());
    }
}

// "methods": known, listed once, applicable to the problem.
void parse_methods(const json& j, const std::string& file, CaseSpec& c) {
    if (!j["methods"].is_array() || j["methods"].empty())
        fail(file, "methods", "must be a non-empty array of method ids");
    for (std::size_t i = 0; i < j["methods"].size(); ++i) {
        const std::string key = "methods[" + std::to_string(i) + "]";
        const std::string m = string_of(j["methods"][i], file, key);
        if (!find_method(m)) {
            std::string list;
            std::vector<std::string> ids;
            for (const auto& mi : method_catalog()) ids.emplace_back(mi.id);
            for (const MethodInfo* mi : loaded_methods()) ids.emplace_back(mi->id); // files
            for (const auto& id : ids) list += (list.empty() ? "" : ", ") + id;
            const std::string hint = did_you_mean(m, ids);
            fail(file, key,
                 "unknown method '" + brief(m) + "'" + (hint.empty() ? "" : "; " + hint) +
                     " (known: " + list + ")");
        }
        if (std::find(c.methods.begin(), c.methods.end(), m) != c.methods.end())
            fail(file, key, "method '" + m + "' listed twice");
        if (!method_applies(m, c.problem_id)) {
            std::string list;
            for (const auto& mi : method_catalog())
                if (method_applies(mi.id, c.problem_id))
                    list += (list.empty() ? "" : ", ") + std::string(mi.id);
            fail(file, key,
                 "method '" + m + "' (" + std::string(form_name(find_method(m)->form)) +
                     " form) does not apply to problem '" + c.problem_id +
                     "' (applicable: " + list + ")");
        }
        c.methods.push_back(m);
    }
}

// "t0", "t_end", "dt" or "dt_ladder", "output_dt".
void parse_time_grid(const json& j, const std::string& file, CaseSpec& c) {
    if (j.contains("t0")) c.t0 = number(j["t0"], file, "t0");
    c.t_end = number(j["t_end"], file, "t_end");
    for (const auto& [k, t] : {std::pair<const char*, double>{"t0", c.t0}, {"t_end", c.t_end}})
        if (!(std::abs(t) <= limits::max_abs_time))
            fail(file, k, "|" + std::string(k) + "| must be <= 1e9, got " + format_number(t));
    if (!(c.t_end > c.t0)) fail(file, "t_end", "must be > t0");
    if (j.contains("dt") == j.contains("dt_ladder"))
        fail(file, "dt", "give exactly one of \"dt\" and \"dt_ladder\"");
    if (j.contains("dt")) {
        c.dts.push_back(number(j["dt"], file, "dt"));
        if (!(c.dts[0] > 0.0)) fail(file, "dt", "must be > 0");
        c.steps.push_back(
            step_count(c.t_end - c.t0, c.dts[0], file, "dt", limits::max_steps_per_run));
    } else {
        c.ladder = true;
        const json& lj = j["dt_ladder"];
        if (!lj.is_array() || lj.empty()) fail(file, "dt_ladder", "must be a non-empty array");
        if (lj.size() > limits::max_ladder)
            fail(file, "dt_ladder",
                 "has " + std::to_string(lj.size()) + " step sizes (at most " +
                     std::to_string(limits::max_ladder) + ")");
        for (std::size_t i = 0; i < lj.size(); ++i) {
            const std::string key = "dt_ladder[" + std::to_string(i) + "]";
            const double dt = number(lj[i], file, key);
            if (!(dt > 0.0)) fail(file, key, "must be > 0");
            if (std::find(c.dts.begin(), c.dts.end(), dt) != c.dts.end())
                fail(file, key, "step size listed twice");
            c.dts.push_back(dt);
            c.steps.push_back(step_count(c.t_end - c.t0, dt, file, key, limits::max_steps_per_run));
        }
    }
    if (j.contains("output_dt")) {
        const double odt = number(j["output_dt"], file, "output_dt");
        if (!(odt > 0.0)) fail(file, "output_dt", "must be > 0");
        step_count(c.t_end - c.t0, odt, file, "output_dt", limits::max_output_points);
        for (double dt : c.dts) {
            const double r = odt / dt;
            if (std::abs(r - std::round(r)) > 1e-9 * r || std::round(r) < 1.0)
                fail(file, "output_dt", "must be an integer multiple of every dt");
        }
        c.output_dt = odt;
    }
}

// "diagnostics" and "reference": each known and supported by the problem (diagnostic registry).
void parse_diagnostics(const json& j, const std::string& file, CaseSpec& c,
                       const ProblemInfo& problem, std::optional<double> forcing_period) {
    const ProblemInfo* prob = &problem;
    if (j.contains("diagnostics")) {
        if (!j["diagnostics"].is_array()) fail(file, "diagnostics", "must be an array");
        for (std::size_t i = 0; i < j["diagnostics"].size(); ++i) {
            const std::string key = "diagnostics[" + std::to_string(i) + "]";
            const std::string d = string_of(j["diagnostics"][i], file, key);
            const auto& known = known_diagnostics();
            if (std::find(known.begin(), known.end(), d) == known.end()) {
                std::string list;
                for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
                const std::string hint =
                    did_you_mean(d, std::vector<std::string>(known.begin(), known.end()));
                fail(file, key,
                     "unknown diagnostic '" + brief(d) + "'" + (hint.empty() ? "" : "; " + hint) +
                         " (known: " + list + ")");
            }
            if (c.wants(d)) fail(file, key, "diagnostic '" + d + "' listed twice");
            c.diagnostics.push_back(d);
        }
    } else {
        c.diagnostics.push_back(std::string(ErrorDiagnostic::name));
    }
    // What each requested diagnostic needs of the ladder and which diagnostics it adds (registry).
    for (std::size_t i = 0; i < c.diagnostics.size(); ++i) {
        const DiagnosticInfo& d = *find_diagnostic(c.diagnostics[i]);
        if (c.dts.size() < d.needs.min_dts)
            fail(file, "dt_ladder",
                 "the " + d.name + " diagnostic needs >= " + std::to_string(d.needs.min_dts) +
                     " step sizes");
        for (const std::string& implied : d.implies)
            if (!c.wants(implied)) c.diagnostics.push_back(implied);
    }
    if (j.contains("reference")) {
        const json& rj = j["reference"];
        if (!rj.is_object()) fail(file, "reference", "must be an object");
        only_keys(rj, {"stepper", "epsrel", "epsabs"}, file, "reference.");
        if (rj.contains("stepper")) {
            c.reference.stepper = string_of(rj["stepper"], file, "reference.stepper");
            if (c.reference.stepper != "rkf45" && c.reference.stepper != "rk8pd")
                fail(file, "reference.stepper", "must be \"rkf45\" or \"rk8pd\"");
        }
        for (const char* k : {"epsrel", "epsabs"}) {
            if (!rj.contains(k)) continue;
            const double x = number(rj[k], file, std::string("reference.") + k);
            if (!(x >= limits::min_reference_tol && x <= limits::max_reference_tol))
                fail(file, std::string("reference.") + k,
                     "must be in [1e-15, 1e-2], got " + format_number(x));
            (std::string(k) == "epsrel" ? c.reference.epsrel : c.reference.epsabs) = x;
        }
    }
    // What each requested diagnostic needs of the problem: its `supports<P>` concept (registry).
    for (const std::string& name : c.diagnostics)
        if (!prob->supports(name))
            fail(file, "diagnostics",
                 name + " is not defined for problem '" + c.problem_id + "' (it needs " +
                     find_diagnostic(name)->requirement + ")");
    if (c.wants(PoincareDiagnostic::name)) {
        // Sections at t0 + kT: the output grid must be the forcing period (typed_case.hpp).
        const double T = forcing_period.value_or(0.0);
        if (!c.output_dt || std::abs(*c.output_dt - T) > 1e-9 * T)
            fail(file, "output_dt",
                 "the poincare diagnostic needs output_dt equal to the forcing period " +
                     format_number(T) +
                     (c.output_dt ? ", got " + format_number(*c.output_dt)
                                  : std::string(", which is not given")));
    }
}

// "stability_sweep": exactly with the stability-sweep diagnostic.
void parse_sweep(const json& j, const std::string& file, CaseSpec& c) {
    if (c.wants(StabilitySweepDiagnostic::name) != j.contains("stability_sweep"))
        fail(file, "stability_sweep",
             "give \"stability_sweep\" exactly when the stability-sweep diagnostic is requested");
    if (j.contains("stability_sweep")) {
        const json& sj = j["stability_sweep"];
        if (!sj.is_object()) fail(file, "stability_sweep", "must be an object");
        only_keys(sj, {"omega", "gamma", "h"}, file, "stability_sweep.");
        SweepSpec s;
        if (sj.contains("omega")) s.omega = number(sj["omega"], file, "stability_sweep.omega");
        if (!(s.omega > 0.0)) fail(file, "stability_sweep.omega", "must be > 0");
        if (!sj.contains("gamma") || !sj.contains("h"))
            fail(file, "stability_sweep", "needs \"gamma\" and \"h\" ranges");
        s.gamma = parse_range(sj["gamma"], file, "stability_sweep.gamma");
        s.h = parse_range(sj["h"], file, "stability_sweep.h");
        if (s.gamma.from < 0.0) fail(file, "stability_sweep.gamma[0]", "must be >= 0");
        if (!(s.h.from > 0.0)) fail(file, "stability_sweep.h[0]", "must be > 0");
        // The linear oscillator's ranges (its exact solution and F's closed forms).
        if (!(s.omega >= 1e-6 && s.omega <= 1e6))
            fail(file, "stability_sweep.omega", "must be in [1e-06, 1e+06]");
        if (!(s.gamma.to <= 1e6)) fail(file, "stability_sweep.gamma[1]", "must be <= 1e+06");
        if (!(s.h.to <= 1e6)) fail(file, "stability_sweep.h[1]", "must be <= 1e+06");
        const double cells = ((s.gamma.to - s.gamma.from) / s.gamma.step + 1.0) *
                             ((s.h.to - s.h.from) / s.h.step + 1.0);
        if (!(cells <= limits::max_sweep_cells))
            fail(file, "stability_sweep",
                 "gamma x h grid of " + format_number(std::round(cells)) + " points (at most 1e6)");
        c.sweep = s;
    }
}

// No silent cases: a case without a check says why.
void parse_no_checks(const json& j, const std::string& file, CaseSpec& c) {
    if (j.contains("no_checks_because")) {
        c.no_checks_because = string_of(j["no_checks_because"], file, "no_checks_because");
        if (c.no_checks_because.empty())
            fail(file, "no_checks_because", "must say why the case has no check");
        if (!c.checks.empty())
            fail(file, "no_checks_because",
                 "the case has " + std::to_string(c.checks.size()) +
                     " checks; give a reason only for a case without checks");
    } else if (c.checks.empty()) {
        fail(file, "expect",
             "the case has no check: add one, or say why with \"no_checks_because\": \"...\"");
    }
}

} // namespace

CaseSpec parse_case_unchecked(const json& input, const std::string& file,
                              const std::vector<std::string>& overrides, json& applied) {
    if (!input.is_object()) fail(file, "(top level)", "a case must be a JSON object");
    CaseSpec c;
    c.file = file;
    json j = input;
    for (const auto& o : overrides) {
        auto [key, value] = parse_override(o);
        set_path(j, key, value);
        c.overrides[key] = value;
        applied[key] = o.substr(o.find('=') + 1); // as typed (1e400, not inf)
    }
    c.raw = j;

    // clang-format off
    only_keys(j,
              {"id", "title", "source", "suites", "problem", "methods", "t0", "t_end", "dt",
               "dt_ladder", "diagnostics", "output_dt", "expect", "stability_sweep", "reference",
               "notes", "measures", "no_checks_because", "timeout_seconds", "figures",
               "method_files",
               "$schema"}, // what an editor adds to use schema/case.schema.json; not read
              file, "");
    // clang-format on
    validate_limit_keys(j, file); // timeout_seconds (src/harness/run/limits.hpp)
    for (const char* k : {"id", "problem", "methods", "t_end"})
        if (!j.contains(k)) fail(file, k, "missing required key");

    c.id = string_of(j["id"], file, "id");
    if (c.id.empty()) fail(file, "id", "must not be empty");
    if (!valid_case_id(c.id))
        fail(file, "id",
             "'" + brief(c.id) + "' is not a valid case id (at most " +
                 std::to_string(limits::max_id_length) +
                 " characters of A-Z a-z 0-9 . _ -, starting with a letter or digit)");
    if (j.contains("title")) c.title = string_of(j["title"], file, "title");
    if (j.contains("source")) c.source = string_of(j["source"], file, "source");
    if (j.contains("notes")) string_of(j["notes"], file, "notes");
    if (j.contains("suites")) {
        if (!j["suites"].is_array()) fail(file, "suites", "must be an array of suite names");
        for (std::size_t i = 0; i < j["suites"].size(); ++i) {
            const std::string key = "suites[" + std::to_string(i) + "]";
            const std::string suite = string_of(j["suites"][i], file, key);
            if (!valid_case_id(suite))
                fail(file, key,
                     "'" + brief(suite) +
                         "' is not a valid suite name (characters of A-Z a-z "
                         "0-9 . _ -, starting with a letter or digit)");
            if (std::find(c.suites.begin(), c.suites.end(), suite) != c.suites.end())
                fail(file, key, "suite '" + suite + "' listed twice");
            c.suites.push_back(suite);
        }
    }

    std::optional<double> forcing_period;
    const ProblemInfo* prob = parse_problem(j, file, c, forcing_period);
    parse_method_files(j, file); // harness/user_methods/method_files.hpp, before "methods"
    parse_methods(j, file, c);
    parse_time_grid(j, file, c);
    parse_diagnostics(j, file, c, *prob, forcing_period);
    parse_sweep(j, file, c);
    if (j.contains("measures")) parse_measures(j["measures"], *prob, file, c);
    if (j.contains("expect")) parse_expect(j["expect"], *prob, file, c);
    parse_no_checks(j, file, c);
    validate_figures_key(j, file, c, *prob); // "figures" (harness/case/figures_key.hpp)
    return c;
}

} // namespace dampsym::case_detail
