// The method × property matrix (docs/matrix.md). The battery is one table (properties()): each
// property names its case settings (taken from the default suite's cases, cited), the metric it
// reads, its criterion, which declaration makes a method claim it and whether its negative
// controls must fail. Cases are built as JSON and validated by parse_case, so they are ordinary
// cases; the verdicts evaluate the criterion with the runner's own check_passes.
#include "harness/matrix.hpp"

#include "diagnostics/stability.hpp"
#include "harness/problem_info.hpp"
#include "harness/runner.hpp"
#include "methods/coefficient_checks.hpp"
#include "methods/runtime_methods.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fnmatch.h>
#include <map>
#include <optional>
#include <sstream>

namespace dampsym {
namespace {

using json = nlohmann::json;

// How a property reads its value from the battery's report.
enum class Source {
    order,     // method_metrics[m].order.slope of the case of the method's ladder
    run,       // runs[m].metrics.<metric> of the property's single-step case
    threshold, // method_metrics[m].stability-sweep of the sweep case
};

struct Property {
    std::string id, header, title, source;
    Source from = Source::run;
    std::string case_id; // the battery case (order: the prefix of the ladder cases)
    std::string problem; // problem id (for method_applies)
    json case_json;      // the case's settings (problem, t_end, dt, diagnostics, ...)
    std::string metric;  // "<diagnostic>.<path>" (run); for the order/threshold sources unused
    CheckSpec criterion; // what "holds" means (op, value, tol, abs)
    unsigned claim = 0;  // the claim bit that makes a method claim the property
    bool controls_must_fail = false;
    std::string criterion_text;
};

CheckSpec criterion(CheckOp op, double value, double tol = 0.0, bool use_abs = false) {
    CheckSpec c;
    c.op = op;
    c.value = value;
    c.tol = tol;
    c.use_abs = use_abs;
    return c;
}

// The order ladders on the pendulum (step sizes of verify/cases/families-orders-*.json, where the
// error of a method of that order stays above the fit's floor and in the asymptotic range).
std::vector<double> order_ladder(int order) {
    if (order <= 1) return {0.02, 0.01, 0.005, 0.0025};
    if (order == 2) return {0.1, 0.05, 0.025, 0.0125};
    if (order <= 5) return {0.2, 0.1, 0.05, 0.025};
    return {1.0, 0.625, 0.5, 0.3125};
}
int ladder_group(int order) {
    return order <= 1 ? 1 : order == 2 ? 2 : order <= 5 ? 4 : 6;
}

// The battery (docs/matrix.md "The battery" lists it with the same settings and tolerances).
const std::vector<Property>& properties() {
    static const std::vector<Property> props = [] {
        std::vector<Property> p;
        {
            Property o;
            o.id = "order";
            o.header = "order (pendulum)";
            o.title = "fitted convergence order on the damped pendulum";
            o.source = "verify/cases/families-orders-*.json; docs/conventions.md §5 order";
            o.from = Source::order;
            o.case_id = "matrix-order-";
            o.problem = "pendulum";
            o.case_json = {
                {"problem", {{"id", "pendulum"}, {"gamma", 0.1}, {"q0", 1.0}, {"p0", 0.0}}},
                {"t_end", 10.0},
                {"reference", {{"epsrel", 1e-14}, {"epsabs", 1e-15}}},
                {"diagnostics", {"error", "order"}}};
            o.criterion = criterion(CheckOp::near, 0.0, 0.1); // value: the declared order
            o.criterion_text = "|slope − declared order| ≤ 0.1";
            p.push_back(o);
        }
        const json cs_diag = {"conformal-symplectic"};
        {
            Property e;
            e.id = "en-pendulum";
            e.header = "E_n pendulum";
            e.title = "conformal symplecticity: max_n E_n (relative) on the damped pendulum";
            e.source = "verify/cases/cs-pendulum.json; B(2.42), B(3.2)";
            e.case_id = "matrix-en-pendulum";
            e.problem = "pendulum";
            e.case_json = {
                {"problem", {{"id", "pendulum"}, {"gamma", 0.1}, {"q0", 2.0}, {"p0", 0.5}}},
                {"t_end", 50.0},
                {"dt", 0.5},
                {"diagnostics", cs_diag}};
            e.metric = "conformal-symplectic.max_rel";
            e.criterion = criterion(CheckOp::le, 1e-13);
            e.claim = claim_conformal_symplectic;
            e.controls_must_fail = true;
            e.criterion_text = "max_n E_n ≤ 1e-13";
            p.push_back(e);
            e.id = "en-hill";
            e.header = "E_n Hill";
            e.title = "conformal symplecticity: max_n E_n (relative) on Hill's equation, "
                      "γ(t) = 0.5 cos 2t";
            e.source = "verify/cases/cs-hill.json; B(2.42), B(3.2), B Fig 3.3";
            e.case_id = "matrix-en-hill";
            e.problem = "hill";
            e.case_json["problem"] = {
                {"id", "hill"}, {"epsilon", 1.0}, {"kappa", 1.0}, {"q0", 1.0}, {"p0", 0.0}};
            p.push_back(e);
        }
        {
            Property e;
            e.id = "en-pendulum-undamped";
            e.header = "E_n pendulum γ = 0";
            e.title = "symplecticity: max_n E_n (relative) on the undamped pendulum (γ = 0, "
                      "where a conformal symplectic method is symplectic)";
            e.source = "verify/cases/cs-pendulum.json at gamma = 0; HLW VI, B(2.42)";
            e.case_id = "matrix-en-pendulum-undamped";
            e.problem = "pendulum";
            e.case_json = {
                {"problem", {{"id", "pendulum"}, {"gamma", 0.0}, {"q0", 2.0}, {"p0", 0.5}}},
                {"t_end", 50.0},
                {"dt", 0.5},
                {"diagnostics", cs_diag}};
            e.metric = "conformal-symplectic.max_rel";
            e.criterion = criterion(CheckOp::le, 1e-13);
            e.claim = claim_conformal_symplectic | claim_symplectic_if_undamped;
            e.criterion_text = "max_n E_n ≤ 1e-13";
            p.push_back(e);
        }
        {
            Property h;
            h.id = "hgamma-oscillator";
            h.header = "H_γ law (oscillator)";
            h.title = "conformal law H_{n+1} = e^{-2γh} H_n of H_γ = ½(ω²q² + p²) + γqp on the "
                      "oscillator, max per-step residual";
            h.source = "verify/cases/osc-orders.json; B Ex. 1.2, B Def. 2.3";
            h.case_id = "matrix-hgamma-oscillator";
            h.problem = "oscillator";
            h.case_json = {{"problem",
                            {{"id", "oscillator"},
                             {"omega", 1.0},
                             {"gamma", 0.025},
                             {"q0", 1.0},
                             {"p0", 0.0}}},
                           {"t_end", 10.0},
                           {"dt", 0.1},
                           {"diagnostics", {"invariants"}}};
            h.metric = "invariants.H_gamma.max_step_res";
            h.criterion = criterion(CheckOp::le, 1e-13);
            h.claim = claim_conformal_quadratic;
            h.criterion_text = "max per-step residual ≤ 1e-13";
            p.push_back(h);
        }
        {
            Property n;
            n.id = "linear-momentum";
            n.header = "Σp law (N-body)";
            n.title = "linear momentum per step on the damped 3-body problem: e^{-2γh} (claim "
                      "linear-momentum) or B Table 3.1's e^{-γh}(2-γh)/(2+γh) (claim "
                      "linear-momentum-cayley)";
            n.source = "verify/cases/nbody-table31-momentum.json; B Table 3.1, B(3.9)";
            n.case_id = "matrix-nbody";
            n.problem = "nbody";
            n.case_json = {{"problem", {{"id", "nbody"}, {"gamma", 0.1}}},
                           {"t_end", 2.5},
                           {"dt", 0.05},
                           {"diagnostics", {"momentum"}}};
            n.metric = "momentum.linear.max_law_res"; // max_table_res for the Cayley claim
            n.criterion = criterion(CheckOp::le, 1e-13);
            n.claim = claim_linear_momentum | claim_linear_momentum_cayley;
            n.criterion_text = "max per-step residual of the claimed factor ≤ 1e-13 (unclaimed: "
                               "of e^{-2γh})";
            p.push_back(n);
            n.id = "angular-momentum";
            n.header = "Σq×p law (N-body)";
            n.title = "angular momentum per step on the damped 3-body problem: e^{-2γh}";
            n.metric = "momentum.angular.max_law_res";
            n.criterion = criterion(CheckOp::le, 1e-12);
            n.claim = claim_angular_momentum;
            n.criterion_text = "max per-step residual ≤ 1e-12";
            p.push_back(n);
        }
        {
            Property r;
            r.id = "quadratic-undamped";
            r.header = "quadratic inv. γ = 0 (rigid body)";
            r.title = "drift of the quadratic Casimir |z|² on BS's undamped rigid body: "
                      "least-squares slope of |F_n/F_0 − 1| per unit time";
            r.source = "verify/cases/rb-bs-glm4.json over 10^4 instead of 10^5 steps; BS, BD §3";
            r.case_id = "matrix-quadratic-rigid-body";
            r.problem = "rigid-body";
            r.case_json = {{"problem",
                            {{"id", "rigid-body"},
                             {"epsilon", 0.0},
                             {"I1", 4.0},
                             {"I2", 3.0},
                             {"I3", 2.0},
                             {"z1", 4.0},
                             {"z2", 3.0},
                             {"z3", 0.0}}},
                           {"t_end", 1000.0},
                           {"dt", 0.1},
                           {"diagnostics", {"invariants"}}};
            r.metric = "invariants.casimir.ratio_dev_slope";
            r.criterion = criterion(CheckOp::le, 1e-11, 0.0, true);
            r.claim = claim_g_symplectic | claim_conformal_quadratic;
            r.criterion_text = "|slope| ≤ 1e-11 per unit time";
            p.push_back(r);
        }
        {
            Property d;
            d.id = "drift";
            d.header = "d(t) drift (oscillator)";
            d.title = "slope of d(t) = ln(max q) + γt over the maxima on the oscillator (F(4.4))";
            d.source = "verify/cases/osc-drift-fig47.json; F Figs 4.6, 4.7, F(4.4)";
            d.case_id = "matrix-drift-oscillator";
            d.problem = "oscillator";
            d.case_json = {{"problem", {{"id", "oscillator"}, {"omega", 1.0}, {"gamma", 0.005}}},
                           {"t_end", 1000.0},
                           {"dt", 0.5},
                           {"diagnostics", {"dissipation-drift"}}};
            d.metric = "dissipation-drift.slope";
            d.criterion = criterion(CheckOp::le, 1e-4, 0.0, true);
            d.claim = claim_conformal_symplectic;
            d.criterion_text = "|slope| ≤ 1e-4";
            p.push_back(d);
        }
        {
            Property s;
            s.id = "threshold";
            s.header = "threshold h* (oscillator)";
            s.title = "stability threshold on the oscillator ω = 3.51 over γ ∈ [0, 3.5], h ∈ "
                      "[0.025, 1]: the kernel's one-step matrix against F's closed form (F's "
                      "condition) or the tableau's stability function R(z) (power-boundedness); "
                      "value: the first h of the γ = 0 row where it fails";
            s.source = "verify/cases/osc-stability-sweep.json; F(3.12), (3.17), (3.22), F Figs "
                       "3.1-3.3";
            s.from = Source::threshold;
            s.case_id = "matrix-threshold-oscillator";
            s.problem = "oscillator";
            s.case_json = {
                {"problem", {{"id", "oscillator"}, {"omega", 3.51}, {"gamma", 1.0}}},
                {"t_end", 1.0},
                {"dt", 0.1},
                {"diagnostics", {"stability-sweep"}},
                {"stability_sweep",
                 {{"omega", 3.51}, {"gamma", {0.0, 3.5, 0.25}}, {"h", {0.025, 1.0, 0.025}}}}};
            s.criterion = criterion(CheckOp::le, 1.0);
            s.criterion_text = "first failure per γ row within one h cell of the closed form's";
            p.push_back(s);
        }
        return p;
    }();
    return props;
}

bool claims_property(const Property& p, const MethodInfo& m) {
    if (p.from == Source::order) return true; // every method declares its order
    if (p.from == Source::threshold) return false;
    // an RK method on the plain form that is symplectic for γ = 0 conserves every quadratic
    // invariant (B(1.18), HLW IV.2); a partitioned one only those of the form qᵀCp
    if (p.id == "quadratic-undamped" && (m.claims & claim_symplectic_if_undamped) != 0 &&
        m.form == Form::plain)
        return true;
    return (m.claims & p.claim) != 0;
}

json base_case(const Property& p, const std::string& id, const std::vector<std::string>& methods) {
    json c = p.case_json;
    c["id"] = id;
    c["title"] = "matrix: " + p.title;
    c["source"] = p.source;
    c["suites"] = json::array({"matrix"});
    c["methods"] = methods;
    c["no_checks_because"] = "the method x property matrix judges the metrics against the "
                             "methods' declared claims (src/harness/matrix.cpp, docs/matrix.md)";
    return c;
}

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
const json* method_metric(const json& c, const MethodInfo& m, const std::string& diag) {
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
        metric = "momentum.linear.max_table_res";
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
    const json* v = dotted(run["metrics"], metric);
    if (v && v->is_number()) {
        cell.value = v->get<double>();
        cell.verdict = check_passes(p.criterion, *cell.value) ? "holds" : "fails";
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

Cell judge_order(const Property& p, const MethodInfo& m, const json& c) {
    Cell cell;
    cell.extra["declared"] = m.order;
    cell.extra["ladder"] = order_ladder(m.order);
    const json* fit = method_metric(c, m, "order");
    if (fit && fit->contains("slope") && (*fit)["slope"].is_number()) {
        cell.value = (*fit)["slope"].get<double>();
        CheckSpec crit = p.criterion;
        crit.value = m.order;
        cell.verdict = check_passes(crit, *cell.value) ? "holds" : "fails";
        if (fit->contains("r2")) cell.extra["r2"] = (*fit)["r2"];
    } else {
        cell.verdict = "fails";
        cell.detail = "no order fit";
        if (fit && fit->contains("reason") && (*fit)["reason"].is_string())
            cell.detail += ": " + (*fit)["reason"].get<std::string>();
    }
    set_role(cell, true);
    return cell;
}

Cell judge_threshold(const Property& p, const MethodInfo& m, const json& c) {
    Cell cell;
    const json* s = method_metric(c, m, "stability-sweep");
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

std::string fmt(double v, const char* f = "%.3g") {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

std::string cell_text(const std::string& prop, const json& c) {
    const std::string verdict = c["verdict"];
    const std::string role = c["role"];
    std::string v;
    if (c["value"].is_number()) {
        const double x = c["value"].get<double>();
        v = prop == "order" ? fmt(x, "%.2f") : fmt(x, "%.2g");
    } else if (prop == "threshold" && (verdict != "n/a" || c.contains("swept"))) {
        v = "none"; // no failure on the grid
    } else if (c.contains("detail") && c["detail"].get<std::string>().rfind("run ", 0) == 0) {
        v = c["detail"].get<std::string>().substr(4); // the run's status, e.g. solve-failed
    } else if (prop == "order") {
        v = "no fit"; // fewer than three consistent points (docs/conventions.md §5 order)
    }
    if (prop == "threshold" && !v.empty()) v = "h " + v;
    std::string mark;
    if (verdict == "n/a")
        mark = v.empty() ? "n/a" : "(n/a)";
    else if (role == "claimed")
        mark = verdict == "holds" ? "✓" : "✗ **FAILS**";
    else // control
        mark = verdict == "holds"
                   ? (c.value("agrees", true) ? "✓ (unclaimed)" : "✓ **(control passes)**")
                   : "✗ (control)";
    return v.empty() ? mark : v + " " + mark;
}

} // namespace

std::vector<const MethodInfo*> matrix_methods(const std::vector<std::string>& globs) {
    std::vector<const MethodInfo*> all;
    for (const auto& m : method_catalog()) all.push_back(&m);
    for (const MethodInfo* m : loaded_methods()) all.push_back(m); // method files, plugins
    std::vector<const MethodInfo*> out;
    for (const MethodInfo* m : all) {
        const std::string id(m->id);
        bool keep = globs.empty();
        for (const auto& g : globs)
            if (fnmatch(g.c_str(), id.c_str(), 0) == 0) keep = true;
        if (keep) out.push_back(m);
    }
    return out;
}

std::vector<CaseSpec> matrix_battery(const std::vector<const MethodInfo*>& methods) {
    std::vector<CaseSpec> cases;
    std::map<std::string, bool> made; // the N-body case serves two properties
    const std::string file = "dampsym matrix battery";
    for (const Property& p : properties()) {
        if (p.from == Source::order) {
            std::map<int, std::vector<std::string>> groups;
            for (const MethodInfo* m : methods)
                if (method_applies(m->id, p.problem))
                    groups[ladder_group(m->order)].push_back(std::string(m->id));
            for (const auto& [g, ms] : groups) {
                json c = base_case(p, p.case_id + std::to_string(g), ms);
                c["dt_ladder"] = order_ladder(g);
                cases.push_back(parse_case(c, file, {}));
            }
            continue;
        }
        if (made[p.case_id]) continue;
        made[p.case_id] = true;
        std::vector<std::string> ms;
        for (const MethodInfo* m : methods)
            if (method_applies(m->id, p.problem)) ms.push_back(std::string(m->id));
        if (ms.empty()) continue;
        cases.push_back(parse_case(base_case(p, p.case_id, ms), file, {}));
    }
    return cases;
}

json judge_matrix(const std::vector<const MethodInfo*>& methods, const json& battery_report) {
    std::map<std::string, const json*> by_id;
    for (const auto& c : battery_report["cases"]) by_id[c.value("id", "")] = &c;
    json props = json::array();
    for (const Property& p : properties())
        props.push_back(
            {{"id", p.id},
             {"header", p.header},
             {"title", p.title},
             {"source", p.source},
             {"criterion", p.criterion_text},
             {"claimed_by", p.from == Source::order       ? json("the declared order")
                            : p.from == Source::threshold ? json("a closed form (F ch. 3 or R(z))")
                                                          : json(claim_words(p.claim))},
             {"controls_must_fail", p.controls_must_fail},
             {"problem", p.case_json["problem"]}});
    json rows = json::array();
    int claimed_failures = 0, controls_passing = 0, controls = 0, claimed_holds = 0;
    for (const MethodInfo* m : methods) {
        const std::string id(m->id);
        json cells = json::object();
        for (const Property& p : properties()) {
            Cell cell;
            const std::string case_id = p.from == Source::order
                                            ? p.case_id + std::to_string(ladder_group(m->order))
                                            : p.case_id;
            const auto it = by_id.find(case_id);
            if (!method_applies(m->id, p.problem) || it == by_id.end()) {
                cell.detail = "the method (" + std::string(form_name(m->form)) +
                              " form) does not apply to problem '" + p.problem + "'";
            } else if (p.from == Source::order) {
                cell = judge_order(p, *m, *it->second);
            } else if (p.from == Source::threshold) {
                cell = judge_threshold(p, *m, *it->second);
            } else if (const json* run = find_run(*it->second, id)) {
                cell = judge_run_metric(p, *m, *run);
            } else {
                cell.detail = "no run";
            }
            json j = cell_json(cell, p.controls_must_fail);
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

std::string render_matrix_markdown(const json& matrix) {
    std::ostringstream md;
    md << "| method | order | claims |";
    for (const auto& p : matrix["properties"]) md << " " << p["header"].get<std::string>() << " |";
    md << "\n|---|---|---|";
    for (std::size_t i = 0; i < matrix["properties"].size(); ++i) md << "---|";
    md << "\n";
    for (const auto& m : matrix["methods"]) {
        std::string claims;
        for (const auto& w : m["claims"])
            claims += (claims.empty() ? "" : ", ") + w.get<std::string>();
        md << "| " << m["id"].get<std::string>() << (m["built_in"].get<bool>() ? "" : " (loaded)")
           << " | " << m["order"].get<int>() << " | " << (claims.empty() ? "none" : claims) << " |";
        for (const auto& p : matrix["properties"]) {
            const std::string pid = p["id"];
            md << " " << cell_text(pid, m["cells"][pid]) << " |";
        }
        md << "\n";
    }
    md << "\n✓ claimed and holds; ✗ **FAILS** claimed and fails; ✗ (control) not claimed and "
          "fails (a negative control); ✓ (unclaimed) not claimed but holds (allowed where the "
          "controls need not fail); ✓ **(control passes)** a negative control that holds where "
          "it must fail; n/a the method does not run on the problem or has no closed form. "
          "Criteria:\n\n";
    for (const auto& p : matrix["properties"]) {
        md << "- **" << p["header"].get<std::string>() << "**: " << p["title"].get<std::string>()
           << "; holds iff " << p["criterion"].get<std::string>() << " ("
           << p["source"].get<std::string>() << ")"
           << (p["controls_must_fail"].get<bool>() ? "; negative controls must fail" : "") << ".\n";
    }
    const json& s = matrix["summary"];
    md << "\n"
       << s["methods"].get<int>() << " methods: " << s["claimed_holds"].get<int>()
       << " claimed properties hold, " << s["claimed_failures"].get<int>() << " fail; "
       << s["controls"].get<int>() << " negative-control cells, "
       << s["controls_passing"].get<int>() << " passing where they must fail.\n";
    return md.str();
}

} // namespace dampsym
