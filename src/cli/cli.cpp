#include "cli/cli.hpp"

#include "harness/case.hpp"
#include "harness/compare.hpp"
#include "harness/figures.hpp"
#include "harness/junit.hpp"
#include "harness/limits.hpp"
#include "harness/progress.hpp"
#include "harness/provenance.hpp"
#include "harness/registry.hpp"
#include "harness/report.hpp"
#include "harness/runner.hpp"
#include "harness/shard.hpp"
#include "methods/coefficient_checks.hpp"

#include <CLI/CLI.hpp>
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

namespace dampsym {
namespace {

using json = nlohmann::json;
namespace fs = std::filesystem;

std::string default_cases_dir() {
    if (const char* env = std::getenv("DAMPSYM_CASES")) return env;
    return std::string(DAMPSYM_SOURCE_DIR) + "/verify/cases";
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

// What to run (or list): case ids or files, or the cases of the cases directory restricted by
// suite, id glob, problem and method; then, for run, one shard of that selection.
struct Selection {
    std::vector<std::string> targets, filters, suites, methods, problems;
    std::string shard; // "K/N", "none", or "" (read the CI engines' variables)
    std::string costs; // measured case costs for sharding ("" = next to the cases directory)
};

struct Selected {
    std::vector<CaseSpec> cases;      // this shard's
    std::vector<std::string> all_ids; // the whole selection, in order
    std::optional<ShardSpec> shard;
};

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
        std::vector<std::string> ms;
        for (const auto& m : cs.methods)
            if (glob_any(globs, m)) ms.push_back(m);
        if (ms.empty()) continue;
        cs.methods = ms;
        checks.push_back(cs);
    }
    c.checks = checks;
    return true;
}

// `default_suite`: the run command's default ("default" when neither a case nor --suite is
// given); list shows every case.
Selected select_cases(const Selection& sel, const std::vector<std::string>& sets,
                      const std::string& cases_dir, bool default_suite, bool sharding) {
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
            throw InputError(t + ": no case with this id in " + cases_dir);
        }
    }
    std::vector<CaseSpec> loaded;
    for (const auto& p : paths) loaded.push_back(load_case(p, sets)); // all validated first
    check_unique_ids(loaded);
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
    if (sel.shard == "none") return out;
    if (!sel.shard.empty())
        out.shard = parse_shard(sel.shard);
    else if (sel.targets.empty()) // named cases are never split by the engines' variables
        out.shard = shard_from_env([](const char* name) { return std::getenv(name); });
    if (!out.shard) return out;
    json measured = json::object();
    const std::string costs_file =
        !sel.costs.empty() ? sel.costs
                           : (fs::path(cases_dir).parent_path() / "case_costs.json").string();
    if (fs::exists(costs_file)) {
        std::ifstream in(costs_file);
        std::stringstream buf;
        buf << in.rdbuf();
        const json j = json::parse(buf.str(), nullptr, false);
        if (j.is_discarded() || !j.is_object() || !j.contains("cases") || !j["cases"].is_object())
            throw InputError(costs_file + ": cases: expected {\"cases\": {ID: seconds}}");
        measured = j["cases"];
    } else if (!sel.costs.empty()) {
        throw InputError(sel.costs + ": --costs: file not found");
    }
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
    return out;
}

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

// The progress line on stderr: only when stderr is a terminal, and only once the run has taken
// more than a second; erased when the run ends.
class ProgressLine {
public:
    explicit ProgressLine(bool enabled) : enabled_(enabled), start_(Clock::now()) {
        if (enabled_) thread_ = std::thread([this] { loop(); });
    }
    ~ProgressLine() { stop(); }
    ProgressLine(const ProgressLine&) = delete;
    ProgressLine& operator=(const ProgressLine&) = delete;

