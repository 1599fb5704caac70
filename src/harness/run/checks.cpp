// Check evaluation (docs/case-keys.md "expect"): per-method checks on run or method metrics, and
// comparison checks (ratio, spread, across_dt) over runs. What a diagnostic's checks need (method
// level, readable whatever the run's status, explained by a failed reference) comes from the
// diagnostic registry (diagnostics/diagnostic.hpp).
#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"
#include "diagnostics/order_diagnostic.hpp"
#include "diagnostics/order_fit.hpp"
#include "harness/run/case_run.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

namespace dampsym::detail {

namespace {

// The run record's own fields as metrics "run.<field>" (any status: a check may expect a
// divergence, or an exact step or evaluation count; conventions §7 report fields).
json run_record_metrics(const json& run) {
    json r = json::object();
    for (const char* k :
         {"steps", "steps_planned", "rhs_evals", "jac_evals", "newton_iters", "final_time"})
        if (run.contains(k)) r[k] = run[k];
    const std::string status = run.value("status", std::string());
    r["ok"] = status == "ok" ? 1 : 0;
    r["diverged"] = status == "diverged" ? 1 : 0;
    r["failed_at_step"] = run.value("failed_at_step", std::int64_t{0});
    return {{"run", r}};
}

// The reason set_undefined() recorded for metric "a.b.key" (under "a.b".undefined.key), or "".
std::string undefined_reason(const json& metrics, const std::string& metric) {
    const auto dot = metric.rfind('.');
    const json* parent = lookup(metrics, metric.substr(0, dot));
    if (!parent || !parent->is_object() || !parent->contains("undefined")) return {};
    const json& u = (*parent)["undefined"];
    const std::string key = metric.substr(dot + 1);
    return u.contains(key) && u[key].is_string() ? u[key].get<std::string>() : std::string();
}

// An order check (`near` on an order fit's slope) fails when the fit's finest steps disagree with
// its slope beyond the check's tolerance (diagnostics/order_fit.hpp).
std::string finest_disagreement(const CheckSpec& cs, const json& metrics, const std::string& diag) {
    if (cs.op != CheckOp::near ||
        (diag != OrderDiagnostic::name && diag != LocalOrderDiagnostic::name) ||
        cs.metric != diag + ".slope" || !metrics.contains(diag))
        return {};
    const json& fit = metrics[diag];
    if (!fit.contains("slope") || !fit.contains("finest_local_order")) return {};
    return finest_steps_disagree(fit["slope"].get<double>(),
                                 fit["finest_local_order"].get<double>(), cs.tol);
}

json check_head(const CheckSpec& cs, const std::string& method) {
    json ck = {{"name", cs.name},      {"metric", cs.metric},
               {"method", method},     {"op", op_name(cs.op)},
               {"expected", cs.value}, {"negative_control", cs.negative_control}};
    if (cs.op == CheckOp::near) ck["tolerance"] = cs.tol;
    if (cs.use_abs) ck["abs"] = true;
    if (cs.refutes) ck["refutes"] = true;
    if (!cs.note.empty()) ck["note"] = cs.note;
    return ck;
}

struct CheckContext {
    const CaseSpec& c;
    const std::vector<json>& runs;
    const json& reference;
    bool reference_ok;
    const json& run(std::size_t m, std::size_t d) const { return runs[m * c.dts.size() + d]; }
    std::size_t index_of(const std::string& mid) const {
        return static_cast<std::size_t>(std::find(c.methods.begin(), c.methods.end(), mid) -
                                        c.methods.begin());
    }
};

// A per-method check on `metrics` (a run's, with `run`, or a method's).
json evaluate(const CheckContext& x, const CheckSpec& cs, const std::string& mid,
              const json& metrics, const json* run) {
    const std::string diag = cs.metric.substr(0, cs.metric.find('.'));
    const DiagnosticInfo* info = find_diagnostic(diag);
    const bool method_level = info && info->level == DiagnosticLevel::method;
    json ck = check_head(cs, mid);
    if (run) ck["dt"] = (*run)["dt"];
    // "run.*" reads the run record itself; a diagnostic with any_status (stability: the one-step
    // matrix M, not the trajectory) is evaluated whatever the run's status.
    const json run_view = diag == "run" && run ? run_record_metrics(*run) : json();
    const json* v = lookup(diag == "run" ? run_view : metrics, cs.metric);
    auto fail_with = [&](const std::string& why) {
        ck["passed"] = false;
        ck["value"] = nullptr;
        ck["message"] = why;
        return ck;
    };
    if (run && (*run)["status"] != "ok" && diag != "run" && !(info && info->any_status))
        return fail_with(
            "run " + (*run)["status"].get<std::string>() +
            ((*run).contains("failed_at_step")
                 ? " at step " + std::to_string((*run)["failed_at_step"].get<std::int64_t>())
                 : std::string()));
    if (diag != "run")
        if (const std::string why = incomplete_measurement(metrics, diag); !why.empty())
            return fail_with(why);
    if ((!v || !v->is_number()) && !x.reference_ok && info && info->reads_reference)
        return fail_with("reference failed: " + x.reference.value("error", std::string()));
    // defined nowhere here (metric_json.hpp, docs/conventions.md): fails, whatever the check's
    // direction (a negative control too), with the reason
    if (v && v->is_null() && !undefined_reason(metrics, cs.metric).empty())
        return fail_with("metric undefined: " + undefined_reason(metrics, cs.metric));
    if (!v || !v->is_number())
        return fail_with("metric not produced" +
                         (method_level && metrics.contains(diag) && metrics[diag].contains("reason")
                              ? ": " + metrics[diag]["reason"].get<std::string>()
                              : std::string()));
    const double value = v->get<double>();
    ck["value"] = value;
    ck["passed"] = check_passes(cs, value);
    if (const std::string why = finest_disagreement(cs, metrics, diag); !why.empty()) {
        ck["passed"] = false;
        ck["message"] = why;
    }
    return ck;
}

// One (dt, value) input of a comparison check; false (and `missing` set) when a run lacks it.
bool comparison_row(const CheckContext& x, const CheckSpec& cs,
                    const std::vector<std::string>& members, std::size_t d, json& row,
                    std::vector<double>& xs, std::string& missing) {
    for (const auto& m : members) {
        const json& r = x.run(x.index_of(m), d);
        const json* v = r.contains("metrics") ? lookup(r["metrics"], cs.metric) : nullptr;
        const std::string diag = cs.metric.substr(0, cs.metric.find('.'));
        const std::string why = r.contains("metrics") && diag != "run"
                                    ? incomplete_measurement(r["metrics"], diag)
                                    : std::string();
        if (!why.empty()) {
            if (missing.empty()) missing = m + " at dt = " + json(x.c.dts[d]).dump() + ": " + why;
            row[m] = nullptr;
            continue;
        }
        if (r.value("status", std::string()) != "ok" || !v || !v->is_number()) {
            if (missing.empty())
                missing = m + " at dt = " + json(x.c.dts[d]).dump() + ": " +
                          (r.value("status", std::string()) != "ok"
                               ? "run " + r.value("status", std::string("missing"))
                               : "metric not produced");
            row[m] = nullptr;
            continue;
        }
        xs.push_back(v->get<double>());
        row[m] = xs.back();
    }
    return xs.size() == members.size();
}

// A check that combines runs (docs/case-keys.md): the ratio metric(A) / metric(B) or the spread
// max/min over several methods at each step size, or (across_dt) the log–log slope of those
// values, or of one method's metric, against dt over the ladder. One check entry; its "inputs"
// list every metric value it used.
json comparison_check(const CheckContext& x, const CheckSpec& cs, const std::string& mid,
                      std::optional<double> only_dt) {
    const std::vector<std::string> members =
        cs.form == CheckForm::per_method ? std::vector<std::string>{mid} : cs.methods;
    std::string label;
    const char* sep = cs.form == CheckForm::ratio ? " / " : ", ";
    for (const auto& m : members) label += (label.empty() ? "" : sep) + m;
    if (cs.form == CheckForm::spread) label = "spread(" + label + ")";
    json ck = check_head(cs, label);
    ck["form"] = cs.form == CheckForm::ratio    ? "ratio"
                 : cs.form == CheckForm::spread ? "spread"
                                                : "per-method";
    ck["methods"] = members;
    if (cs.across_dt_slope) ck["across_dt"] = "loglog-slope";
    if (only_dt) ck["dt"] = *only_dt;
    json inputs = json::array();
    std::vector<double> hs, values;
    std::string missing;
    for (std::size_t d = 0; d < x.c.dts.size(); ++d) {
        if (only_dt && *only_dt != x.c.dts[d]) continue;
        json row = {{"dt", x.c.dts[d]}};
        std::vector<double> xs;
        if (comparison_row(x, cs, members, d, row, xs, missing)) {
            double v = xs[0];
            if (cs.form == CheckForm::ratio) {
                v = xs[0] / xs[1];
            } else if (cs.form == CheckForm::spread) {
                v = *std::max_element(xs.begin(), xs.end()) /
                    *std::min_element(xs.begin(), xs.end());
            }
            row["value"] = v;
            hs.push_back(x.c.dts[d]);
            values.push_back(v);
        }
        inputs.push_back(row);
    }
    ck["inputs"] = inputs;
    auto fail_with = [&](const std::string& why) {
        ck["passed"] = false;
        ck["value"] = nullptr;
        ck["message"] = why;
        return ck;
    };
    if (!missing.empty()) return fail_with(missing);
    double value = 0.0;
    if (cs.across_dt_slope) {
        std::vector<double> lx, ly;
        for (std::size_t i = 0; i < hs.size(); ++i) {
            if (!(values[i] > 0.0) || !std::isfinite(values[i]))
                return fail_with("log-log slope needs positive values");
            lx.push_back(std::log(hs[i]));
            ly.push_back(std::log(values[i]));
        }
        value = least_squares(lx, ly).slope;
    } else {
        value = values.front(); // one step size (only_dt)
    }
    ck["value"] = value;
    ck["passed"] = std::isfinite(value) && check_passes(cs, value);
    return ck;
}

} // namespace

json evaluate_checks(const CaseSpec& c, const std::vector<json>& runs,
                     const std::vector<json>& method_metrics, const json& reference,
                     bool reference_ok) {
    const CheckContext x{c, runs, reference, reference_ok};
    json checks = json::array();
    for (const CheckSpec& cs : c.checks) {
        const std::string diag = cs.metric.substr(0, cs.metric.find('.'));
        const DiagnosticInfo* info = find_diagnostic(diag);
        const bool method_level = info && info->level == DiagnosticLevel::method;
        for (const std::string& mid : cs.methods) {
            const std::size_t mi = x.index_of(mid);
            if (cs.form != CheckForm::per_method || cs.across_dt_slope) {
                if (&mid != &cs.methods.front() && cs.form != CheckForm::per_method) continue;
                if (cs.across_dt_slope) {
                    checks.push_back(comparison_check(x, cs, mid, std::nullopt));
                } else {
                    for (double h : c.dts)
                        if (!cs.dt || *cs.dt == h)
                            checks.push_back(comparison_check(x, cs, mid, h));
                }
            } else if (method_level) {
                checks.push_back(evaluate(x, cs, mid, method_metrics[mi], nullptr));
            } else {
                for (std::size_t d = 0; d < c.dts.size(); ++d) {
                    if (cs.dt && *cs.dt != c.dts[d]) continue;
                    const json& r = x.run(mi, d);
                    checks.push_back(evaluate(x, cs, mid, r["metrics"], &r));
                }
            }
        }
    }
    return checks;
}

json not_run_checks(const CaseSpec& c) {
    json out = json::array();
    for (const NotRunCheck& nr : c.checks_not_run) {
        std::string label;
        for (const auto& m : nr.spec.methods) label += (label.empty() ? "" : ", ") + m;
        json ck = check_head(nr.spec, label);
        ck["methods"] = nr.spec.methods;
        ck["reason"] = nr.reason;
        out.push_back(ck);
    }
    return out;
}

} // namespace dampsym::detail
