#include "cli/cli_detail.hpp"

#include "harness/case.hpp"
#include "harness/compare.hpp"
#include "harness/junit.hpp"
#include "harness/problem_info.hpp"
#include "harness/progress.hpp"
#include "harness/provenance.hpp"
#include "harness/report.hpp"
#include "harness/runner.hpp"
#include "harness/shard.hpp"
#include "methods/coefficient_checks.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fnmatch.h>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <optional>
#include <ostream>
#include <sstream>
#include <thread>
#include <unistd.h>

namespace dampsym::cli_detail {

namespace fs = std::filesystem;

int cmd_list(bool as_json, const Selection& sel, const std::string& cases_dir, std::ostream& out) {
    const Selected selected = select_cases(sel, {}, cases_dir, false, !sel.shard.empty());
    json cases = json::array();
    for (const auto& c : selected.cases)
        cases.push_back({{"id", c.id},
                         {"file", c.file},
                         {"problem", c.problem_id},
                         {"methods", c.methods},
                         {"suites", c.suites},
                         {"diagnostics", c.diagnostics}});
    json problems = json::array();
    for (const auto& p : problem_catalog()) {
        json params = json::array();
        for (const auto& ps : p.params) {
            json row = {{"name", ps.name}, {"doc", ps.doc}};
            if (!ps.choices.empty()) {
                row["type"] = "choice";
                row["choices"] = ps.choices;
                row["default"] = ps.choices[static_cast<std::size_t>(ps.default_value)];
            } else {
                row["type"] = ps.is_array ? "array" : ps.integer ? "integer" : "number";
                row["default"] = ps.is_array  ? json(ps.default_array)
                                 : ps.integer ? json(static_cast<int>(ps.default_value))
                                              : json(ps.default_value);
                row["range"] = {{"min", ps.range.lo},
                                {"max", ps.range.hi},
                                {"min_exclusive", ps.range.lo_open},
                                {"max_exclusive", ps.range.hi_open}};
                if (ps.is_array) {
                    row["max_entries"] = ps.max_size;
                    if (ps.size_multiple > 1) row["length_multiple_of"] = ps.size_multiple;
                }
            }
            params.push_back(row);
        }
        json diagnostics = json::array();
        for (const auto& d : known_diagnostics())
            if (diagnostic_applies(d, p) && (d != "invariants" || !p.invariants.empty()))
                diagnostics.push_back(d);
        problems.push_back({{"id", p.id},
                            {"title", p.title},
                            {"params", params},
                            {"invariants", p.invariants},
                            {"exact_solution", p.has_exact},
                            {"diagnostics", diagnostics}});
    }
    json diagnostics = json::array();
    for (const auto& d : known_diagnostics())
        diagnostics.push_back({{"id", d},
                               {"per_method", diagnostic_is_method_level(d)},
                               {"metrics", diagnostic_metric_names(d, {})}});
    diagnostics.push_back({{"id", "run"},
                           {"per_method", false},
                           {"metrics", diagnostic_metric_names("run", {})},
                           {"note", "the run record itself; checkable in every case"}});
    json methods = json::array();
    for (const auto& m : method_catalog())
        methods.push_back({{"id", m.id},
                           {"order", m.order},
                           {"implicit", m.implicit},
                           {"form", form_name(m.form)},
                           {"kernel", kernel_name(m)},
                           {"citation", m.citation}});
    if (as_json) {
        out << json{{"cases", cases},
                    {"problems", problems},
                    {"diagnostics", diagnostics},
                    {"methods", methods},
                    {"case_keys_doc", "docs/case-keys.md"}}
                   .dump(2)
            << "\n";
        return 0;
    }
    out << "Cases (" << cases_dir << "):\n";
    for (const auto& c : cases) {
        std::string suites, methods_s;
        for (const auto& s : c["suites"])
            suites += (suites.empty() ? "" : ",") + s.get<std::string>();
        for (const auto& m : c["methods"])
            methods_s += (methods_s.empty() ? "" : ",") + m.get<std::string>();
        out << "  " << c["id"].get<std::string>() << "  [" << c["problem"].get<std::string>()
            << "; " << methods_s << "; suites: " << (suites.empty() ? "-" : suites) << "]\n";
    }
    out << "Problems (parameters: default, valid range, meaning; set as problem.NAME):\n";
    for (const auto& p : problems) {
        out << "  " << p["id"].get<std::string>() << "  " << p["title"].get<std::string>() << "\n";
        for (const auto& ps : p["params"]) {
            out << "      " << ps["name"].get<std::string>() << " = ";
            if (ps["type"] == "choice") {
                std::string list;
                for (const auto& ch : ps["choices"])
                    list += (list.empty() ? "" : " | ") + ch.get<std::string>();
                out << '"' << ps["default"].get<std::string>() << "\"  (one of " << list << ")";
            } else {
                const json& r = ps["range"];
                std::ostringstream range;
                range << (r["min_exclusive"].get<bool>() ? "(" : "[") << r["min"].get<double>()
                      << ", " << r["max"].get<double>()
                      << (r["max_exclusive"].get<bool>() ? ")" : "]");
                if (ps["type"] == "array")
                    out << "array of <= " << ps["max_entries"].get<int>() << " numbers in "
                        << range.str() << " (default " << ps["default"].size() << " entries)";
                else
                    out << ps["default"].dump() << "  in " << range.str()
                        << (ps["type"] == "integer" ? ", whole number" : "");
            }
            out << "  " << ps["doc"].get<std::string>() << "\n";
        }
        std::string inv, diags;
        for (const auto& i : p["invariants"])
            inv += (inv.empty() ? "" : ", ") + i.get<std::string>();
        for (const auto& d : p["diagnostics"])
            diags += (diags.empty() ? "" : ", ") + d.get<std::string>();
        out << "      invariants: " << (inv.empty() ? "none" : inv)
            << (p["exact_solution"].get<bool>() ? "; exact solution" : "; certified GSL reference")
            << "\n      diagnostics: " << diags << "\n";
    }
    out << "Diagnostics (metrics, for \"expect\": \"<diagnostic>.<metric>\"):\n";
    for (const auto& d : diagnostics) {
        std::string metrics;
        for (const auto& m : d["metrics"])
            metrics += (metrics.empty() ? "" : ", ") + m.get<std::string>();
        out << "  " << d["id"].get<std::string>()
            << (d["per_method"].get<bool>() ? " (per method)" : "") << ": " << metrics << "\n";
    }
    out << "Case file keys: docs/case-keys.md\nMethods:\n";
    for (const auto& m : method_catalog())
        out << "  " << m.id << "  order " << m.order << (m.implicit ? ", implicit" : ", explicit")
            << ", " << form_name(m.form) << " form, " << m.citation << "\n";
    return 0;
}

// `dampsym methods [--check] [--json]`: every registered method with its declaration and, with
// --check, the coefficient-level checks of its family (src/methods/coefficient_checks.hpp). A check
// passes when the coefficients agree with the declaration (order, claims), including the expected
// failures (order conditions beyond the declared order, symplecticity of a non-symplectic method).
// Exit status 1 if any check disagrees.
int cmd_methods(bool check, bool as_json, std::ostream& out) {
    auto number = [](double v) { return std::isfinite(v) ? json(v) : json(nullptr); };
    json methods = json::array();
    int agree = 0, disagree = 0, unchecked = 0;
    for (const auto& m : method_catalog()) {
        json row = {{"id", m.id},
                    {"kernel", kernel_name(m)},
                    {"order", m.order},
                    {"implicit", m.implicit},
                    {"form", form_name(m.form)},
                    {"claims", claim_words(m.claims)},
                    {"citation", m.citation}};
        if (check) {
            const auto checks = method_checks(m);
            json arr = json::array();
            for (const auto& c : checks) {
                (c.agrees() ? agree : disagree) += 1;
                arr.push_back({{"name", c.name},
                               {"what", c.what},
                               {"expected", c.expected},
                               {"holds", c.holds},
                               {"passed", c.agrees()},
                               {"value", number(c.value)},
                               {"tolerance", c.tolerance}});
            }
            if (checks.empty()) {
                ++unchecked;
                row["checks"] = nullptr;
                row["note"] = "no coefficient-level check";
            } else {
                row["checks"] = arr;
            }
        }
        methods.push_back(row);
    }
    if (as_json) {
        json doc = {{"methods", methods}};
        if (check)
            doc["summary"] = {{"checks_passed", agree},
                              {"checks_failed", disagree},
                              {"methods_without_check", unchecked}};
        out << doc.dump(2) << "\n";
        return disagree == 0 ? 0 : 1;
    }
    for (const auto& m : methods) {
        std::string claims;
        for (const auto& c : m["claims"])
            claims += (claims.empty() ? "" : ",") + c.get<std::string>();
        out << m["id"].get<std::string>() << "  [" << m["kernel"].get<std::string>() << "] order "
            << m["order"].get<int>() << (m["implicit"].get<bool>() ? ", implicit" : ", explicit")
            << ", " << m["form"].get<std::string>()
            << " form, claims: " << (claims.empty() ? "none" : claims) << "; "
            << m["citation"].get<std::string>() << "\n";
        if (!check) continue;
        if (m["checks"].is_null()) {
            out << "    no coefficient-level check\n";
            continue;
        }
        for (const auto& c : m["checks"]) {
            char value[64];
            if (c["value"].is_null())
                std::snprintf(value, sizeof value, "n/a");
            else
                std::snprintf(value, sizeof value, "%.2e", c["value"].get<double>());
            out << "    " << (c["passed"].get<bool>() ? "pass" : "FAIL") << "  "
                << c["name"].get<std::string>() << ": "
                << (c["holds"].get<bool>() ? "holds" : "fails") << " ("
                << (c["expected"].get<bool>() ? "expected to hold" : "expected to fail")
                << "), value " << value << ", tol " << c["tolerance"].get<double>() << "; "
                << c["what"].get<std::string>() << "\n";
        }
    }
    if (check)
        out << "Coefficient checks: " << agree << " agree with the declarations, " << disagree
            << " disagree; " << unchecked << " methods without a coefficient-level check\n";
    return disagree == 0 ? 0 : 1;
}

} // namespace dampsym::cli_detail
