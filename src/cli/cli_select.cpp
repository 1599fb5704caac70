#include "cli/cli_detail.hpp"

#include "core/method.hpp"
#include "harness/bounded_read.hpp"
#include "harness/case/case.hpp"
#include "harness/ci/junit.hpp"
#include "harness/ci/shard.hpp"
#include "harness/problem_info.hpp"
#include "harness/report/compare.hpp"
#include "harness/report/provenance.hpp"
#include "harness/report/report.hpp"
#include "harness/run/progress.hpp"
#include "harness/run/runner.hpp"
#include "harness/suggest.hpp"
#include "harness/user_methods/method_files.hpp"
#include "harness/user_methods/plugins.hpp"
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
#include <set>
#include <sstream>
#include <thread>
#include <unistd.h>

namespace dampsym::cli_detail {

namespace fs = std::filesystem;

std::string default_cases_dir() {
    if (const char* env = std::getenv("DAMPSYM_CASES")) return env;
    return source_dir() + "/verify/cases";
}

// A case file found in the cases directory, with the id, suites and problem read from it.
struct CaseFile {
    std::string path, id, problem;
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
        CaseFile cf{p, j["id"].get<std::string>(), "", {}};
        if (j.contains("suites") && j["suites"].is_array())
            for (const auto& s : j["suites"])
                if (s.is_string()) cf.suites.push_back(s.get<std::string>());
        if (j.contains("problem") && j["problem"].is_object() && j["problem"].contains("id") &&
            j["problem"]["id"].is_string())
            cf.problem = j["problem"]["id"].get<std::string>();
        if (seen.count(cf.id))
            throw InputError(p + ": id: '" + cf.id + "' is also the id of " + seen[cf.id]);
        seen[cf.id] = p;
        out.push_back(cf);
    }
    return out;
}

bool glob_any(const std::vector<std::string>& globs, const std::string& text) {
    for (const auto& g : globs)
        if (fnmatch(g.c_str(), text.c_str(), 0) == 0) return true;
    return false;
}

std::string describe_selection(const Selection& sel, bool default_suite) {
    std::string d;
    auto add = [&](const char* flag, const std::vector<std::string>& v) {
        for (const auto& x : v) d += std::string(d.empty() ? "" : " ") + flag + " '" + x + "'";
    };
    if (sel.suites.empty() && default_suite) d = "--suite 'default'";
    add("--suite", sel.suites);
    add("--filter", sel.filters);
    add("--problem", sel.problems);
    add("--method", sel.methods);
    return d;
}

// Keeps only the methods matching --method in a case (and the checks of those methods).
bool restrict_methods(CaseSpec& c, const std::vector<std::string>& globs) {
    if (globs.empty()) return true;
    std::vector<std::string> kept;
    for (const auto& m : c.methods)
        if (glob_any(globs, m)) kept.push_back(m);
    if (kept.empty()) return false;
    c.methods = kept;
    std::vector<CheckSpec> checks;
    for (auto cs : c.checks) {
        std::vector<std::string> ms, missing;
        for (const auto& m : cs.methods) (glob_any(globs, m) ? ms : missing).push_back(m);
        if (ms.empty()) continue;
        // A comparison (ratio, spread) of methods some of which were not selected measures
        // nothing: not run, never a failure; a per-method check keeps its selected methods.
        if (cs.form != CheckForm::per_method && !missing.empty()) {
            std::string names;
            for (const auto& m : missing) names += (names.empty() ? "" : ", ") + m;
            c.checks_not_run.push_back(
                {cs, "compares with " + names + ", not selected (--method)"});
            continue;
        }
        cs.methods = ms;
        checks.push_back(cs);
    }
    c.checks = checks;
    return true;
}

