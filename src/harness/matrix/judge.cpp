// The method × property matrix, the judging: each method × property cell from the battery's
// report — the measured value, a verdict (holds / fails / n/a) from the property's criterion
// evaluated with the runner's own check_passes, and its role (claimed, negative control or n/a)
// (docs/matrix.md). The battery is matrix/battery.cpp, the Markdown table matrix/render.cpp.
#include "harness/matrix/matrix.hpp"

#include "diagnostics/conformal_symplectic_diagnostic.hpp"
#include "diagnostics/metric_json.hpp"
#include "diagnostics/momentum_diagnostic.hpp"
#include "diagnostics/order_diagnostic.hpp"
#include "diagnostics/order_fit.hpp"
#include "diagnostics/stability.hpp"
#include "diagnostics/stability_sweep_diagnostic.hpp"
#include "harness/matrix/battery.hpp"
#include "harness/problem_info.hpp"
#include "harness/run/runner.hpp"
#include "harness/user_methods/method_coefficients.hpp"
#include "methods/coefficient_checks.hpp"
#include "methods/runtime_methods.hpp"

#include <map>
#include <optional>

namespace dampsym {
namespace matrix_detail {
namespace {

// The run of method m in a case's report (the single step size of the property's case).
const json* find_run(const json& c, const std::string& m) {
    if (!c.contains("runs")) return nullptr;
    for (const auto& r : c["runs"])
        if (r.value("method", "") == m) return &r;
    return nullptr;
}

const json* dotted(const json& root, const std::string& path) {
    const json* cur = &root;
    std::size_t start = 0;
    while (start <= path.size()) {
        const std::size_t dot = path.find('.', start);
        const std::string key = path.substr(start, dot == std::string::npos ? dot : dot - start);
        if (!cur->is_object() || !cur->contains(key)) return nullptr;
        cur = &(*cur)[key];
        if (dot == std::string::npos) break;
        start = dot + 1;
    }
    return cur;
}

// The method-level metrics of diagnostic `diag` of method m in a case's report, or nullptr.
const json* method_metric(const json& c, const MethodInfo& m, std::string_view diag_name) {
    const std::string diag(diag_name);
    const std::string id(m.id); // ids may hold characters dotted() would split on
    if (!c.contains("method_metrics") || !c["method_metrics"].contains(id)) return nullptr;
    const json& mm = c["method_metrics"][id];
    return mm.contains(diag) ? &mm[diag] : nullptr;
}

struct Cell {
    std::optional<double> value;
    std::string verdict = "n/a"; // holds, fails, n/a
    std::string role = "n/a";    // claimed, control (not claimed: a comparison), n/a
    bool claimed = false;
    std::string detail; // what the value is, or why n/a / why it fails
    json extra = json::object();
};

json cell_json(const Cell& c, bool controls_must_fail) {
    json j = {{"value", c.value ? json(*c.value) : json(nullptr)},
              {"verdict", c.verdict},
              {"role", c.role},
              {"claimed", c.claimed}};
    if (!c.detail.empty()) j["detail"] = c.detail;
    // the disagreements that make `dampsym matrix` exit 1
    const bool claimed_fails = c.claimed && c.verdict == "fails";
    const bool control_passes = c.role == "control" && c.verdict == "holds" && controls_must_fail;
    j["agrees"] = !(claimed_fails || control_passes);
    for (auto it = c.extra.begin(); it != c.extra.end(); ++it) j[it.key()] = it.value();
    return j;
}

void set_role(Cell& cell, bool claimed) {
    cell.claimed = claimed;
    if (cell.verdict == "n/a")
        cell.role = "n/a";
    else
        cell.role = claimed ? "claimed" : "control";
}

// Value of a finished run's metric, or why there is none.
Cell judge_run_metric(const Property& p, const MethodInfo& m, const json& run) {
    Cell cell;
    const bool claimed = claims_property(p, m);
    std::string metric = p.metric;
    if (p.id == "linear-momentum" && (m.claims & claim_linear_momentum_cayley) != 0 &&
        (m.claims & claim_linear_momentum) == 0) {
        metric = std::string(MomentumDiagnostic::name) + ".linear.max_table_res";
        cell.extra["law"] = "e^{-gamma h}(2 - gamma h)/(2 + gamma h) (B Table 3.1)";
    } else if (p.id == "linear-momentum") {
        cell.extra["law"] = "e^{-2 gamma h}";
    }
    cell.extra["metric"] = metric;
    const std::string status = run.value("status", "");
    if (status == "not-applicable") {
        cell.detail = "the method does not apply to this problem";
        return cell;
    }
    if (status != "ok") { // not measured: a failure of a claimed property, else n/a
        cell.detail = "run " + status;
        if (claimed) cell.verdict = "fails";
        set_role(cell, claimed);
        return cell;
    }
    const std::string incomplete =
        incomplete_measurement(run["metrics"], metric.substr(0, metric.find('.')));
    if (!incomplete.empty()) { // not measured: a failure of a claimed property, else n/a
        cell.detail = incomplete;
        if (claimed) cell.verdict = "fails";
        set_role(cell, claimed);
        return cell;
    }
    const json* v = dotted(run["metrics"], metric);
    if (v && v->is_number()) {
        cell.value = v->get<double>();
        CheckSpec crit = p.criterion;
        // A plugin's E_n from central differences of its step (methods/plugin_kernel.hpp): the
        // entries of Ψ are good to about ε^{2/3} ≈ 4e-11 relative, so the round-off criterion
        // becomes 1e-8 (docs/plugins.md); the cell says so.
        const std::string cs(ConformalSymplecticDiagnostic::name);
        const json* src = dotted(run["metrics"], cs + ".jacobian");
        if (metric == cs + ".max_rel" && src && src->is_string() &&
            src->get<std::string>() == "central-differences" && crit.op == CheckOp::le) {
            crit.value = std::max(crit.value, 1e-8);
            cell.extra["jacobian"] = "central differences (criterion 1e-8)";
        }
        cell.verdict = check_passes(crit, *cell.value) ? "holds" : "fails";
    } else {
        const std::string diag = metric.substr(0, metric.find('.'));
        const json* d = dotted(run["metrics"], diag);
        cell.detail = "metric not defined";
        if (d && d->contains("reason") && (*d)["reason"].is_string())
            cell.detail = (*d)["reason"].get<std::string>();
        else if (d && d->contains("undefined")) {
            const std::string key = metric.substr(metric.rfind('.') + 1);
            const json* why = dotted(*d, "undefined." + key);
            if (why && why->is_string()) cell.detail = why->get<std::string>();
        }
        if (claimed) { // a claimed property must be measured
            cell.verdict = "fails";
            cell.detail = "claimed but not measured: " + cell.detail;
        }
    }
    set_role(cell, claimed);
    return cell;
}

Cell judge_coefficients(const MethodInfo& m) {
    Cell cell;
    const CoefficientVerdict v = coefficient_verdict(m);
    if (!v.checked()) {
        cell.detail = "no coefficients to check (the method is its code)";
        return cell;
    }
    cell.value = v.disagree;
    cell.verdict = v.disagree == 0 ? "holds" : "fails";
    cell.extra["agree"] = v.agree;
    cell.extra["checks"] = v.agree + v.disagree;
    cell.extra["refuted"] = v.refuted;
    if (v.disagree > 0) {
        std::string names;
        for (const auto& n : v.refuted) names += (names.empty() ? "" : ", ") + n;
        cell.detail = "the coefficients refute the declaration: " + names;
    }
    set_role(cell, true);
    return cell;
}

Cell judge_order(const Property& p, const MethodInfo& m, const json& c) {
    Cell cell;
    cell.extra["declared"] = m.order;
    cell.extra["ladder"] = order_ladder(m.order);
    const json* fit = method_metric(c, m, OrderDiagnostic::name);
    const bool fit_ok = fit && fit->value("status", std::string("ok")) == "ok";
    if (fit_ok && fit->contains("slope") && (*fit)["slope"].is_number()) {
        cell.value = (*fit)["slope"].get<double>();
        CheckSpec crit = p.criterion;
        crit.value = m.order;
        cell.verdict = check_passes(crit, *cell.value) ? "holds" : "fails";
        if (fit->contains("r2")) cell.extra["r2"] = (*fit)["r2"];
        if (fit->contains("finest_local_order")) {
            const double finest = (*fit)["finest_local_order"].get<double>();
            cell.extra["finest_local_order"] = finest;
            if (const std::string why = finest_steps_disagree(*cell.value, finest, crit.tol);
                !why.empty()) {
                cell.verdict = "fails";
                cell.detail = why;
            }
        }
    } else {
        cell.verdict = "fails";
        cell.detail = "no order fit";
        if (fit && fit->contains("status") && (*fit)["status"].is_string())
            cell.detail += ": " + (*fit)["status"].get<std::string>();
        if (fit && fit->contains("reason") && (*fit)["reason"].is_string())
            cell.detail += ": " + (*fit)["reason"].get<std::string>();
    }
    set_role(cell, true);
    return cell;
}

Cell judge_threshold(const Property& p, const MethodInfo& m, const json& c) {
    Cell cell;
    const json* s = method_metric(c, m, StabilitySweepDiagnostic::name);
    if (!s) {
        cell.detail = "no sweep";
        return cell;
    }
    auto h_at = [&](const char* key) -> std::optional<double> {
        const json* h = dotted(*s, std::string("first_row.") + key);
        if (h && h->is_number()) return h->get<double>();
        return std::nullopt;
    };
    const bool has_F = s->contains("max_boundary_mismatch_cells");
    const bool has_R = s->contains("max_power_boundary_mismatch_cells");
    if (has_F) {
        cell.value = h_at("h_F_empirical");
        cell.detail = "F's condition |tr M/2| < e^{-gamma h} vs " +
                      s->value("formula_source", std::string("F's closed form"));
        const double cells = (*s)["max_boundary_mismatch_cells"].get<double>();
        cell.extra["mismatch_cells"] = cells;
        cell.extra["mismatch_points"] = s->value("mismatch_points", json(nullptr));
        cell.extra["formula"] = s->value("formula_source", "");
        cell.verdict = check_passes(p.criterion, cells) ? "holds" : "fails";
    } else if (has_R) {
        cell.value = h_at("h_power_unbounded");
        cell.detail = "power-boundedness vs the stability function R(z) of the tableau";
        const double cells = (*s)["max_power_boundary_mismatch_cells"].get<double>();
        cell.extra["mismatch_cells"] = cells;
        cell.extra["mismatch_points"] = s->value("power_mismatch_points", json(nullptr));
        cell.extra["formula"] = "R(z)";
        cell.verdict = check_passes(p.criterion, cells) ? "holds" : "fails";
    } else {
        cell.extra["swept"] = true;
        cell.value = h_at("h_power_unbounded");
        cell.detail = "no closed form for this method: measured first h where M is not "
                      "power-bounded (null: none on the grid)";
    }
    cell.extra["h_F_empirical"] = h_at("h_F_empirical") ? json(*h_at("h_F_empirical")) : json();
    cell.extra["h_power_unbounded"] =
        h_at("h_power_unbounded") ? json(*h_at("h_power_unbounded")) : json();
    if (cell.verdict != "n/a") {
        cell.claimed = true; // a closed form states the threshold
        cell.role = "claimed";
    }
    return cell;
}

} // namespace
} // namespace matrix_detail

namespace {
using json = nlohmann::json;
} // namespace

json judge_matrix(const std::vector<const MethodInfo*>& methods, const json& battery_report) {
    std::map<std::string, const json*> by_id;
    for (const auto& c : battery_report["cases"]) by_id[c.value("id", "")] = &c;
    json props = json::array();
    for (const matrix_detail::Property& p : matrix_detail::properties())
        props.push_back(
            {{"id", p.id},
             {"header", p.header},
             {"title", p.title},
             {"source", p.source},
             {"criterion", p.criterion_text},
             {"claimed_by", p.from == matrix_detail::Source::order ? json("the declared order")
                            : p.from == matrix_detail::Source::coefficients
                                ? json("the declared order and claims")
                            : p.from == matrix_detail::Source::threshold
                                ? json("a closed form (F ch. 3 or R(z))")
                                : json(claim_words(p.claim))},
             {"controls_must_fail", p.controls_must_fail},
             {"problem", p.case_json.contains("problem") ? p.case_json["problem"] : json()}});
    json rows = json::array();
    int claimed_failures = 0, controls_passing = 0, controls = 0, claimed_holds = 0;
    for (const MethodInfo* m : methods) {
        const std::string id(m->id);
        json cells = json::object();
        for (const matrix_detail::Property& p : matrix_detail::properties()) {
            matrix_detail::Cell cell;
            const std::string case_id =
                p.from == matrix_detail::Source::order
                    ? p.case_id + std::to_string(matrix_detail::ladder_group(m->order))
                    : p.case_id;
            const auto it = by_id.find(case_id);
            if (p.from == matrix_detail::Source::coefficients) {
                cell = matrix_detail::judge_coefficients(*m);
            } else if (!method_applies(m->id, p.problem) || it == by_id.end()) {
                cell.detail = "the method (" + std::string(form_name(m->form)) +
                              " form) does not apply to problem '" + p.problem + "'";
            } else if (p.from == matrix_detail::Source::order) {
                cell = matrix_detail::judge_order(p, *m, *it->second);
            } else if (p.from == matrix_detail::Source::threshold) {
                cell = matrix_detail::judge_threshold(p, *m, *it->second);
            } else if (const json* run = matrix_detail::find_run(*it->second, id)) {
                cell = matrix_detail::judge_run_metric(p, *m, *run);
            } else {
                cell.detail = "no run";
            }
            json j = matrix_detail::cell_json(cell, p.controls_must_fail);
            j["case"] = case_id;
            if (cell.claimed && cell.verdict == "fails") ++claimed_failures;
            if (cell.claimed && cell.verdict == "holds") ++claimed_holds;
            if (cell.role == "control") ++controls;
            if (!j["agrees"].get<bool>() && !cell.claimed) ++controls_passing;
            cells[p.id] = j;
        }
        rows.push_back({{"id", id},
                        {"order", m->order},
                        {"form", std::string(form_name(m->form))},
                        {"implicit", m->implicit},
                        {"claims", claim_words(m->claims)},
                        {"citation", std::string(m->citation)},
                        {"built_in", find_loaded_method(m->id) != m},
                        {"cells", cells}});
    }
    return {{"schema", "dampsym-matrix/1"},
            {"properties", props},
            {"methods", rows},
            {"summary",
             {{"methods", methods.size()},
              {"claimed_holds", claimed_holds},
              {"claimed_failures", claimed_failures},
              {"controls", controls},
              {"controls_passing", controls_passing}}}};
}

int matrix_exit_status(const json& matrix) {
    const json& s = matrix["summary"];
    return s["claimed_failures"].get<int>() == 0 && s["controls_passing"].get<int>() == 0 ? 0 : 1;
}

} // namespace dampsym
