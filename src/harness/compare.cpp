#include "harness/compare.hpp"

#include "harness/case.hpp"
#include "harness/compare_input.hpp"

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
            const std::string kind =
                d == "order" || d == "local-order" ? "order fit" : "method metric";
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

std::string fmt(const json& v) {
    if (v.is_null()) return "—";
    if (v.is_number_float()) {
        char buf[40];
        std::snprintf(buf, sizeof buf, "%.17g", v.get<double>());
        return buf;
    }
    std::string s = v.dump();
    if (s.size() > 60) s = s.substr(0, 57) + "...";
    return s;
}

std::string md_cell(std::string s) {
    std::string out;
    for (char c : s) out += c == '|' ? std::string("\\|") : std::string(1, c);
    return out;
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
        os << "**" << rows.size() << " changes**:";
        for (auto it = result["counts"].begin(); it != result["counts"].end(); ++it)
            os << " " << it.key() << " " << it.value();
        os << ".\n\n| case | run | kind | path | base | new | rel diff |\n"
              "|---|---|---|---|---|---|---|\n";
        const std::size_t limit = 500;
        for (std::size_t i = 0; i < rows.size() && i < limit; ++i) {
            const json& r = rows[i];
            os << "| " << md_cell(r["case"].get<std::string>()) << " | "
               << (r["run"].is_null() ? "" : md_cell(r["run"].get<std::string>())) << " | "
               << r["kind"].get<std::string>() << " | `" << md_cell(r["path"].get<std::string>())
               << "` | " << md_cell(fmt(r["base"])) << " | " << md_cell(fmt(r["new"])) << " | "
               << (r.contains("rel_diff") ? fmt(r["rel_diff"]) : "") << " |\n";
        }
        if (rows.size() > limit)
            os << "\n… " << rows.size() - limit << " more rows (see --json).\n";
    }
    if (result.contains("timings")) {
        const json& t = result["timings"];
        os << "\nTimings (information only): total wall " << fmt(t["base_wall_seconds"]) << " s → "
           << fmt(t["new_wall_seconds"]) << " s.";
        if (!t["cases"].empty()) {
            os << " Largest slowdowns of the runs' wall time:\n\n| case | base s | new s | "
                  "ratio |\n|---|---|---|---|\n";
            for (std::size_t i = 0; i < t["cases"].size() && i < 5; ++i) {
                const json& c = t["cases"][i];
                char line[256];
                std::snprintf(line, sizeof line, "| %s | %.3g | %.3g | %s |\n",
                              c["case"].get<std::string>().c_str(), c["base_seconds"].get<double>(),
                              c["new_seconds"].get<double>(),
                              c["ratio"].is_number()
                                  ? (std::to_string(c["ratio"].get<double>()).substr(0, 5)).c_str()
                                  : "—");
                os << line;
            }
        } else {
            os << "\n";
        }
    }
    return os.str();
}

} // namespace dampsym
