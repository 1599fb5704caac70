// The checks ("expect") and measures of a case (docs/case-keys.md).
#include "diagnostics/error_diagnostic.hpp"
#include "diagnostics/invariants_diagnostic.hpp"
#include "harness/case/util.hpp"
#include "harness/run/case_job.hpp"
#include "harness/suggest.hpp"

#include <algorithm>
#include <cmath>

namespace dampsym::case_detail {

// "methods" (each method), "ratio" ([A, B]: metric(A) / metric(B)) or "spread" ("all" or
// [A, B, ...]: max / min over the methods), and "across_dt" (docs/case-keys.md).
void parse_check_methods(const json& cj, const CaseSpec& c, const std::string& diag,
                         const std::string& file, const std::string& base, CheckSpec& cs) {
    int forms = 0;
    for (const char* k : {"methods", "ratio", "spread"}) forms += cj.contains(k) ? 1 : 0;
    if (forms != 1) fail(file, base + ".methods", "give exactly one of methods, ratio, spread");
    const char* key = cj.contains("methods") ? "methods"
                      : cj.contains("ratio") ? "ratio"
                                             : "spread";
    cs.form = cj.contains("methods") ? CheckForm::per_method
              : cj.contains("ratio") ? CheckForm::ratio
                                     : CheckForm::spread;
    const json& mj = cj[key];
    const std::string mkey = base + "." + key;
    if (mj.is_string() && mj.get<std::string>() == "all" && cs.form != CheckForm::ratio) {
        cs.methods = c.methods;
    } else {
        if (!mj.is_array() || mj.empty())
            fail(file, mkey,
                 cs.form == CheckForm::ratio ? "must be an array [A, B] of two methods"
                                             : "must be \"all\" or a non-empty array");
        for (std::size_t i = 0; i < mj.size(); ++i) {
            const std::string ki = mkey + "[" + std::to_string(i) + "]";
            const std::string m = string_of(mj[i], file, ki);
            if (std::find(c.methods.begin(), c.methods.end(), m) == c.methods.end())
                fail(file, ki, "method '" + brief(m) + "' is not among the case's methods");
            if (std::find(cs.methods.begin(), cs.methods.end(), m) != cs.methods.end())
                fail(file, ki, "method '" + brief(m) + "' listed twice");
            cs.methods.push_back(m);
        }
    }
    if (cs.form == CheckForm::ratio && cs.methods.size() != 2)
        fail(file, mkey, "must name exactly two methods [A, B] (value A / B)");
    if (cs.form == CheckForm::spread && cs.methods.size() < 2)
        fail(file, mkey, "needs at least two methods");
    if (cj.contains("across_dt")) {
        const std::string a = string_of(cj["across_dt"], file, base + ".across_dt");
        if (a != "loglog-slope") fail(file, base + ".across_dt", "must be \"loglog-slope\"");
        if (c.dts.size() < 2)
            fail(file, base + ".across_dt", "needs a dt_ladder of at least two step sizes");
        cs.across_dt_slope = true;
    }
    if ((cs.form != CheckForm::per_method || cs.across_dt_slope) &&
        (diagnostic_is_method_level(diag) || diag == "run"))
        fail(file, base + ".metric",
             "ratio, spread and across_dt compare per-run metrics; '" + diag + "' is not one");
}

namespace {

// A measure's "component": "state", "q", "p", "q[i]", "p[i]" or "z[i]" (error measures only).
void parse_component(const json& e, const std::string& base, const std::string& file,
                     const CaseSpec& c, int dim, int dof, MeasureSpec& m) {
    m.count = dim;
    if (e.contains("component")) {
        m.component = string_of(e["component"], file, base + ".component");
        const std::string& s = m.component;
        if (s.empty()) fail(file, base + ".component", "must not be empty");
        const bool qp = s[0] == 'q' || s[0] == 'p';
        if ((qp || s.rfind("z[", 0) == 0) && s != "state") {
            if (qp && dof < 0)
                fail(file, base + ".component",
                     "problem '" + c.problem_id +
                         "' has no canonical q/p split; use \"z[i]\" or \"state\"");
            const int block = s[0] == 'z' ? dim : dof;
            const int offset = s[0] == 'p' ? dof : 0;
            if (s.size() == 1) {
                m.first = offset;
                m.count = dof;
            } else {
                std::size_t used = 0;
                int idx = -1;
                if (s.size() > 3 && s[1] == '[' && s.back() == ']') {
                    try {
                        idx = std::stoi(s.substr(2, s.size() - 3), &used);
                    } catch (const std::exception&) {
                        idx = -1;
                    }
                }
                if (idx < 0 || used != s.size() - 3)
                    fail(file, base + ".component",
                         "must be \"state\", \"q\", \"p\", \"q[i]\", \"p[i]\" or "
                         "\"z[i]\", got \"" +
                             s + "\"");
                if (idx >= block)
                    fail(file, base + ".component",
                         "index " + std::to_string(idx) + " out of range (" +
                             std::to_string(block) + " components)");
                m.first = offset + idx;
                m.count = 1;
            }
        } else if (s != "state") {
            fail(file, base + ".component",
                 "must be \"state\", \"q\", \"p\", \"q[i]\", \"p[i]\" or \"z[i]\", "
                 "got \"" +
                     s + "\"");
        }
    }
}

// A measure's "over" (final, max, mean, rms, growth) and, for growth, "from".
void parse_over(const json& e, const std::string& base, const std::string& file, const CaseSpec& c,
                std::int64_t points, MeasureSpec& m) {
    if (!e.contains("over")) fail(file, base + ".over", "missing required key");
    const std::string over = string_of(e["over"], file, base + ".over");
    const std::pair<const char*, MeasureStat> stats[] = {{"final", MeasureStat::final_value},
                                                         {"max", MeasureStat::max},
                                                         {"mean", MeasureStat::mean},
                                                         {"rms", MeasureStat::rms},
                                                         {"growth", MeasureStat::growth}};
    bool found = false;
    for (const auto& [name, st] : stats)
        if (over == name) {
            m.over = st;
            found = true;
        }
    if (!found) fail(file, base + ".over", "must be one of final, max, mean, rms, growth");
    if (m.over != MeasureStat::final_value && points < 2)
        fail(file, base + ".over",
             "'" + over +
                 "' needs an output grid: give \"output_dt\" (or a ladder whose "
                 "step sizes divide each other)");
    const double span = c.t_end - c.t0;
    m.growth_from = c.t0 + 0.1 * span;
    if (e.contains("from")) {
        if (m.over != MeasureStat::growth)
            fail(file, base + ".from", "only \"over\": \"growth\" takes a fit start");
        m.growth_from = number(e["from"], file, base + ".from");
        if (!(m.growth_from > c.t0) || !(m.growth_from < c.t_end))
            fail(file, base + ".from", "must lie in (t0, t_end)");
    }
    if (m.over == MeasureStat::growth) {
        const double spacing = span / static_cast<double>(points);
        if ((c.t_end - m.growth_from) / spacing < 2.0)
            fail(file, base + ".from", "the growth fit needs >= 3 output points after it");
    }
}

} // namespace

// "measures": { "<name>": { "quantity", "component", "norm", "over", "from" } }
// (docs/case-keys.md).
void parse_measures(const json& mj, const ProblemInfo& prob, const std::string& file, CaseSpec& c) {
    if (!mj.is_object() || mj.empty())
        fail(file, "measures", "must be an object of named measures");
    if (!c.wants(ErrorDiagnostic::name))
        fail(file, "measures",
             "measures are computed by the \"" + std::string(ErrorDiagnostic::name) +
                 "\" diagnostic; request it");
    const ProblemFacts facts = prob.facts(c.params);
    const int dim = facts.dim, dof = facts.dof; // dof: of a canonical z = [q; p], else -1
    const std::int64_t points = detail::output_points(c);
    for (auto it = mj.begin(); it != mj.end(); ++it) {
        const std::string base = "measures." + it.key();
        const json& e = it.value();
        MeasureSpec m;
        m.name = it.key();
        if (m.name.empty() ||
            m.name.find_first_not_of("abcdefghijklmnopqrstuvwxyz"
                                     "ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-") != std::string::npos)
            fail(file, base, "a measure name uses letters, digits, '_' and '-' only");
        if (!e.is_object()) fail(file, base, "must be an object");
        only_keys(e, {"quantity", "component", "norm", "over", "from"}, file, base + ".");
        if (e.contains("quantity")) {
            const std::string q = string_of(e["quantity"], file, base + ".quantity");
            if (q == "energy-error")
                m.quantity = MeasureQuantity::energy_error;
            else if (q != "error")
                fail(file, base + ".quantity", "must be \"error\" or \"energy-error\"");
        }
        if (m.quantity == MeasureQuantity::energy_error) {
            if (!prob.has_energy)
                fail(file, base + ".quantity", "problem '" + c.problem_id + "' declares no energy");
            if (e.contains("component"))
                fail(file, base + ".component", "the energy error has no component");
            m.component = "energy";
        } else {
            parse_component(e, base, file, c, dim, dof, m);
        }
        if (e.contains("norm")) {
            const std::string n = string_of(e["norm"], file, base + ".norm");
            if (n == "rel")
                m.relative = true;
            else if (n != "abs")
                fail(file, base + ".norm", "must be \"abs\" or \"rel\" (relative to |u(t_n)|)");
        }
        parse_over(e, base, file, c, points, m);
        c.measures.push_back(m);
    }
}

namespace {

// The check's "metric": a metric of a requested diagnostic (or a measure, or run.<field>) of this
// problem; returns its diagnostic.
std::string parse_check_metric(const json& cj, const ProblemInfo& problem, const std::string& file,
                               const std::string& base, const CaseSpec& c, CheckSpec& cs) {
    const ProblemInfo* prob = &problem;
    if (!cj.contains("metric")) fail(file, base + ".metric", "missing required key");
    cs.metric = string_of(cj["metric"], file, base + ".metric");
    const auto dot = cs.metric.find('.');
    const std::string diag = cs.metric.substr(0, dot);
    const bool is_measure = diag == "measure" && !c.measures.empty();
    if (dot == std::string::npos || (!c.wants(diag) && diag != "run" && !is_measure))
        fail(file, base + ".metric",
             "'" + brief(cs.metric) + "' is not a metric of a requested diagnostic" +
                 (diag == "measure" ? " (no \"measures\" defined)" : ""));
    std::vector<std::string> names = metric_names(diag, prob->invariants);
    if (diag == InvariantsDiagnostic::name && names.empty())
        fail(file, base + ".metric",
             "problem '" + c.problem_id + "' declares no conformal invariants");
    if (is_measure)
        for (const auto& m : c.measures) names.push_back(m.name);
    if (std::find(names.begin(), names.end(), cs.metric.substr(dot + 1)) == names.end()) {
        std::string list;
        std::vector<std::string> full;
        for (const auto& n : names) {
            list += (list.empty() ? "" : ", ") + diag + "." + n;
            full.push_back(diag + "." + n);
        }
        const std::string hint = did_you_mean(cs.metric, full);
        fail(file, base + ".metric",
             "unknown metric '" + brief(cs.metric) + "'" + (hint.empty() ? "" : "; " + hint) +
                 " (known: " + list + ")");
    }
    return diag;
}

// The check's operator (exactly one of near, le, ge, lt, gt) and its value; "near"'s tolerance.
void parse_check_op(const json& cj, const std::string& file, const std::string& base,
                    CheckSpec& cs) {
    int ops = 0;
    const std::pair<const char*, CheckOp> op_names[] = {{"near", CheckOp::near},
                                                        {"le", CheckOp::le},
                                                        {"ge", CheckOp::ge},
                                                        {"lt", CheckOp::lt},
                                                        {"gt", CheckOp::gt}};
    for (const auto& [name, op] : op_names) {
        if (!cj.contains(name)) continue;
        ++ops;
        cs.op = op;
        const json& v = cj[name];
        cs.value =
            v.is_boolean() ? (v.get<bool>() ? 1.0 : 0.0) : number(v, file, base + "." + name);
    }
    if (ops != 1) fail(file, base, "give exactly one of near, le, ge, lt, gt");
    if (cs.op == CheckOp::near) {
        if (!cj.contains("tol")) fail(file, base + ".tol", "\"near\" needs a tolerance");
        cs.tol = number(cj["tol"], file, base + ".tol");
        if (!(cs.tol >= 0.0)) fail(file, base + ".tol", "must be >= 0");
    } else if (cj.contains("tol")) {
        fail(file, base + ".tol", "only \"near\" takes a tolerance");
    }
}

} // namespace

// The "expect" object: one CheckSpec per named check.
void parse_expect(const json& ej, const ProblemInfo& problem, const std::string& file,
                  CaseSpec& c) {
    if (!ej.is_object()) fail(file, "expect", "must be an object of named checks");
    for (auto it = ej.begin(); it != ej.end(); ++it) {
        const std::string base = "expect." + brief(it.key());
        const json& cj = it.value();
        if (!cj.is_object()) fail(file, base, "must be an object");
        only_keys(cj,
                  {"metric", "methods", "ratio", "spread", "across_dt", "refutes", "near", "le",
                   "ge", "lt", "gt", "tol", "abs", "negative_control", "dt", "note"},
                  file, base + ".");
        CheckSpec cs;
        cs.name = it.key();
        const std::string diag = parse_check_metric(cj, problem, file, base, c, cs);
        parse_check_methods(cj, c, diag, file, base, cs);
        parse_check_op(cj, file, base, cs);
        if (cj.contains("abs")) cs.use_abs = boolean(cj["abs"], file, base + ".abs");
        if (cj.contains("negative_control"))
            cs.negative_control = boolean(cj["negative_control"], file, base + ".negative_control");
        if (cj.contains("note")) cs.note = string_of(cj["note"], file, base + ".note");
        if (cj.contains("refutes")) cs.refutes = boolean(cj["refutes"], file, base + ".refutes");
        if (cj.contains("dt")) {
            if (cs.across_dt_slope)
                fail(file, base + ".dt", "\"across_dt\" uses every step size; no dt");
            const double dt = number(cj["dt"], file, base + ".dt");
            if (std::find(c.dts.begin(), c.dts.end(), dt) == c.dts.end())
                fail(file, base + ".dt", "not one of the case's step sizes");
            if (diagnostic_is_method_level(diag))
                fail(file, base + ".dt", "'" + diag + "' is a per-method metric; no dt");
            cs.dt = dt;
        }
        c.checks.push_back(cs);
    }
}

} // namespace dampsym::case_detail

namespace dampsym::detail {

// (Here rather than in runner.cpp, so that the readers link without the runner: ci/fuzz.sh.)
// Output grid shared by every step size of a case: a common multiple of all dt, at most ~20000
// points; the last point is t_end.
std::int64_t output_points(const CaseSpec& c) {
    const double span = c.t_end - c.t0;
    if (c.output_dt) return std::llround(span / *c.output_dt);
    std::size_t coarse = 0;
    for (std::size_t i = 1; i < c.dts.size(); ++i)
        if (c.dts[i] > c.dts[coarse]) coarse = i;
    for (double dt : c.dts) {
        const double r = c.dts[coarse] / dt;
        if (std::abs(r - std::round(r)) > 1e-9 * r) return 1; // no common grid: final time only
    }
    const std::int64_t n = c.steps[coarse];
    for (std::int64_t k = 1; k <= n; ++k)
        if (n % k == 0 && n / k <= 20000) return n / k;
    return 1;
}

} // namespace dampsym::detail
