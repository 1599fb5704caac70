// The Markdown tables of report.md (report.cpp renders the rest): checks, measures, order fits,
// stability sweeps, work-precision timing, runs and the per-run metrics table (its columns come
// from the diagnostic registry, src/diagnostics/diagnostic.hpp).
#include "harness/report/tables.hpp"

#include "diagnostics/error_diagnostic.hpp"
#include "diagnostics/order_diagnostic.hpp"
#include "diagnostics/stability_sweep_diagnostic.hpp"
#include "harness/case/case.hpp"
#include "harness/report/markdown.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <string>

namespace dampsym::report_detail {

std::string num(const json& v, int digits) {
    if (v.is_null()) return "—";
    if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
    if (v.is_number_integer() || v.is_number_unsigned()) return v.dump();
    if (!v.is_number()) return v.dump();
    const double x = v.get<double>();
    if (x == 0.0) return "0";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*g", digits, x);
    return buf;
}

bool case_passed(const json& c) {
    for (const auto& ck : c["checks"])
        if (!ck["passed"].get<bool>()) return false;
    return true;
}

std::string expected_text(const json& ck) {
    const std::string op = ck["op"].get<std::string>();
    std::string expected = op == "near" ? num(ck["expected"]) + " ± " + num(ck["tolerance"])
                                        : (op == "le"   ? "≤ "
                                           : op == "ge" ? "≥ "
                                           : op == "lt" ? "< "
                                                        : "> ") +
                                              num(ck["expected"]);
    if (ck.value("abs", false)) expected = "|x| " + expected;
    return expected;
}

std::string check_line(const json& ck, const char* result) {
    std::ostringstream os;
    const std::string expected = expected_text(ck);
    const std::string verdict = result ? result : ck.value("passed", false) ? "pass" : "**FAIL**";
    const std::string name = ck["name"].get<std::string>();
    // the label once: many check names already say "(negative control)"
    const bool label =
        ck["negative_control"].get<bool>() && name.find("negative control") == std::string::npos;
    const std::string note =
        (ck.contains("message") ? ck["message"].get<std::string>() : std::string()) +
        (ck.value("refutes", false) ? " (passing refutes the paper's claim)" : "") +
        (ck.contains("across_dt") ? " (log–log slope against dt over the ladder)" : "");
    os << "| " << verdict << " | " << md_cell(name + (label ? " (negative control)" : "")) << " | "
       << md_cell(ck["method"].get<std::string>()) << " | "
       << (ck.contains("dt") ? num(ck["dt"]) : "") << " | `"
       << md_cell(ck["metric"].get<std::string>()) << "` | " << num(ck["value"], 6) << " | "
       << md_cell(expected) << " | " << md_cell(note) << " |\n";
    return os.str();
}

// The case's "measures" (error as the paper states it), one column per measure.
void measures_table(std::ostringstream& os, const json& c) {
    if (!c.contains("measures")) return;
    os << "\nMeasures (";
    bool first = true;
    for (auto it = c["measures"].begin(); it != c["measures"].end(); ++it) {
        os << (first ? "" : "; ") << "`" << it.key() << "`: " << it.value().dump();
        first = false;
    }
    os << "):\n\n| method | dt |";
    for (auto it = c["measures"].begin(); it != c["measures"].end(); ++it)
        os << " " << md_cell(it.key()) << " |";
    os << "\n|---|---|";
    for (std::size_t i = 0; i < c["measures"].size(); ++i) os << "---|";
    os << "\n";
    for (const auto& r : c["runs"]) {
        os << "| " << md_cell(r["method"].get<std::string>()) << " | " << num(r["dt"]) << " |";
        for (auto it = c["measures"].begin(); it != c["measures"].end(); ++it) {
            const json& m = r["metrics"];
            os << " "
               << (m.contains("measure") && m["measure"].contains(it.key())
                       ? num(m["measure"][it.key()], 6)
                       : std::string("—"))
               << " |";
        }
        os << "\n";
    }
}

// diag: "order" (global error at t_end) or "local-order" (one-step error, slope p + 1).
void order_table(std::ostringstream& os, const json& c, std::string_view diag_name) {
    const std::string diag(diag_name);
    bool any = false;
    for (auto it = c["method_metrics"].begin(); it != c["method_metrics"].end(); ++it)
        if (it.value().contains(diag)) any = true;
    if (!any) return;
    const bool global = diag == OrderDiagnostic::name;
    os << (global ? "\nConvergence (least-squares slope of log error vs log dt over the "
                    "asymptotic window):\n\n"
                  : "\nLocal error (one step from the initial state against the exact solution; "
                    "slope p + 1 for a method of order p):\n\n")
       << "| method | " << (global ? "order" : "local slope")
       << " | R² | window dt | local orders | dropped |\n|---|---|---|---|---|---|\n";
    for (auto it = c["method_metrics"].begin(); it != c["method_metrics"].end(); ++it) {
        if (!it.value().contains(diag)) continue;
        const json& o = it.value()[diag];
        std::string window, local, dropped;
        for (const auto& h : o["window_dt"]) window += (window.empty() ? "" : ", ") + num(h);
        for (const auto& p : o["local_orders"]) local += (local.empty() ? "" : ", ") + num(p, 3);
        for (const auto& d : o["dropped"])
            dropped += (dropped.empty() ? "" : "; ") + num(d["dt"]) + ": " +
                       d["reason"].get<std::string>();
        os << "| " << md_cell(it.key()) << " | "
           << (o["ok"].get<bool>() ? num(o["slope"], 4)
                                   : md_cell("failed: " + o["reason"].get<std::string>()))
           << " | " << (o.contains("r2") ? num(o["r2"], 6) : "—") << " | " << window << " | "
           << local << " | " << md_cell(dropped) << " |\n";
    }
}

void sweep_table(std::ostringstream& os, const json& c) {
    for (auto it = c["method_metrics"].begin(); it != c["method_metrics"].end(); ++it) {
        const std::string sweep(StabilitySweepDiagnostic::name);
        if (!it.value().contains(sweep)) continue;
        const json& s = it.value()[sweep];
        os << "\nStability sweep of " << it.key() << " (ω = " << num(s["omega"])
           << "): first grid h where F's condition |½trM| < e^{−γh} fails (empirical, and by "
           << (s.contains("formula_source") ? s["formula_source"].get<std::string>()
                                            : std::string("no formula"))
           << "), and first h where M is not power-bounded.\n\n"
           << "| γ | h F empirical | h F formula | h not power-bounded | "
           << md_cell("max |½trM − e^{−γh}cos βh|") << " |\n"
           << "|---|---|---|---|---|\n";
        for (const auto& r : s["rows"])
            os << "| " << num(r["gamma"]) << " | " << num(r["h_F_empirical"]) << " | "
               << (r.contains("h_F_formula") ? num(r["h_F_formula"]) : "—") << " | "
               << num(r["h_power_unbounded"]) << " | " << num(r["max_half_trace_err"], 3) << " |\n";
    }
}

// Work-precision (ladder cases): error against the minimum wall time of the bare step loop and
// the rhs evaluations, per method and step size, sorted by method then dt as run.
// `t` is the case's entry in the report's timings section (null if absent).
void work_precision_table(std::ostringstream& os, const json& c, const json* t) {
    auto timing = [&](std::size_t i) -> const json* {
        if (!t || i >= (*t)["runs"].size() || !(*t)["runs"][i].contains("timing")) return nullptr;
        return &(*t)["runs"][i]["timing"];
    };
    bool any = false;
    for (std::size_t i = 0; i < c["runs"].size(); ++i)
        if (timing(i)) any = true;
    if (!any) return;
    os << "\nWork-precision (bare step loop: one warm-up, then the minimum of N repetitions; "
          "failed runs are not timed):\n\n"
       << "| method | dt | final error | rhs evals | wall s (min) | ns/step | N |\n"
       << "|---|---|---|---|---|---|---|\n";
    for (std::size_t i = 0; i < c["runs"].size(); ++i) {
        const json& r = c["runs"][i];
        if (r["status"] == "not-applicable") continue;
        const json& m = r["metrics"];
        const std::string err(ErrorDiagnostic::name);
        const bool has_err = m.contains(err);
        const json* tm = timing(i);
        const bool timed = tm != nullptr;
        os << "| " << md_cell(r["method"].get<std::string>()) << " | " << num(r["dt"]) << " | "
           << (has_err ? num(m[err]["final_abs"], 3) : "—") << " | "
           << (r.contains("rhs_evals") ? num(r["rhs_evals"]) : "—") << " | "
           << (timed ? num((*tm)["wall_seconds_min"], 3) : md_cell(r["status"].get<std::string>()))
           << " | " << (timed ? num((*tm)["ns_per_step"], 3) : "—") << " | "
           << (timed ? num((*tm)["repetitions"]) : "—") << " |\n";
    }
}

void runs_table(std::ostringstream& os, const json& c, const json* t) {
    os << "\n| method | dt | status | steps | final error | max error | rhs evals | Newton its | "
          "wall s |\n"
          "|---|---|---|---|---|---|---|---|---|\n";
    for (std::size_t i = 0; i < c["runs"].size(); ++i) {
        const json& r = c["runs"][i];
        const json* tr = t && i < (*t)["runs"].size() ? &(*t)["runs"][i] : nullptr;
        const json& m = r["metrics"];
        const std::string err(ErrorDiagnostic::name);
        const bool has_err = m.contains(err);
        std::string status = r["status"].get<std::string>();
        if (r.contains("failed_at_step")) status += " at step " + r["failed_at_step"].dump();
        const std::string mark =
            r.contains("coefficients_refuted") ? " ⚠ coefficients refuted" : "";
        os << "| " << md_cell(r["method"].get<std::string>() + mark) << " | " << num(r["dt"])
           << " | " << md_cell(status) << " | " << num(r["steps"]) << " | "
           << (has_err ? num(m[err]["final_abs"], 3) : "—") << " | "
           << (has_err ? num(m[err]["max_abs"], 3) : "—") << " | "
           << (r.contains("rhs_evals") ? num(r["rhs_evals"]) : "—") << " | "
           << (r.contains("newton_iters") ? num(r["newton_iters"]) : "—") << " | "
           << (tr && tr->contains("wall_seconds") ? num((*tr)["wall_seconds"], 3) : "—") << " |\n";
    }
}

void metrics_table(std::ostringstream& os, const json& c) {
    // Compact per-run table of the structure metrics the case asked for.
    // The columns each diagnostic declares (src/diagnostics/*_diagnostic.cpp), in registry order.
    struct Col {
        std::string diag;
        ReportColumn column;
    };
    std::vector<Col> cols;
    for (const DiagnosticInfo& d : diagnostic_registry())
        for (const ReportColumn& rc : d.report_columns) cols.push_back({d.name, rc});
    std::vector<const Col*> used;
    for (const auto& col : cols)
        for (const auto& r : c["runs"])
            if (r["metrics"].contains(col.diag)) {
                used.push_back(&col);
                break;
            }
    if (used.empty()) return;
    os << "\n| method | dt |";
    for (auto* col : used) os << " " << md_cell(col->column.label) << " |";
    os << "\n|---|---|";
    for (std::size_t i = 0; i < used.size(); ++i) os << "---|";
    os << "\n";
    for (const auto& r : c["runs"]) {
        os << "| " << md_cell(r["method"].get<std::string>()) << " | " << num(r["dt"]) << " |";
        for (auto* col : used) {
            const json& m = r["metrics"];
            std::string cell = "—";
            if (m.contains(col->diag)) {
                const json& d = m[col->diag];
                const ReportColumn& rc = col->column;
                if (rc.per_part) {
                    // the residual of each part on its scale, and the scale at that step
                    cell.clear();
                    std::vector<std::string> parts = rc.parts;
                    if (parts.empty())
                        for (auto it = d.begin(); it != d.end(); ++it) parts.push_back(it.key());
                    for (const std::string& part : parts)
                        if (d.contains(part) && d[part].contains(rc.key))
                            cell += (cell.empty() ? "" : ", ") + part + " " +
                                    num(d[part][rc.key], 3) + " (scale " +
                                    num(d[part][rc.scale_key], 3) + ")";
                } else if (d.contains(rc.key)) {
                    cell = num(d[rc.key], 4);
                }
            }
            os << " " << md_cell(cell) << " |";
        }
        os << "\n";
    }
}

} // namespace dampsym::report_detail
