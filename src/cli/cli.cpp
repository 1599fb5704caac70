#include "cli/cli.hpp"

#include "harness/case.hpp"
#include "harness/registry.hpp"
#include "harness/report.hpp"
#include "harness/runner.hpp"
#include "methods/coefficient_checks.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <ostream>
#include <sstream>

namespace dampsym {
namespace {

using json = nlohmann::json;
namespace fs = std::filesystem;

std::string default_cases_dir() {
    if (const char* env = std::getenv("DAMPSYM_CASES")) return env;
    return std::string(DAMPSYM_SOURCE_DIR) + "/verify/cases";
}

// A case file found in the cases directory, with the id and suites read from it.
struct CaseFile {
    std::string path, id;
    std::vector<std::string> suites;
};

std::vector<CaseFile> scan_cases(const std::string& dir) {
    if (!fs::is_directory(dir)) throw InputError(dir + ": cases directory not found");
    std::vector<std::string> paths;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().extension() == ".json") paths.push_back(e.path().string());
    std::sort(paths.begin(), paths.end());
    std::vector<CaseFile> out;
    std::map<std::string, std::string> seen;
    for (const auto& p : paths) {
        const json j = read_case_json(p); // regular file, bounded size, depth and keys checked
        if (!j.is_object()) throw InputError(p + ": (top level): a case must be a JSON object");
        if (!j.contains("id") || !j["id"].is_string())
            throw InputError(p + ": id: missing or not a string");
        CaseFile cf{p, j["id"].get<std::string>(), {}};
        if (j.contains("suites") && j["suites"].is_array())
            for (const auto& s : j["suites"])
                if (s.is_string()) cf.suites.push_back(s.get<std::string>());
        if (seen.count(cf.id))
            throw InputError(p + ": id: '" + cf.id + "' is also the id of " + seen[cf.id]);
        seen[cf.id] = p;
        out.push_back(cf);
    }
    return out;
}

int cmd_list(bool as_json, const std::string& cases_dir, std::ostream& out) {
    const auto files = scan_cases(cases_dir);
    json cases = json::array();
    for (const auto& f : files) {
        const CaseSpec c = load_case(f.path, {});
        cases.push_back({{"id", c.id},
                         {"file", f.path},
                         {"problem", c.problem_id},
                         {"methods", c.methods},
                         {"suites", c.suites},
                         {"diagnostics", c.diagnostics}});
    }
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
                           {"form", m.form},
                           {"kernel", m.kernel},
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
            << ", " << m.form << " form, " << m.citation << "\n";
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
                    {"kernel", m.kernel},
                    {"order", m.order},
                    {"implicit", m.implicit},
                    {"form", m.form},
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

int cmd_run(const std::vector<std::string>& targets, const std::string& suite,
            const std::string& out_dir, int jobs, double time_budget,
            const std::vector<std::string>& sets, const std::string& cases_dir, std::ostream& out) {
    if (jobs < 1) throw InputError("--jobs: must be >= 1");
    if (!(time_budget >= 0.0 && time_budget <= 60.0))
        throw InputError("--time-budget: must be between 0 and 60 seconds");
    for (const auto& s : sets) parse_override(s); // usage errors before any work
    std::vector<std::string> paths;
    std::vector<CaseFile> files;
    auto ensure_scanned = [&] {
        if (files.empty()) files = scan_cases(cases_dir);
    };
    if (targets.empty()) {
        ensure_scanned();
        for (const auto& f : files)
            if (std::find(f.suites.begin(), f.suites.end(), suite) != f.suites.end())
                paths.push_back(f.path);
        if (paths.empty())
            throw InputError("--suite: no case in " + cases_dir + " belongs to suite '" + suite +
                             "'");
    } else {
        for (const auto& t : targets) {
            // A path (it ends in .json or names a directory) is read as a case file, which must
            // be a regular .json file; anything else is a case id.
            const bool is_path = (t.size() > 5 && t.substr(t.size() - 5) == ".json") ||
                                 t.find('/') != std::string::npos;
            if (is_path) {
                paths.push_back(t);
                continue;
            }
            ensure_scanned();
            auto it = std::find_if(files.begin(), files.end(),
                                   [&](const CaseFile& f) { return f.id == t; });
            if (it != files.end()) {
                paths.push_back(it->path);
                continue;
            }
            std::error_code ec;
            const auto st = fs::status(t, ec);
            if (!ec && fs::is_directory(st))
                throw InputError(brief(t) + ": is a directory, not a case file or case id");
            if (!ec && fs::exists(st))
                throw InputError(brief(t) + ": not a case id in " + cases_dir +
                                 ", and as a file it does not end in .json");
            if (!valid_case_id(t))
                throw InputError(brief(t) + ": not a case id (ids are made of A-Z a-z 0-9 . _ -) "
                                            "and not a .json file");
            throw InputError(t + ": no case with this id in " + cases_dir);
        }
    }
    std::vector<CaseSpec> cases;
    for (const auto& p : paths) cases.push_back(load_case(p, sets)); // all validated before running
    check_unique_ids(cases);
    for (const auto& c : cases) {
        const double secs = case_predicted_seconds(c);
        if (secs < 10.0) continue;
        char line[256];
        std::snprintf(line, sizeof line,
                      "note: case '%s' runs %.3g steps; predicted duration about %.0f s "
                      "(rough estimate, diagnostics and references extra)\n",
                      c.id.c_str(), case_total_steps(c), secs);
        out << line << std::flush;
    }
    const json report = run_cases(cases, RunOptions{jobs, time_budget});
    write_reports(report, out_dir);
    out << render_summary(report) << "Reports: " << out_dir << "/report.json, " << out_dir
        << "/report.md\n";
    return report["summary"]["checks_failed"].get<std::int64_t>() == 0 ? 0 : 1;
}

} // namespace

int run_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
    CLI::App app{"dampsym: verification harness for structure-preserving integrators of damped "
                 "Hamiltonian systems"};
    app.require_subcommand(1);
    std::string cases_dir = default_cases_dir();
    app.add_option("--cases", cases_dir, "directory of case files (default: verify/cases)");