    ProgressCallback callback() {
        if (!enabled_) return {};
        return [this](const RunProgress& p) {
            std::lock_guard<std::mutex> lock(m_);
            state_ = p;
        };
    }
    void stop() {
        if (!thread_.joinable()) return;
        {
            std::lock_guard<std::mutex> lock(m_);
            done_ = true;
        }
        cv_.notify_all();
        thread_.join();
        if (shown_) std::cerr << "\r\033[K" << std::flush;
    }

private:
    using Clock = std::chrono::steady_clock;
    void loop() {
        std::unique_lock<std::mutex> lock(m_);
        while (!cv_.wait_for(lock, std::chrono::milliseconds(250), [this] { return done_; })) {
            const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
            if (elapsed < 1.0) continue;
            char eta[32] = "?";
            if (!state_.planned)
                std::snprintf(eta, sizeof eta, "? (references)");
            else if (state_.tasks_done > 0 && state_.tasks_total >= state_.tasks_done)
                std::snprintf(eta, sizeof eta, "%.0f s",
                              elapsed *
                                  static_cast<double>(state_.tasks_total - state_.tasks_done) /
                                  static_cast<double>(state_.tasks_done));
            char line[256];
            std::snprintf(line, sizeof line, "[%zu/%zu cases] %.40s  %.0f s elapsed, ETA %s",
                          state_.cases_done, state_.cases_total, state_.current.c_str(), elapsed,
                          eta);
            std::cerr << "\r\033[K" << line << std::flush;
            shown_ = true;
        }
    }
    bool enabled_;
    Clock::time_point start_;
    std::mutex m_;
    std::condition_variable cv_;
    RunProgress state_;
    bool done_ = false, shown_ = false;
    std::thread thread_;
};

// GitHub workflow-command escaping (data; properties also escape ':' and ',').
std::string gh_escape(const std::string& s, bool property) {
    std::string out;
    for (char c : s) {
        if (c == '%')
            out += "%25";
        else if (c == '\r')
            out += "%0D";
        else if (c == '\n')
            out += "%0A";
        else if (property && c == ':')
            out += "%3A";
        else if (property && c == ',')
            out += "%2C";
        else
            out += c;
    }
    return out;
}

// The case file relative to the working directory (the repository root in a workflow).
std::string relative_file(const std::string& file) {
    std::error_code ec;
    const fs::path rel = fs::relative(fs::absolute(file, ec), fs::current_path(ec), ec);
    if (ec || rel.empty() || rel.string().rfind("..", 0) == 0) return file;
    return rel.string();
}

std::string check_text(const json& ck) {
    std::ostringstream os;
    os << ck["metric"].get<std::string>() << " = "
       << (ck["value"].is_null() ? std::string("null") : ck["value"].dump()) << ", expected "
       << ck["op"].get<std::string>() << " " << ck["expected"].dump();
    if (ck.contains("tolerance")) os << " (tol " << ck["tolerance"].dump() << ")";
    if (ck.contains("message")) os << ": " << ck["message"].get<std::string>();
    return os.str();
}

void github_annotations(const json& report, std::ostream& out) {
    for (const auto& c : report["cases"])
        for (const auto& ck : c["checks"]) {
            if (ck["passed"].get<bool>()) continue;
            out << "::error file=" << gh_escape(relative_file(c.value("file", std::string())), true)
                << ",title="
                << gh_escape("dampsym " + c["id"].get<std::string>() + ": " + junit_test_name(ck),
                             true)
                << "::" << gh_escape(check_text(ck), false) << "\n";
        }
}