namespace {

// --substitute OLD=NEW: the method NEW stands in for OLD in every selected case that names OLD
// (its "methods" and the methods, ratio and spread of its checks), before --set; recorded in the
// case's overrides as "substitute": {OLD: NEW}. Validated after the method files are loaded.
using Substitutes = std::vector<std::pair<std::string, std::string>>;

Substitutes parse_substitutes(const std::vector<std::string>& given) {
    Substitutes out;
    for (const auto& s : given) {
        const auto eq = s.find('=');
        const std::string old_id = eq == std::string::npos ? "" : s.substr(0, eq);
        const std::string new_id = eq == std::string::npos ? "" : s.substr(eq + 1);
        if (!valid_case_id(old_id) || !valid_case_id(new_id))
            throw InputError("--substitute: '" + brief(s) +
                             "' is not OLD=NEW (two method ids, e.g. csv1=my-csv1)");
        if (old_id == new_id) throw InputError("--substitute: '" + s + "' names one method twice");
        if (find_method(new_id) == nullptr)
            throw InputError("--substitute: '" + new_id +
                             "' is not a built-in or loaded method (load it with --methods)");
        for (const auto& [o, n] : out)
            if (o == old_id) throw InputError("--substitute: '" + old_id + "' is given twice");
        out.emplace_back(old_id, new_id);
    }
    return out;
}

// Renames in one list of method ids; true if any was renamed.
bool rename_in(json& list, const std::string& old_id, const std::string& new_id) {
    bool any = false;
    if (!list.is_array()) return false;
    for (auto& m : list)
        if (m.is_string() && m.get<std::string>() == old_id) {
            m = new_id;
            any = true;
        }
    return any;
}

// Reads and parses one case file with the substitutions applied; `used` collects the OLD ids met.
CaseSpec load_substituted(const std::string& path, const std::vector<std::string>& sets,
                          const Substitutes& subs, std::set<std::string>& used) {
    if (subs.empty()) return load_case(path, sets);
    json j = read_case_json(path);
    json applied = json::object();
    for (const auto& [old_id, new_id] : subs) {
        if (!j.is_object() || !j.contains("methods") || !rename_in(j["methods"], old_id, new_id))
            continue;
        if (j.contains("expect") && j["expect"].is_object())
            for (auto& check : j["expect"])
                for (const char* k : {"methods", "ratio", "spread"})
                    if (check.is_object() && check.contains(k)) rename_in(check[k], old_id, new_id);
        applied[old_id] = new_id;
        used.insert(old_id);
    }
    if (applied.empty()) return parse_case(j, path, sets);
    try {
        CaseSpec c = parse_case(j, path, sets);
        c.overrides["substitute"] = applied;
        return c;
    } catch (const InputError& e) {
        throw InputError(std::string(e.what()) + " (with --substitute " + applied.dump() + ")");
    }
}

// The case files of the selection: the cases directory's files in the selected suites, matching
// --filter and --problem, or the named case ids and files.
std::vector<std::string> selected_paths(const Selection& sel, const std::string& cases_dir,
                                        bool default_suite) {
    std::vector<std::string> paths;
    std::vector<CaseFile> files;
    auto ensure_scanned = [&] {
        if (files.empty()) files = scan_cases(cases_dir);
    };
    if (sel.targets.empty()) {
        ensure_scanned();
        std::vector<std::string> suites = sel.suites;
        if (suites.empty() && default_suite) suites = {"default"};
        const bool all =
            suites.empty() || std::find(suites.begin(), suites.end(), "all") != suites.end();
        for (const auto& f : files) {
            const bool in_suite =
                all || std::any_of(suites.begin(), suites.end(), [&](const std::string& s) {
                    return std::find(f.suites.begin(), f.suites.end(), s) != f.suites.end();
                });
            if (!in_suite) continue;
            if (!sel.filters.empty() && !glob_any(sel.filters, f.id)) continue;
            if (!sel.problems.empty() && !glob_any(sel.problems, f.problem)) continue;
            paths.push_back(f.path);
        }
    } else {
        for (const auto& t : sel.targets) {
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
            std::vector<std::string> ids;
            for (const auto& f : files) ids.push_back(f.id);
            const std::string hint = did_you_mean(t, ids);
            throw InputError(t + ": no case with this id in " + cases_dir +
                             (hint.empty() ? "" : "; " + hint));
        }
    }
    return paths;
}

// A selected case's id (its file's, or set by --set id=) must not be the id of another case file
// in the cases directory: the report would show one case's results under another case's id, and
// compare, merge and --costs, keyed by id, would take them for that case's.
void check_ids_against_directory(const std::vector<CaseSpec>& loaded,
                                 const std::string& cases_dir) {
    std::error_code ec;
    if (!fs::is_directory(cases_dir, ec)) return;
    std::map<std::string, std::string> by_id;
    for (const auto& f : scan_cases(cases_dir)) by_id.emplace(f.id, f.path);
    for (const auto& c : loaded) {
        const auto it = by_id.find(c.id);
        if (it == by_id.end() || fs::equivalent(it->second, c.file, ec)) continue;
        const bool set = c.overrides.contains("id");
        throw InputError(quote_for_message(c.file) + ": id" +
                         (set ? " (set by --set id=" + quote_for_message(c.id) + ")" : "") + ": '" +
                         c.id + "' is the id of another case, " + it->second +
                         "; case ids must be unique among the cases directory's files and the "
                         "run's (give " +
                         (set ? "--set id=" : "the case") + " another id)");
    }
}

// Every selected file read and validated (with --substitute applied) before any case runs.
std::vector<CaseSpec> load_selected(const std::vector<std::string>& paths,
                                    const std::vector<std::string>& sets, const Substitutes& subs) {
    std::vector<CaseSpec> loaded;
    std::set<std::string> used; // --substitute's OLD ids met in the selected files
    for (const auto& p : paths) // all validated first
        loaded.push_back(load_substituted(p, sets, subs, used));
    for (const auto& [old_id, new_id] : subs)
        if (!used.count(old_id))
            throw InputError("--substitute: no selected case names the method '" + old_id + "'");
    check_unique_ids(loaded);
    return loaded;
}

} // namespace

