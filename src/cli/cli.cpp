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
        std::ifstream in(p);
        std::stringstream buf;
        buf << in.rdbuf();
        const json j = json::parse(buf.str(), nullptr, false);
        if (j.is_discarded() || !j.is_object()) throw InputError(p + ": malformed JSON");
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
        json params = json::object();
        for (const auto& ps : p.params)
            params[ps.name] = ps.is_array ? json(ps.default_array) : json(ps.default_value);
        problems.push_back(
            {{"id", p.id}, {"title", p.title}, {"params", params}, {"invariants", p.invariants}});
    }
    json methods = json::array();
    for (const auto& m : method_catalog())
        methods.push_back({{"id", m.id},
                           {"order", m.order},
                           {"implicit", m.implicit},
                           {"form", form_name(m.form)},
                           {"kernel", kernel_name(m)},
                           {"citation", m.citation}});
    if (as_json) {
        out << json{{"cases", cases}, {"problems", problems}, {"methods", methods}}.dump(2) << "\n";
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
    out << "Problems:\n";
    for (const auto& p : problems)
        out << "  " << p["id"].get<std::string>() << "  " << p["title"].get<std::string>() << "\n";
    out << "Methods:\n";
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
            if (t.size() > 5 && t.substr(t.size() - 5) == ".json") {
                paths.push_back(t);
                continue;
            }
            ensure_scanned();
            auto it = std::find_if(files.begin(), files.end(),
                                   [&](const CaseFile& f) { return f.id == t; });
            if (it == files.end()) throw InputError(t + ": no case with this id in " + cases_dir);
            paths.push_back(it->path);
        }
    }
    std::vector<CaseSpec> cases;
    for (const auto& p : paths) cases.push_back(load_case(p, sets)); // all validated before running
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