// Appends totals and failing checks (at most 50) to $GITHUB_STEP_SUMMARY, never the whole report.
void github_step_summary(const json& report, std::ostream& err) {
    const char* path = std::getenv("GITHUB_STEP_SUMMARY");
    if (!path || !*path) return;
    std::ostringstream os;
    const json& s = report["summary"];
    os << "### dampsym: " << (s["checks_failed"].get<std::int64_t>() == 0 ? "passed" : "FAILED")
       << "\n\n"
       << render_totals(report) << "\n";
    int shown = 0, failing = 0;
    for (const auto& c : report["cases"])
        for (const auto& ck : c["checks"]) {
            if (ck["passed"].get<bool>()) continue;
            if (failing++ == 0) os << "| case | check | result |\n|---|---|---|\n";
            if (shown >= 50) continue;
            ++shown;
            std::string text = check_text(ck);
            for (auto& ch : text)
                if (ch == '|' || ch == '\n') ch = ' ';
            os << "| " << c["id"].get<std::string>() << " | " << junit_test_name(ck) << " | "
               << text << " |\n";
        }
    if (failing > shown) os << "\n… and " << failing - shown << " more failing checks.\n";
    std::ofstream f(path, std::ios::app);
    f << os.str() << "\n";
    if (!f) err << "dampsym: warning: cannot append to GITHUB_STEP_SUMMARY=" << path << "\n";
}

struct OutputOptions {
    std::string out_dir = "reports";
    std::string junit;       // "" = none
    std::string annotations; // "" or "github"
    bool quiet = false;
    bool figures = false; // run --figures (issue 14, harness/figures.hpp)
};

// Writes the reports and prints the summary; returns the exit status of the checks.
int finish_report(const json& report, const OutputOptions& o, std::ostream& out,
                  std::ostream& err) {
    write_reports(report, o.out_dir);
    if (!o.junit.empty()) write_file_atomic(o.junit, render_junit(report));
    if (o.annotations == "github") github_annotations(report, out);
    github_step_summary(report, err);
    if (o.quiet) {
        out << render_totals(report);
    } else {
        out << render_summary(report) << "Reports: " << o.out_dir << "/report.json, " << o.out_dir
            << "/report.md" << (o.junit.empty() ? "" : ", " + o.junit) << "\n";
    }
    return report["summary"]["checks_failed"].get<std::int64_t>() == 0 ? 0 : 1;
}

int cmd_run(const Selection& sel, const OutputOptions& o, int jobs, double time_budget,
            const CliLimits& limits, const std::vector<std::string>& sets,
            const std::string& cases_dir, const std::vector<std::string>& command_line,
            std::ostream& out, std::ostream& err) {
    for (const auto& s : sets) parse_override(s); // usage errors before any work
    const Selected selected = select_cases(sel, sets, cases_dir, true, true);
    check_output_dir(o.out_dir); // an unwritable --out fails before any case runs (exit 3)
    if (!o.junit.empty()) check_output_file(o.junit);
    before_run(selected.cases, jobs, limits); // memory limit, SIGINT/SIGTERM (harness/limits.hpp)
    for (const auto& c : selected.cases) {
        const double secs = case_predicted_seconds(c);
        if (secs < 10.0) continue;
        char line[256];
        std::snprintf(line, sizeof line,
                      "note: case '%s' runs %.3g steps; predicted duration about %.0f s "
                      "(rough estimate, diagnostics and references extra)\n",
                      c.id.c_str(), case_total_steps(c), secs);
        err << line << std::flush;
    }
    const auto start = std::chrono::system_clock::now();
    json report;
    {
        ProgressLine progress(!o.quiet && &err == &std::cerr && isatty(STDERR_FILENO) == 1);
        RunOptions ro;
        ro.jobs = jobs;
        ro.time_budget = time_budget;
        ro.case_timeout = limits.case_timeout;                       // issue 17 (limits.hpp)
        if (o.figures) ro.series_sink = series_file_sink(o.out_dir); // figures hook (issue 14)
        report = run_cases(selected.cases, ro, progress.callback());
    }
    report["provenance"] = make_provenance(command_line, jobs, start);
    if (selected.shard)
        report["provenance"]["shard"] = {{"index", selected.shard->index},
                                         {"count", selected.shard->count},
                                         {"source", selected.shard->source},
                                         {"selected", selected.all_ids}};
    mark_interrupted(report);
    const int status = exit_status_after_run(finish_report(report, o, out, err));
    if (o.figures && report.value("interrupted", false) == false) {
        // figures hook (issue 14): draw, then report.md again with the figures
        if (make_figures(o.out_dir, jobs, err) != 0) return 3;
        if (!o.quiet)
            out << "Figures: " << o.out_dir << "/figures/, " << o.out_dir << "/figures.md\n";
    }
    return status;
}