json measured_case_costs(const Selection& sel, const std::string& cases_dir) {
    json measured = json::object();
    const std::string costs_file =
        !sel.costs.empty() ? sel.costs
                           : (fs::path(cases_dir).parent_path() / "case_costs.json").string();
    if (fs::exists(costs_file)) { // (a FIFO or device is refused, a large file not read)
        const json j =
            json::parse(read_regular_file(costs_file, kMaxCostsBytes, "--costs"), nullptr, false);
        if (j.is_discarded() || !j.is_object() || !j.contains("cases") || !j["cases"].is_object())
            throw InputError(quote_for_message(costs_file) +
                             ": cases: expected {\"cases\": {ID: seconds}}");
        measured = j["cases"];
    } else if (!sel.costs.empty()) {
        throw InputError(sel.costs + ": --costs: file not found");
    }
    return measured;
}

namespace {

// --shard K/N (or the CI engines' variables): keeps this shard's cases, balanced by cost.
void take_shard(Selected& out, const Selection& sel, const std::string& cases_dir) {
    if (sel.shard == "none") return;
    if (!sel.shard.empty())
        out.shard = parse_shard(sel.shard);
    else if (sel.targets.empty()) // named cases are never split by the engines' variables
        out.shard = shard_from_env([](const char* name) { return std::getenv(name); });
    if (!out.shard) return;
    const json measured = measured_case_costs(sel, cases_dir);
    std::vector<double> steps;
    for (const auto& c : out.cases) {
        double n = 0.0;
        for (const auto s : c.steps) n += static_cast<double>(s);
        steps.push_back(n * static_cast<double>(c.methods.size()));
    }
    const auto costs = estimate_costs(out.all_ids, steps, measured);
    const auto shard_of = assign_shards(costs, out.all_ids, out.shard->count);
    std::vector<CaseSpec> mine;
    for (std::size_t i = 0; i < out.cases.size(); ++i)
        if (shard_of[i] == out.shard->index - 1) mine.push_back(std::move(out.cases[i]));
    out.cases = std::move(mine);
}

} // namespace

Selected select_cases(const Selection& sel, const std::vector<std::string>& sets,
                      const std::string& cases_dir, bool default_suite, bool sharding) {
    // Method files: the methods/ folder beside the cases directory, then --methods;
    // a case's own "method_files" are loaded by parse_case.
    load_method_folder(method_folder_beside(cases_dir));
    for (const auto& f : sel.method_files) load_method_file(f);
    // C plugins (harness/user_methods/plugins.hpp)
    for (const auto& lib : sel.plugins) load_plugin(lib);
    const Substitutes subs = parse_substitutes(sel.substitutes);
    const std::vector<std::string> paths = selected_paths(sel, cases_dir, default_suite);
    std::vector<CaseSpec> loaded = load_selected(paths, sets, subs);
    check_ids_against_directory(loaded, cases_dir);
    Selected out;
    for (auto& c : loaded) {
        if (!sel.targets.empty()) { // named cases: the filters still apply
            if (!sel.filters.empty() && !glob_any(sel.filters, c.id)) continue;
            if (!sel.problems.empty() && !glob_any(sel.problems, c.problem_id)) continue;
            if (!sel.suites.empty() &&
                std::none_of(sel.suites.begin(), sel.suites.end(), [&](const std::string& s) {
                    return s == "all" ||
                           std::find(c.suites.begin(), c.suites.end(), s) != c.suites.end();
                }))
                continue;
        }
        if (!restrict_methods(c, sel.methods)) continue;
        out.cases.push_back(std::move(c));
    }
    if (out.cases.empty()) {
        if (sel.targets.empty() && sel.filters.empty() && sel.problems.empty() &&
            sel.methods.empty() && !sel.suites.empty())
            throw InputError("--suite: no case in " + cases_dir + " belongs to suite " +
                             describe_selection(sel, default_suite).substr(8));
        throw InputError("no case in " + cases_dir + " matches " +
                         describe_selection(sel, default_suite && sel.targets.empty()));
    }
    for (const auto& c : out.cases) out.all_ids.push_back(c.id);
    if (!sharding) return out;
    take_shard(out, sel, cases_dir);
    return out;
}

} // namespace dampsym::cli_detail
