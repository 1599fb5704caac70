#include "harness/report.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace dampsym {
namespace {

using json = nlohmann::json;

std::string num(const json& v, int digits = 4) {
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

std::string check_line(const json& ck) {
    std::ostringstream os;
    const std::string op = ck["op"].get<std::string>();
    std::string expected = op == "near" ? num(ck["expected"]) + " ± " + num(ck["tolerance"])
                                        : (op == "le"   ? "≤ "
                                           : op == "ge" ? "≥ "
                                           : op == "lt" ? "< "
                                                        : "> ") +
                                              num(ck["expected"]);
    if (ck.value("abs", false)) expected = "|x| " + expected;
    os << "| " << (ck["passed"].get<bool>() ? "pass" : "**FAIL**") << " | "
       << ck["name"].get<std::string>()
       << (ck["negative_control"].get<bool>() ? " (negative control)" : "") << " | "
       << ck["method"].get<std::string>() << " | " << (ck.contains("dt") ? num(ck["dt"]) : "")
       << " | `" << ck["metric"].get<std::string>() << "` | " << num(ck["value"], 6) << " | "
       << expected << " | " << (ck.contains("message") ? ck["message"].get<std::string>() : "")
       << (ck.value("refutes", false) ? " (passing refutes the paper's claim)" : "")
       << (ck.contains("across_dt") ? " (log–log slope against dt over the ladder)" : "") << " |\n";
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
        os << " " << it.key() << " |";
    os << "\n|---|---|";
    for (std::size_t i = 0; i < c["measures"].size(); ++i) os << "---|";
    os << "\n";
    for (const auto& r : c["runs"]) {
        os << "| " << r["method"].get<std::string>() << " | " << num(r["dt"]) << " |";
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
void order_table(std::ostringstream& os, const json& c, const char* diag) {
    bool any = false;
    for (auto it = c["method_metrics"].begin(); it != c["method_metrics"].end(); ++it)
        if (it.value().contains(diag)) any = true;
    if (!any) return;
    const bool global = std::string(diag) == "order";
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
        os << "| " << it.key() << " | "
           << (o["ok"].get<bool>() ? num(o["slope"], 4)
                                   : "failed: " + o["reason"].get<std::string>())
           << " | " << (o.contains("r2") ? num(o["r2"], 6) : "—") << " | " << window << " | "
           << local << " | " << dropped << " |\n";
    }
}

void sweep_table(std::ostringstream& os, const json& c) {
    for (auto it = c["method_metrics"].begin(); it != c["method_metrics"].end(); ++it) {
        if (!it.value().contains("stability-sweep")) continue;
        const json& s = it.value()["stability-sweep"];
        os << "\nStability sweep of " << it.key() << " (ω = " << num(s["omega"])
           << "): first grid h where F's condition |½trM| < e^{−γh} fails (empirical, and by "
           << (s.contains("formula_source") ? s["formula_source"].get<std::string>()
                                            : std::string("no formula"))
           << "), and first h where M is not power-bounded.\n\n"
           << "| γ | h F empirical | h F formula | h not power-bounded | max \\|½trM − e^{−γh}cos "
              "βh\\| |\n"
           << "|---|---|---|---|---|\n";
        for (const auto& r : s["rows"])
            os << "| " << num(r["gamma"]) << " | " << num(r["h_F_empirical"]) << " | "
               << (r.contains("h_F_formula") ? num(r["h_F_formula"]) : "—") << " | "
               << num(r["h_power_unbounded"]) << " | " << num(r["max_half_trace_err"], 3) << " |\n";
    }
}

// Work-precision (ladder cases): error against the minimum wall time of the bare step loop and
// the rhs evaluations, per method and step size, sorted by method then dt as run.
void work_precision_table(std::ostringstream& os, const json& c) {
    bool any = false;
    for (const auto& r : c["runs"])
        if (r.contains("timing")) any = true;
    if (!any) return;
    os << "\nWork-precision (bare step loop: one warm-up, then the minimum of N repetitions; "
          "failed runs are not timed):\n\n"
       << "| method | dt | final error | rhs evals | wall s (min) | ns/step | N |\n"
       << "|---|---|---|---|---|---|---|\n";
    for (const auto& r : c["runs"]) {
        if (r["status"] == "not-applicable") continue;
        const json& m = r["metrics"];
        const bool has_err = m.contains("error");
        const bool timed = r.contains("timing");
        os << "| " << r["method"].get<std::string>() << " | " << num(r["dt"]) << " | "
           << (has_err ? num(m["error"]["final_abs"], 3) : "—") << " | "
           << (r.contains("rhs_evals") ? num(r["rhs_evals"]) : "—") << " | "
           << (timed ? num(r["timing"]["wall_seconds_min"], 3) : r["status"].get<std::string>())
           << " | " << (timed ? num(r["timing"]["ns_per_step"], 3) : "—") << " | "
           << (timed ? num(r["timing"]["repetitions"]) : "—") << " |\n";
    }
}

void runs_table(std::ostringstream& os, const json& c) {
    os << "\n| method | dt | status | steps | final error | max error | rhs evals | Newton its | "
          "wall s |\n"
          "|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& r : c["runs"]) {
        const json& m = r["metrics"];
        const bool has_err = m.contains("error");
        std::string status = r["status"].get<std::string>();
        if (r.contains("failed_at_step")) status += " at step " + r["failed_at_step"].dump();
        os << "| " << r["method"].get<std::string>() << " | " << num(r["dt"]) << " | " << status
           << " | " << num(r["steps"]) << " | " << (has_err ? num(m["error"]["final_abs"], 3) : "—")
           << " | " << (has_err ? num(m["error"]["max_abs"], 3) : "—") << " | "
           << (r.contains("rhs_evals") ? num(r["rhs_evals"]) : "—") << " | "
           << (r.contains("newton_iters") ? num(r["newton_iters"]) : "—") << " | "
           << (r.contains("wall_seconds") ? num(r["wall_seconds"], 3) : "—") << " |\n";
    }
}

void metrics_table(std::ostringstream& os, const json& c) {
    // Compact per-run table of the structure metrics the case asked for.
    struct Col {
        const char* diag;
        const char* key;
        const char* label;
    };
    static const Col cols[] = {
        {"invariants", "", "invariant max step residual (rel)"},
        {"dissipation-drift", "slope", "d(t) slope"},
        {"dissipation-drift", "maxima", "maxima"},
        {"energy", "max_abs_error", "max |H_exact−H|"},
        {"energy", "drift_slope", "H error slope"},
        {"energy", "max_abs_change", "max |H−H₀|"},
        {"stability", "det_rel_err", "det M vs e^{−2γh} (rel)"},
        {"stability", "half_trace_formula_rel_err", "½trM vs F (rel)"},
        {"stability", "spectral_radius", "ρ(M)"},
        {"cost", "newton_iters_per_step", "Newton its/step"},
    };
    std::vector<const Col*> used;
    for (const auto& col : cols)
        for (const auto& r : c["runs"])
            if (r["metrics"].contains(col.diag)) {
                used.push_back(&col);
                break;
            }
    if (used.empty()) return;
    os << "\n| method | dt |";
    for (auto* col : used) os << " " << col->label << " |";
    os << "\n|---|---|";
    for (std::size_t i = 0; i < used.size(); ++i) os << "---|";
    os << "\n";
    for (const auto& r : c["runs"]) {
        os << "| " << r["method"].get<std::string>() << " | " << num(r["dt"]) << " |";
        for (auto* col : used) {
            const json& m = r["metrics"];
            std::string cell = "—";
            if (m.contains(col->diag)) {
                const json& d = m[col->diag];
                if (std::string(col->key).empty()) {
                    cell.clear();
                    for (auto it = d.begin(); it != d.end(); ++it)
                        cell += (cell.empty() ? "" : ", ") + it.key() + " " +
                                num(it.value()["max_step_rel"], 3);
                } else if (d.contains(col->key)) {
                    cell = num(d[col->key], 4);
                }
            }
            os << " " << cell << " |";
        }
        os << "\n";
    }
}

} // namespace

std::string render_markdown(const json& report) {
    std::ostringstream os;
    const json& s = report["summary"];
    os << "# dampsym report\n\n"
       << s["cases"] << " cases, " << s["runs"] << " runs: **" << s["checks_passed"]
       << " checks passed, " << s["checks_failed"] << " failed** (" << num(s["wall_seconds"], 3)
       << " s with --jobs " << s["jobs"]
       << ").\n\nCases with a failing check come first; in each case failing checks come first. A "
          "*negative "
          "control* is a check that passes only when the structure check detects a method that "
          "lacks the "
          "property.\n";
    std::vector<const json*> order;
    for (const auto& c : report["cases"])
        if (!case_passed(c)) order.push_back(&c);
    for (const auto& c : report["cases"])
        if (case_passed(c)) order.push_back(&c);
    for (const json* cp : order) {
        const json& c = *cp;
        os << "\n## " << (case_passed(c) ? "" : "FAILED: ") << c["id"].get<std::string>();
        if (!c["title"].get<std::string>().empty()) os << " — " << c["title"].get<std::string>();
        os << "\n\n";
        if (!c["source"].get<std::string>().empty())
            os << "Source: " << c["source"].get<std::string>() << ". ";
        os << "Problem `" << c["problem"]["id"].get<std::string>() << "` ";
        std::string params;
        for (auto it = c["problem"]["params"].begin(); it != c["problem"]["params"].end(); ++it) {
            if (!params.empty()) params += ", ";
            params += it.key();
            params += " = ";
            if (it.value().is_array() && it.value().size() > 6) {
                params += "[";
                params += std::to_string(it.value().size());
                params += " values]";
            } else {
                params += num(it.value(), 6);
            }
        }
        os << "(" << params << "), t ∈ [" << num(c["t0"]) << ", " << num(c["t_end"])
           << "], reference: " << c["reference"]["kind"].get<std::string>() << ".";
        if (!c["overrides"].empty()) os << " Overrides: `" << c["overrides"].dump() << "`.";
        if (c.contains("no_checks_because"))
            os << " No checks: " << c["no_checks_because"].get<std::string>() << ".";
        os << "\n\n| result | check | method | dt | metric | value | expected | note |\n"
              "|---|---|---|---|---|---|---|---|\n";
        for (const auto& ck : c["checks"])
            if (!ck["passed"].get<bool>()) os << check_line(ck);
        for (const auto& ck : c["checks"])
            if (ck["passed"].get<bool>()) os << check_line(ck);
        measures_table(os, c);
        order_table(os, c, "order");
        order_table(os, c, "local-order");
        metrics_table(os, c);
        sweep_table(os, c);
        work_precision_table(os, c);
        runs_table(os, c);
    }
    return os.str();
}

std::string render_summary(const json& report) {
    std::ostringstream os;
    for (const auto& c : report["cases"]) {
        int pass = 0, fail = 0;
        std::string failed;
        for (const auto& ck : c["checks"]) {
            if (ck["passed"].get<bool>()) {
                ++pass;
            } else {
                ++fail;
                if (failed.size() < 80)
                    failed += (failed.empty() ? "" : ", ") + ck["name"].get<std::string>() + " [" +
                              ck["method"].get<std::string>() + "]";
            }
        }
        char line[160];
        std::snprintf(line, sizeof line, "%-4s %-34s %3d checks", fail ? "FAIL" : "ok",
                      c["id"].get<std::string>().c_str(), pass + fail);
        os << line;
        if (fail) os << "  failed: " << failed;
        if (c.contains("no_checks_because")) os << "  (no checks: stated reason in the report)";
        os << "\n";
    }
    const json& s = report["summary"];
    os << s["cases"] << " cases, " << s["runs"] << " runs, " << s["checks_passed"]
       << " checks passed, " << s["checks_failed"] << " failed, " << num(s["wall_seconds"], 3)
       << " s\n";
    return os.str();
}

void write_file_atomic(const std::string& path, const std::string& text) {
    const std::string tmp = path + ".tmp";
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) throw std::runtime_error("cannot write " + tmp);
        out << text;
        if (!out) throw std::runtime_error("cannot write " + tmp);
    }
    std::filesystem::rename(tmp, path);
}

void write_reports(const json& report, const std::string& dir) {
    std::filesystem::create_directories(dir);
    write_file_atomic(dir + "/report.json", report.dump(2) + "\n");
    write_file_atomic(dir + "/report.md", render_markdown(report));
}

} // namespace dampsym