json read_report(const std::string& arg) {
    const fs::path p = fs::is_directory(arg) ? fs::path(arg) / "report.json" : fs::path(arg);
    std::ifstream in(p);
    if (!in) throw InputError(p.string() + ": cannot open report");
    std::stringstream buf;
    buf << in.rdbuf();
    const json j = json::parse(buf.str(), nullptr, false);
    if (j.is_discarded()) throw InputError(p.string() + ": malformed JSON");
    return j;
}

int cmd_compare(const std::string& base, const std::string& next, const CompareOptions& opt,
                bool as_json, std::ostream& out) {
    const json a = read_report(base), b = read_report(next);
    json result;
    try {
        result = compare_reports(a, b, opt);
    } catch (const InputError& e) {
        std::string what = e.what();
        if (what.rfind("BASE", 0) == 0) what = base + what.substr(4);
        if (what.rfind("NEW", 0) == 0) what = next + what.substr(3);
        throw InputError(what);
    }
    result["base"] = base;
    result["new"] = next;
    if (as_json)
        out << result.dump(2) << "\n";
    else
        out << render_compare_markdown(result);
    return result["equal"].get<bool>() ? 0 : 1;
}

int cmd_merge(const std::string& out_dir, const std::vector<std::string>& inputs,
              const OutputOptions& o, const std::vector<std::string>& command_line,
              std::ostream& out, std::ostream& err) {
    std::vector<json> reports;
    for (const auto& in : inputs) reports.push_back(read_report(in));
    check_output_dir(out_dir);
    const auto start = std::chrono::system_clock::now();
    json prov = {{"version", DAMPSYM_VERSION},
                 {"command_line", command_line.empty() ? std::string() : [&] {
                      std::string s;
                      for (const auto& a : command_line) s += (s.empty() ? "" : " ") + a;
                      return s;
                  }()},
                 {"start_utc", utc_iso8601(start)}};
    const json merged = merge_reports(reports, inputs, prov);
    OutputOptions mo = o;
    mo.out_dir = out_dir;
    mo.junit = out_dir + "/junit.xml";
    return finish_report(merged, mo, out, err);
}

const char* kExitCodes = "Exit status: 0 all checks passed (compare: nothing moved), 1 a check "
                         "failed (compare: something moved), 2 bad input or usage (one line naming "
                         "the file and key; also a case above --max-memory), 3 internal or I/O "
                         "error (e.g. an unwritable --out), 130/143 stopped by SIGINT/SIGTERM "
                         "(report of what finished written, marked interrupted).";

} // namespace