    auto* list = app.add_subcommand("list", "list every registered case, problem and method");
    bool list_json = false;
    list->add_flag("--json", list_json, "machine-readable output");

    auto* run =
        app.add_subcommand("run", "run cases (default: the default suite) and write reports");
    std::vector<std::string> targets, sets;
    std::string suite = "default", out_dir = "reports";
    int jobs = 1;
    run->add_option("cases", targets, "case ids or case files (.json)");
    run->add_option("--suite", suite, "suite to run when no case is named (default: default)");
    run->add_option("--out", out_dir, "directory for report.json and report.md (default: reports)");
    run->add_option("--jobs,-j", jobs, "worker threads (results do not depend on it)");
    double time_budget = RunOptions{}.time_budget;
    run->add_option("--time-budget", time_budget,
                    "seconds of timed repetitions per run of a step ladder (work-precision; "
                    "0 = off; default 0.02)");
    run->add_option("--set", sets, "override a case field, e.g. --set problem.gamma=0.3")
        ->take_all();

    auto* methods_cmd =
        app.add_subcommand("methods", "list every registered method; --check verifies its "
                                      "coefficients (order conditions, symplecticity, GLM)");
    bool methods_check = false, methods_json = false;
    methods_cmd->add_flag("--check", methods_check,
                          "run the coefficient-level checks; exit 1 if one disagrees");
    methods_cmd->add_flag("--json", methods_json, "machine-readable output");

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp&) {
        out << app.help();
        return 0;
    } catch (const CLI::CallForAllHelp&) {
        out << app.help("", CLI::AppFormatMode::All);
        return 0;
    } catch (const CLI::ParseError& e) {
        // "A subcommand is required" for `dampsym frobnicate`: name the word instead.
        for (int i = 1; i < argc; ++i) {
            const std::string a = argv[i];
            if (a == "--cases") {
                ++i;
                continue;
            }
            if (a.empty() || a[0] == '-') continue;
            if (a != "list" && a != "run" && a != "methods") {
                err << "dampsym: unknown subcommand '" << brief(a)
                    << "' (known: list, run, methods; dampsym --help)\n";
                return 2;
            }
            break;
        }
        err << "dampsym: " << e.what() << "\n";
        return 2;
    }
    try {
        if (*list) return cmd_list(list_json, cases_dir, out);
        if (*run) return cmd_run(targets, suite, out_dir, jobs, time_budget, sets, cases_dir, out);
        if (*methods_cmd) return cmd_methods(methods_check, methods_json, out);
    } catch (const InputError& e) {
        err << "dampsym: " << e.what() << "\n";
        return 2;
    }
    return 2;
}

} // namespace dampsym
