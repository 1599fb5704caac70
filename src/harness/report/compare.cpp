#include "harness/report/compare.hpp"

#include "diagnostics/order_diagnostic.hpp"
#include "harness/case/case.hpp"
#include "harness/report/compare_input.hpp"
#include "harness/report/markdown.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <set>
#include <sstream>
#include <vector>

namespace dampsym {
namespace {

using json = nlohmann::json;

// Clock-dependent keys inside a case record (schema_version 1 kept them there).
bool clock_key(const std::string& k) {
    return k == "wall_seconds" || k == "timing";
}

using compare_detail::check_key;
using compare_detail::run_key;

struct Walker {
    const CompareOptions& opt;
    json& rows;
    std::string case_id, run;

    void row(const std::string& kind, const std::string& path, const json& a, const json& b) {
        json r = {{"case", case_id}, {"kind", kind}, {"path", path}, {"base", a}, {"new", b}};
        r["run"] = run.empty() ? json(nullptr) : json(run);
        if (a.is_number() && b.is_number()) {
            const double x = a.get<double>(), y = b.get<double>();
            r["abs_diff"] = std::abs(x - y);
            const double scale = std::max(std::abs(x), std::abs(y));
            r["rel_diff"] = scale > 0.0 ? std::abs(x - y) / scale : 0.0;
        }
        rows.push_back(r);
    }

    bool numbers_equal(double x, double y) const {
        if (x == y) return true;
        if (std::isnan(x) && std::isnan(y)) return true;
        return std::abs(x - y) <= opt.atol + opt.rtol * std::max(std::abs(x), std::abs(y));
    }