int run_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
    std::vector<std::string> command_line(argv, argv + argc);
    CLI::App app{"dampsym: verification harness for structure-preserving integrators of damped "
                 "Hamiltonian systems"};
    app.require_subcommand(1);
    app.fallthrough(); // global options are accepted after the subcommand too
    app.set_version_flag("--version", version_string());
    app.footer(std::string("\nExamples:\n"
                           "  dampsym run --out reports --jobs 4          the default suite\n"
                           "  dampsym run --suite stress --time-budget 0  another suite\n"
                           "  dampsym run --filter 'pend-*' --method csv1 a selection\n"
                           "  dampsym run --shard 2/4 --out shard2        one of four CI jobs\n"
                           "  dampsym merge reports shard1 shard2 shard3 shard4\n"
                           "  dampsym compare base/report.json reports/report.json\n"
                           "  dampsym list --suite default\n\n") +
               kExitCodes);
    std::string cases_dir = default_cases_dir();
    app.add_option("--cases", cases_dir, "directory of case files (default: verify/cases)");

    Selection sel;
    auto add_selection = [&](CLI::App* sub) {
        sub->add_option("--suite", sel.suites,
                        "suite(s) to take cases from; repeatable; 'all' = every case")
            ->allow_extra_args(false);
        sub->add_option("--filter", sel.filters, "glob on case ids (repeatable: any may match)")
            ->allow_extra_args(false);
        sub->add_option("--problem", sel.problems, "glob on problem ids (repeatable)")
            ->allow_extra_args(false);
        sub->add_option("--method", sel.methods,
                        "glob on method ids (repeatable): only these runs and their checks")
            ->allow_extra_args(false);
        sub->add_option("--shard", sel.shard,
                        "K/N: run share K of N (cost-balanced); 'none' ignores TEST_TOTAL_SHARDS, "
                        "CI_NODE_TOTAL and SLURM_ARRAY_TASK_COUNT");
        sub->add_option("--costs", sel.costs,
                        "measured case costs for --shard (default: case_costs.json beside the "
                        "cases directory)");
    };

    auto* list = app.add_subcommand("list", "list registered cases (filtered), problems, methods");
    bool list_json = false;
    list->add_flag("--json", list_json, "machine-readable output");
    add_selection(list);
    list->footer("\nExamples:\n  dampsym list --suite stress\n  dampsym list --filter 'osc-*' "
                 "--json\n  dampsym list --shard 1/3 --suite default\n\n" +
                 std::string(kExitCodes));

    auto* run =
        app.add_subcommand("run", "run cases (default: the default suite) and write reports");
    std::vector<std::string> sets;
    OutputOptions oo;
    int jobs = 1;
    run->add_option("cases", sel.targets, "case ids or case files (.json)");
    add_selection(run);
    run->add_option("--out", oo.out_dir,
                    "directory for report.json and report.md (default: reports)");
    run->add_option("--junit", oo.junit, "also write JUnit XML (one testcase per check) to FILE");
    run->add_option("--jobs,-j", jobs, "worker threads (results do not depend on it)")
        ->check(CLI::Range(1, 4096));
    double time_budget = RunOptions{}.time_budget;
    run->add_option("--time-budget", time_budget,
                    "seconds of timed repetitions per run of a step ladder (work-precision; "
                    "0 = off; default 0.02)")
        ->check(CLI::Range(0.0, 60.0));
    CliLimits limits;
    add_limit_options(*run, limits); // --case-timeout, --max-memory (harness/limits.hpp)
    run->add_option("--set", sets, "override a case field, e.g. --set problem.gamma=0.3")
        ->take_all();
    run->add_option("--annotations", oo.annotations,
                    "github: print ::error lines for failing checks")
        ->check(CLI::IsMember({"github"}));
    run->add_flag("--quiet,-q", oo.quiet, "only errors and the final totals line");
    run->add_flag("--figures", oo.figures,
                  "keep time series (DIR/series/) and draw the figures into DIR/figures/, "
                  "embedded in report.md (docs/reports.md)");
    run->footer(
        "\nExamples:\n"
        "  dampsym run                                   default suite into reports/\n"
        "  dampsym run pend-fig411-drift --jobs 2         one case\n"
        "  dampsym run --suite default --suite stress --filter 'osc-*'\n"
        "  dampsym run --junit reports/junit.xml --annotations github --quiet\n"
        "  dampsym run --shard 1/3 --out shard1           (or TEST_TOTAL_SHARDS/TEST_SHARD_INDEX,\n"
        "                                                 CI_NODE_TOTAL/CI_NODE_INDEX,\n"
        "                                                 SLURM_ARRAY_TASK_COUNT/_ID)\n"
        "  dampsym run osc-orders --set problem.gamma=0.3\n\n"
        "report.json: schema/report.schema.json; everything before \"provenance\" is identical\n"
        "between runs of the same build. GITHUB_STEP_SUMMARY, if set, gets totals and "
        "failures.\n\n" +
        std::string(kExitCodes));

    // Figures (issue 14, harness/figures.hpp): draw the figures of an existing report directory.
    auto* plot = app.add_subcommand(
        "plot", "draw the figures of a report directory (REPORT_DIR/figures/, report.md, "
                "figures.md); time series only if it was run with --figures");
    std::string plot_dir;
    int plot_jobs = 2;
    plot->add_option("REPORT_DIR", plot_dir, "directory holding report.json")->required();
    plot->add_option("--jobs,-j", plot_jobs, "figure processes")->check(CLI::Range(1, 256));

    auto* compare = app.add_subcommand(
        "compare", "compare two reports: final states, metrics, order fits, check verdicts");
    std::string cmp_base, cmp_new;
    CompareOptions copt;
    bool cmp_json = false;
    compare->add_option("BASE", cmp_base, "base report.json (or its directory)")->required();
    compare->add_option("NEW", cmp_new, "new report.json (or its directory)")->required();
    compare->add_option("--rtol", copt.rtol, "relative tolerance (default 0: bitwise)")
        ->check(CLI::NonNegativeNumber);
    compare->add_option("--atol", copt.atol, "absolute tolerance (default 0)")
        ->check(CLI::NonNegativeNumber);
    compare->add_flag("--ignore-timings", copt.ignore_timings,
                      "omit the (information-only) wall-time table");
    compare->add_flag("--json", cmp_json, "JSON instead of Markdown");
    compare->footer("\nExamples:\n  dampsym compare base/report.json reports/report.json\n"
                    "  dampsym compare base reports --rtol 1e-12 --json > diff.json\n\n"
                    "Exit status: 0 nothing moved, 1 something moved (rows listed), 2 bad input.");

    auto* merge = app.add_subcommand(
        "merge", "merge shard reports into one report.json, report.md and junit.xml");
    std::string merge_out;
    std::vector<std::string> merge_in;
    merge->add_option("OUT_DIR", merge_out, "directory for the merged reports")->required();
    merge->add_option("IN_DIR", merge_in, "shard report directories (or report.json files)")
        ->required();
    merge->add_option("--annotations", oo.annotations, "github: ::error lines for failures")
        ->check(CLI::IsMember({"github"}));
    merge->add_flag("--quiet,-q", oo.quiet, "only errors and the final totals line");
    merge->footer("\nExamples:\n  dampsym merge reports shard1 shard2 shard3\n\n"
                  "The merged report's part before \"provenance\" is byte-identical to that of "
                  "the unsharded run.\n\n" +
                  std::string(kExitCodes));

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
    } catch (const CLI::CallForVersion& e) {
        out << e.what() << "\n";
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
            if (a != "list" && a != "run" && a != "methods" && a != "plot") {
                err << "dampsym: unknown subcommand '" << brief(a)
                    << "' (known: list, run, methods, plot; dampsym --help)\n";
                return 2;
            }
            break;
        }
        err << "dampsym: " << e.what() << "\n";
        return 2;
    }
    try {
        if (*plot) return make_figures(plot_dir, plot_jobs, err); // issue 14
        if (*list) return cmd_list(list_json, sel, cases_dir, out);
        if (*run)
            return cmd_run(sel, oo, jobs, time_budget, limits, sets, cases_dir, command_line, out,
                           err);
        if (*compare) return cmd_compare(cmp_base, cmp_new, copt, cmp_json, out);
        if (*merge) return cmd_merge(merge_out, merge_in, oo, command_line, out, err);
        if (*methods_cmd) return cmd_methods(methods_check, methods_json, out);
    } catch (const InputError& e) {
        err << "dampsym: " << e.what() << "\n";
        return 2;
    } catch (const OutputError& e) {
        err << "dampsym: " << e.what() << "\n";
        return 3;
    } catch (const std::exception& e) {
        err << "dampsym: internal error: " << e.what() << "\n";
        return 3;
    }
    return 2;
}

} // namespace dampsym