    // Structural comparison; `kind` labels every row found below this point.
    void walk(const json& a, const json& b, const std::string& path, const std::string& kind,
              bool skip_clock) {
        if (a.is_object() && b.is_object()) {
            std::set<std::string> keys;
            for (auto it = a.begin(); it != a.end(); ++it) keys.insert(it.key());
            for (auto it = b.begin(); it != b.end(); ++it) keys.insert(it.key());
            for (const auto& k : keys) {
                if (skip_clock && clock_key(k)) continue;
                const std::string p = path.empty() ? k : path + "." + k;
                if (!a.contains(k))
                    row(kind + " added", p, nullptr, b[k]);
                else if (!b.contains(k))
                    row(kind + " removed", p, a[k], nullptr);
                else
                    walk(a[k], b[k], p, kind, skip_clock);
            }
        } else if (a.is_array() && b.is_array()) {
            if (a.size() != b.size()) {
                row(kind, path + " (length)", a.size(), b.size());
                return;
            }
            for (std::size_t i = 0; i < a.size(); ++i)
                walk(a[i], b[i], path + "[" + std::to_string(i) + "]", kind, skip_clock);
        } else if (a.is_number() && b.is_number()) {
            if (!numbers_equal(a.get<double>(), b.get<double>())) row(kind, path, a, b);
        } else if (a != b) {
            row(kind, path, a, b);
        }
    }
};

std::string kind_of_run_field(const std::string& k) {
    if (k == "final_state") return "final state";
    if (k == "metrics") return "metric";
    if (k == "status" || k == "failed_at_step") return "run status";
    return "run field";
}

// Case fields other than runs, checks and method metrics (problem, reference, grid, ...).
void compare_case_fields(const json& a, const json& b, Walker& w) {
    for (auto it = a.begin(); it != a.end(); ++it) {
        const std::string& k = it.key();
        // "file" is where the case file was read from, not a result.
        if (k == "runs" || k == "checks" || k == "method_metrics" || k == "file") continue;
        if (!b.contains(k))
            w.row("case field removed", k, it.value(), nullptr);
        else
            w.walk(it.value(), b[k], k, k == "reference" ? "reference" : "case field", false);
    }
    for (auto it = b.begin(); it != b.end(); ++it)
        if (!a.contains(it.key()) && it.key() != "method_metrics" && it.key() != "file")
            w.row("case field added", it.key(), nullptr, it.value());
}

// Runs, matched by method and dt: final states, metrics, statuses.
void compare_runs(const json& a, const json& b, Walker& w) {
    std::map<std::string, const json*> ra, rb;
    std::vector<std::string> order;
    for (const auto& r : a["runs"]) {
        ra[run_key(r)] = &r;
        order.push_back(run_key(r));
    }
    for (const auto& r : b["runs"]) {
        rb[run_key(r)] = &r;
        if (!ra.count(run_key(r))) order.push_back(run_key(r));
    }
    for (const auto& k : order) {
        w.run = k;
        if (!rb.count(k)) {
            w.row("run removed", "", nullptr, nullptr);
        } else if (!ra.count(k)) {
            w.row("run added", "", nullptr, nullptr);
        } else {
            const json& x = *ra[k];
            const json& y = *rb[k];
            std::set<std::string> keys;
            for (auto it = x.begin(); it != x.end(); ++it) keys.insert(it.key());
            for (auto it = y.begin(); it != y.end(); ++it) keys.insert(it.key());
            for (const auto& f : keys) {
                if (clock_key(f)) continue;
                const std::string kind = kind_of_run_field(f);
                if (!x.contains(f))
                    w.row(kind + " added", f, nullptr, y[f]);
                else if (!y.contains(f))
                    w.row(kind + " removed", f, x[f], nullptr);
                else
                    w.walk(x[f], y[f], f, kind, true);
            }
        }
    }
    w.run.clear();
}

// Method-level metrics (order fits, stability sweeps).
void compare_method_metrics(const json& a, const json& b, Walker& w) {
    const json empty = json::object();
    const json& ma = a.contains("method_metrics") ? a["method_metrics"] : empty;
    const json& mb = b.contains("method_metrics") ? b["method_metrics"] : empty;
    std::set<std::string> methods;
    for (auto it = ma.begin(); it != ma.end(); ++it) methods.insert(it.key());
    for (auto it = mb.begin(); it != mb.end(); ++it) methods.insert(it.key());
    for (const auto& m : methods) {
        w.run = m;
        const json& x = ma.contains(m) ? ma[m] : empty;
        const json& y = mb.contains(m) ? mb[m] : empty;
        std::set<std::string> diags;
        for (auto it = x.begin(); it != x.end(); ++it) diags.insert(it.key());
        for (auto it = y.begin(); it != y.end(); ++it) diags.insert(it.key());
        for (const auto& d : diags) {
            const std::string kind = d == OrderDiagnostic::name || d == LocalOrderDiagnostic::name
                                         ? "order fit"
                                         : "method metric";
            const std::string p = "method_metrics." + d;
            if (!x.contains(d))
                w.row(kind + " added", p, nullptr, y[d]);
            else if (!y.contains(d))
                w.row(kind + " removed", p, x[d], nullptr);
            else
                w.walk(x[d], y[d], p, kind, true);
        }
    }
    w.run.clear();
}

// Checks: verdicts, matched by name, method and dt.
void compare_checks(const json& a, const json& b, Walker& w) {
    std::map<std::string, const json*> ca, cb;
    std::vector<std::string> corder;
    for (const auto& ck : a["checks"]) {
        ca[check_key(ck)] = &ck;
        corder.push_back(check_key(ck));
    }
    for (const auto& ck : b["checks"]) {
        cb[check_key(ck)] = &ck;
        if (!ca.count(check_key(ck))) corder.push_back(check_key(ck));
    }
    for (const auto& k : corder) {
        if (!cb.count(k)) {
            w.row("check removed", k, (*ca[k])["passed"], nullptr);
        } else if (!ca.count(k)) {
            w.row("check added", k, nullptr, (*cb[k])["passed"]);
        } else {
            const json& x = *ca[k];
            const json& y = *cb[k];
            if (x["passed"] != y["passed"]) {
                json r = {{"case", w.case_id},
                          {"run", nullptr},
                          {"kind", "check flipped"},
                          {"path", k},
                          {"base", x["passed"]},
                          {"new", y["passed"]},
                          {"base_value", x.value("value", json())},
                          {"new_value", y.value("value", json())}};
                w.rows.push_back(r);
            }
        }
    }
}

void compare_case(const json& a, const json& b, Walker& w) {
    compare_case_fields(a, b, w);
    compare_runs(a, b, w);
    compare_method_metrics(a, b, w);
    compare_checks(a, b, w);
}

// Wall seconds per case id from a report's timings (schema 2) or its runs (schema 1).
std::map<std::string, double> case_walls(const json& r) {
    std::map<std::string, double> out;
    if (r.contains("timings") && r["timings"].is_object() && r["timings"].contains("cases")) {
        for (const auto& c : r["timings"]["cases"])
            if (c.contains("id") && c["id"].is_string() && c.contains("runs_wall_seconds") &&
                c["runs_wall_seconds"].is_number())
                out[c["id"].get<std::string>()] += c["runs_wall_seconds"].get<double>();
        return out;
    }
    for (const auto& c : r["cases"])
        for (const auto& run : c["runs"])
            if (run.contains("wall_seconds") && run["wall_seconds"].is_number())
                out[c["id"].get<std::string>()] += run["wall_seconds"].get<double>();
    return out;
}

json total_wall(const json& r) {
    if (r.contains("timings") && r["timings"].is_object() && r["timings"].contains("wall_seconds"))
        return r["timings"]["wall_seconds"];
    if (r.contains("summary") && r["summary"].is_object() && r["summary"].contains("wall_seconds"))
        return r["summary"]["wall_seconds"];
    return nullptr;
}

// A value for a person: numbers to 6 significant digits (the JSON has them in full).
std::string fmt(const json& v) {
    if (v.is_null()) return "—";
    if (v.is_number_float()) {
        char buf[40];
        std::snprintf(buf, sizeof buf, "%.6g", v.get<double>());
        return buf;
    }
    std::string s = v.dump();
    if (s.size() > 60) s = s.substr(0, 57) + "...";
    return s;
}

// The signed relative change (new − base)/|base| of two numbers, "" otherwise.
std::string relative_change(const json& r) {
    if (!r["base"].is_number() || !r["new"].is_number()) return "";
    const double a = r["base"].get<double>(), b = r["new"].get<double>();
    char buf[40];
    if (a == 0.0) return b == 0.0 ? "0" : "from 0";
    std::snprintf(buf, sizeof buf, "%+.3g", (b - a) / std::abs(a));
    return buf;
}

bool is_flip(const json& r, bool to_pass) {
    return r["kind"] == "check flipped" && r["new"] == json(to_pass);
}

bool is_membership(const std::string& kind) {
    for (const char* k :
         {"case added", "case removed", "check added", "check removed", "run added", "run removed"})
        if (kind == k) return true;
    return false;
}

// Verdict flips (pass → fail first), then cases, runs and checks added or removed.
void flips_and_membership(std::ostringstream& os, const json& rows) {
    for (const bool to_pass : {false, true}) {
        bool any = false;
        for (const auto& r : rows) {
            if (!is_flip(r, to_pass)) continue;
            if (!any)
                os << (to_pass ? "\n## Checks that now pass (fail → pass)\n\n"
                               : "\n## Checks that now fail (pass → fail)\n\n")
                   << "| case | check | base value | new value |\n|---|---|---|---|\n";
            any = true;
            os << "| " << md_cell(r["case"].get<std::string>()) << " | "
               << md_cell(r["path"].get<std::string>()) << " | "
               << md_cell(fmt(r.value("base_value", json()))) << " | "
               << md_cell(fmt(r.value("new_value", json()))) << " |\n";
        }
    }
    bool any = false;
    for (const auto& r : rows) {
        const std::string kind = r["kind"].get<std::string>();
        if (!is_membership(kind)) continue;
        if (!any) os << "\n## Added or removed\n\n| case | what | name |\n|---|---|---|\n";
        any = true;
        const std::string name = kind.rfind("run", 0) == 0 && r["run"].is_string()
                                     ? r["run"].get<std::string>()
                                     : r["path"].get<std::string>();
        os << "| " << md_cell(r["case"].get<std::string>()) << " | " << kind << " | "
           << md_cell(name) << " |\n";
    }
}

// Every other change: changes that are not numbers (a status, a string) first, then numbers by
// their relative change, largest first.
void value_changes(std::ostringstream& os, const json& rows) {
    std::vector<const json*> values;
    for (const auto& r : rows)
        if (r["kind"] != "check flipped" && !is_membership(r["kind"].get<std::string>()))
            values.push_back(&r);
    if (values.empty()) return;
    auto rank = [](const json* r) {
        return r->contains("rel_diff") ? (*r)["rel_diff"].get<double>() : HUGE_VAL;
    };
    std::stable_sort(values.begin(), values.end(),
                     [&](const json* a, const json* b) { return rank(a) > rank(b); });
    os << "\n## Values changed (largest relative change first)\n\n"
          "| case | run | kind | path | base | new | relative change |\n"
          "|---|---|---|---|---|---|---|\n";
    const std::size_t limit = 500;
    for (std::size_t i = 0; i < values.size() && i < limit; ++i) {
        const json& r = *values[i];
        os << "| " << md_cell(r["case"].get<std::string>()) << " | "
           << (r["run"].is_null() ? "" : md_cell(r["run"].get<std::string>())) << " | "
           << r["kind"].get<std::string>() << " | `" << md_cell(r["path"].get<std::string>())
           << "` | " << md_cell(fmt(r["base"])) << " | " << md_cell(fmt(r["new"])) << " | "
           << relative_change(r) << " |\n";
    }
    if (values.size() > limit)
        os << "\n… " << values.size() - limit << " more rows (see --json).\n";
}

// The one-line count that leads: flips, then membership, then values.
void change_counts(std::ostringstream& os, const json& rows) {
    std::size_t to_fail = 0, to_pass = 0, membership = 0, values = 0;
    for (const auto& r : rows) {
        if (is_flip(r, false))
            ++to_fail;
        else if (is_flip(r, true))
            ++to_pass;
        else if (is_membership(r["kind"].get<std::string>()))
            ++membership;
        else
            ++values;
    }
    os << "**" << rows.size() << " changes**: " << to_fail << " checks pass → fail, " << to_pass
       << " fail → pass, " << membership << " cases, runs or checks added or removed, " << values
       << " values changed.\n";
}

// Wall times (information only): the largest slowdowns and the largest speed-ups, apart.
void timing_tables(std::ostringstream& os, const json& t) {
    os << "\n## Timings (information only)\n\nTotal wall " << fmt(t["base_wall_seconds"]) << " s → "
       << fmt(t["new_wall_seconds"]) << " s.\n";
    std::vector<const json*> slower, faster;
    for (const auto& c : t["cases"]) { // sorted by ratio, largest first
        if (!c["ratio"].is_number()) continue;
        if (c["ratio"].get<double>() > 1.0) slower.push_back(&c);
        if (c["ratio"].get<double>() < 1.0) faster.insert(faster.begin(), &c);
    }
    auto table = [&](const char* title, const std::vector<const json*>& list) {
        if (list.empty()) return;
        os << "\n"
           << title << " of the runs' wall time:\n\n"
           << "| case | base s | new s | ratio |\n|---|---|---|---|\n";
        for (std::size_t i = 0; i < list.size() && i < 5; ++i) {
            char line[64];
            std::snprintf(line, sizeof line, " | %.3g | %.3g | %.3g |\n",
                          (*list[i])["base_seconds"].get<double>(),
                          (*list[i])["new_seconds"].get<double>(),
                          (*list[i])["ratio"].get<double>());
            os << "| " << md_cell((*list[i])["case"].get<std::string>()) << line;
        }
    };
    table("Largest slowdowns (ratio > 1)", slower);
    table("Largest speed-ups (ratio < 1)", faster);
}

} // namespace

json compare_reports(const json& base, const json& next, const CompareOptions& options) {
    compare_detail::require_report(base, "BASE");
    compare_detail::require_report(next, "NEW");
    json rows = json::array();
    Walker w{options, rows, "", ""};
    std::map<std::string, const json*> ca, cb;
    std::vector<std::string> order;
    for (const auto& c : base["cases"]) {
        ca[c["id"].get<std::string>()] = &c;
        order.push_back(c["id"].get<std::string>());
    }
    for (const auto& c : next["cases"]) {
        cb[c["id"].get<std::string>()] = &c;
        if (!ca.count(c["id"].get<std::string>())) order.push_back(c["id"].get<std::string>());
    }
    for (const auto& id : order) {
        w.case_id = id;
        if (!cb.count(id))
            w.row("case removed", "", nullptr, nullptr);
        else if (!ca.count(id))
            w.row("case added", "", nullptr, nullptr);
        else
            compare_case(*ca[id], *cb[id], w);
    }
    json counts = json::object();
    for (const auto& r : rows) {
        const std::string k = r["kind"].get<std::string>();
        counts[k] = counts.value(k, 0) + 1;
    }
    json result = {
        {"equal", rows.empty()},
        {"rtol", options.rtol},
        {"atol", options.atol},
        {"cases", {{"base", base["cases"].size()}, {"new", next["cases"].size()}}},
        {"schema_version", {{"base", base["schema_version"]}, {"new", next["schema_version"]}}},
        {"counts", counts},
        {"rows", rows}};
    if (!options.ignore_timings) {
        const auto wa = case_walls(base), wb = case_walls(next);
        json per_case = json::array();
        for (const auto& [id, x] : wa)
            if (wb.count(id))
                per_case.push_back(
                    {{"case", id},
                     {"base_seconds", x},
                     {"new_seconds", wb.at(id)},
                     {"ratio", x > 0.0 && std::isfinite(wb.at(id) / x) ? json(wb.at(id) / x)
                                                                       : json(nullptr)}});
        std::sort(per_case.begin(), per_case.end(), [](const json& p, const json& q) {
            const double a = p["ratio"].is_number() ? p["ratio"].get<double>() : 0.0;
            const double b = q["ratio"].is_number() ? q["ratio"].get<double>() : 0.0;
            return a != b ? a > b : p["case"] < q["case"];
        });
        result["timings"] = {{"note", "information only: wall times never count as a change"},
                             {"base_wall_seconds", total_wall(base)},
                             {"new_wall_seconds", total_wall(next)},
                             {"cases", per_case}};
    }
    return result;
}

std::string render_compare_markdown(const json& result) {
    std::ostringstream os;
    const json& rows = result["rows"];
    os << "# dampsym compare\n\n";
    char tol[128];
    std::snprintf(tol, sizeof tol, "rtol %g, atol %g", result["rtol"].get<double>(),
                  result["atol"].get<double>());
    os << result["cases"]["base"] << " cases in BASE, " << result["cases"]["new"]
       << " in NEW; tolerance " << tol << " (|a − b| <= atol + rtol·max(|a|, |b|)).\n\n";
    if (rows.empty()) {
        os << "**No change**: every final state, metric, order fit and check verdict agrees.\n";
    } else {
        change_counts(os, rows);
        flips_and_membership(os, rows);
        value_changes(os, rows);
    }
    if (result.contains("timings")) timing_tables(os, result["timings"]);
    return os.str();
}

} // namespace dampsym
