// `dampsym list` (cases, problems, diagnostics, methods) and `dampsym methods` (the methods and
// their coefficient-level checks).
#include "cli/cli_detail.hpp"

#include "diagnostics/diagnostic.hpp"
#include "diagnostics/invariants_diagnostic.hpp"
#include "harness/case/case.hpp"
#include "harness/problem_info.hpp"
#include "harness/report/report.hpp"
#include "harness/user_methods/method_coefficients.hpp"
#include "harness/user_methods/method_export.hpp"
#include "harness/user_methods/method_files.hpp"
#include "harness/user_methods/plugins.hpp"
#include "methods/coefficient_checks.hpp"
#include "methods/runtime_methods.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <ostream>
#include <sstream>

namespace dampsym::cli_detail {

namespace fs = std::filesystem;

namespace {

// One problem of `list --json`: parameters (type, default, range), invariants, diagnostics.
json problem_json(const ProblemInfo& p) {
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
        if (diagnostic_applies(d, p) && (d != InvariantsDiagnostic::name || !p.invariants.empty()))
            diagnostics.push_back(d);
    return {{"id", p.id},
            {"title", p.title},
            {"params", params},
            {"invariants", p.invariants},
            {"exact_solution", p.has_exact},
            {"diagnostics", diagnostics}};
}

// What a diagnostic needs, in words, from its registry entry: of the problem (its requirement),
// of the case (a step ladder) and of the run (a reference, an observer, a Jacobian pass).
std::string needs_text(const DiagnosticInfo& d) {
    std::vector<std::string> parts;
    if (!d.requirement.empty()) parts.push_back(d.requirement);
    if (d.needs.min_dts > 0)
        parts.push_back("a dt_ladder of at least " + std::to_string(d.needs.min_dts) +
                        " step sizes");
    if (d.needs.reference || d.needs.reference_grid) parts.push_back("a reference");
    if (d.needs.observer) parts.push_back("a hook in the step loop");
    if (d.needs.jacobian_pass) parts.push_back("a separate pass with the exact step Jacobian");
    std::string out;
    for (const auto& p : parts) out += (out.empty() ? "" : "; ") + p;
    return out;
}

// Everything `list --json` prints: the selected cases, problems, diagnostics and methods.
json list_json(const Selected& selected) {
    json cases = json::array();
    for (const auto& c : selected.cases)
        cases.push_back({{"id", c.id},
                         {"file", c.file},
                         {"problem", c.problem_id},
                         {"methods", c.methods},
                         {"suites", c.suites},
                         {"diagnostics", c.diagnostics}});
    json problems = json::array();
    for (const auto& p : problem_catalog()) problems.push_back(problem_json(p));
    json diagnostics = json::array();
    // what each measures and needs comes from its own file (info()); its definition is its
    // entry in docs/conventions.md §5
    for (const DiagnosticInfo& d : diagnostic_registry())
        diagnostics.push_back({{"id", d.name},
                               {"what", d.what},
                               {"needs", needs_text(d)},
                               {"per_method", diagnostic_is_method_level(d.name)},
                               {"metrics", diagnostic_metric_names(d.name, {})}});
    diagnostics.push_back({{"id", "run"},
                           {"what", "the run record itself; checkable in every case"},
                           {"needs", ""},
                           {"per_method", false},
                           {"metrics", diagnostic_metric_names("run", {})},
                           {"note", "the run record itself; checkable in every case"}});
    json methods = json::array();
    std::vector<const MethodInfo*> rows;
    for (const auto& m : method_catalog()) rows.push_back(&m);
    for (const MethodInfo* m : loaded_methods()) rows.push_back(m); // method files
    for (const MethodInfo* m : rows) {
        methods.push_back({{"id", m->id},
                           {"order", m->order},
                           {"implicit", m->implicit},
                           {"form", form_name(m->form)},
                           {"kernel", kernel_name(*m)},
                           {"citation", m->citation}});
        if (const std::string f = method_file_of(m->id); !f.empty()) methods.back()["file"] = f;
    }
    return {{"cases", cases},
            {"problems", problems},
            {"diagnostics", diagnostics},
            {"methods", methods},
            {"case_keys_doc", "docs/case-keys.md"}};
}

std::string joined(const json& words, const char* sep) {
    std::string s;
    for (const auto& w : words) s += (s.empty() ? "" : sep) + w.get<std::string>();
    return s;
}

void print_problem(const json& p, std::ostream& out) {
    out << "  " << p["id"].get<std::string>() << "  " << p["title"].get<std::string>() << "\n";
    for (const auto& ps : p["params"]) {
        out << "      " << ps["name"].get<std::string>() << " = ";
        if (ps["type"] == "choice") {
            out << '"' << ps["default"].get<std::string>() << "\"  (one of "
                << joined(ps["choices"], " | ") << ")";
        } else {
            const json& r = ps["range"];
            std::ostringstream range;
            range << (r["min_exclusive"].get<bool>() ? "(" : "[") << r["min"].get<double>() << ", "
                  << r["max"].get<double>() << (r["max_exclusive"].get<bool>() ? ")" : "]");
            if (ps["type"] == "array")
                out << "array of <= " << ps["max_entries"].get<int>() << " numbers in "
                    << range.str() << " (default " << ps["default"].size() << " entries)";
            else
                out << ps["default"].dump() << "  in " << range.str()
                    << (ps["type"] == "integer" ? ", whole number" : "");
        }
        out << "  " << ps["doc"].get<std::string>() << "\n";
    }
    const std::string inv = joined(p["invariants"], ", ");
    out << "      invariants: " << (inv.empty() ? "none" : inv)
        << (p["exact_solution"].get<bool>() ? "; exact solution" : "; certified GSL reference")
        << "\n      diagnostics: " << joined(p["diagnostics"], ", ") << "\n";
}

void print_list(const json& doc, const std::string& cases_dir, std::ostream& out) {
    out << "Cases (" << cases_dir << "):\n";
    for (const auto& c : doc["cases"]) {
        const std::string suites = joined(c["suites"], ",");
        out << "  " << c["id"].get<std::string>() << "  [" << c["problem"].get<std::string>()
            << "; " << joined(c["methods"], ",") << "; suites: " << (suites.empty() ? "-" : suites)
            << "]\n";
    }
    out << "Problems (parameters: default, valid range, meaning; set as problem.NAME):\n";
    for (const auto& p : doc["problems"]) print_problem(p, out);
    out << "Diagnostics (what each measures, what it needs, its metrics for "
           "\"expect\": \"<diagnostic>.<metric>\"; definitions: docs/conventions.md §5):\n";
    for (const auto& d : doc["diagnostics"]) {
        const std::string needs = d["needs"].get<std::string>();
        out << "  " << d["id"].get<std::string>()
            << (d["per_method"].get<bool>() ? " (per method)" : "") << ": "
            << d["what"].get<std::string>() << (needs.empty() ? "" : " (needs " + needs + ")")
            << "\n      metrics: " << joined(d["metrics"], ", ") << "\n";
    }
    out << "Case file keys: docs/case-keys.md\nMethods:\n";
    for (const auto& m : doc["methods"])
        out << "  " << m["id"].get<std::string>() << "  order " << m["order"].get<int>()
            << (m["implicit"].get<bool>() ? ", implicit" : ", explicit") << ", "
            << m["form"].get<std::string>() << " form, " << m["citation"].get<std::string>()
            << "\n";
}

int cmd_list(bool as_json, const Selection& sel, const std::string& cases_dir, std::ostream& out) {
    const json doc = list_json(select_cases(sel, {}, cases_dir, false, !sel.shard.empty()));
    if (as_json)
        out << doc.dump(2) << "\n";
    else
        print_list(doc, cases_dir, out);
    return 0;
}

// `dampsym methods [--check] [--json]`: every registered method with its declaration and, with
// --check, the coefficient-level checks of its family (src/methods/coefficient_checks.hpp). A check
// passes when the coefficients agree with the declaration (order, claims), including the expected
// failures (order conditions beyond the declared order, symplecticity of a non-symplectic method).
// Exit status 1 if any check disagrees.
// With --methods FILE (harness/user_methods/method_files.hpp): the methods of those files instead
// of the built-in ones, each with its file, checked by the same method_checks as a built-in method
// of its family. With --plugin LIB (C plugins, harness/user_methods/plugins.hpp): its methods, with
// no coefficients to check.
int cmd_methods(bool check, bool as_json, const std::vector<std::string>& files,
                const std::vector<std::string>& plugins, std::ostream& out) {
    json methods = json::array();
    int agree = 0, disagree = 0, unchecked = 0;
    std::vector<const MethodInfo*> rows;
    for (const auto& f : files)
        for (const MethodInfo* m : load_method_file(f))
            if (std::find(rows.begin(), rows.end(), m) == rows.end()) rows.push_back(m);
    for (const auto& lib : plugins)
        for (const MethodInfo* m : load_plugin(lib))
            if (std::find(rows.begin(), rows.end(), m) == rows.end()) rows.push_back(m);
    if (files.empty() && plugins.empty())
        for (const auto& m : method_catalog()) rows.push_back(&m);
    for (const MethodInfo* mp : rows) {
        const MethodInfo& m = *mp;
        json row = {{"id", m.id},
                    {"kernel", kernel_name(m)},
                    {"order", m.order},
                    {"implicit", m.implicit},
                    {"form", form_name(m.form)},
                    {"claims", claim_words(m.claims)},
                    {"citation", m.citation}};
        if (!files.empty()) row["file"] = method_file_of(m.id);
        if (check) {
            const CoefficientVerdict v = coefficient_verdict(m);
            agree += v.agree;
            disagree += v.disagree;
            if (!v.checked()) {
                ++unchecked;
                row["checks"] = nullptr;
                row["note"] = "no coefficient-level check";
            } else {
                row["checks"] = v.checks;
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
                << (c.contains("inconclusive") ? "; inconclusive" : "") << "), value " << value
                << ", tol " << c["tolerance"].get<double>() << "; " << c["what"].get<std::string>()
                << "\n";
        }
    }
    if (check)
        out << "Coefficient checks: " << agree << " agree with the declarations, " << disagree
            << " disagree; " << unchecked << " methods without a coefficient-level check\n";
    return disagree == 0 ? 0 : 1;
}

// `dampsym methods --export ID --as NEW_ID [--out FILE]`: the built-in's method file
// (harness/user_methods/method_export.hpp), validated by the method-file parser before it is
// written.
int cmd_export(const std::string& id, const std::string& new_id, const std::string& out_file,
               std::ostream& out) {
    if (new_id.empty())
        throw InputError("--as: missing: --export needs the id the method file gives the method "
                         "(a method file cannot reuse a built-in id)");
    const std::string text = export_method_file(id, new_id).dump(2) + "\n";
    check_method_text(text, "--export " + id); // the export is a valid method file
    if (out_file.empty())
        out << text;
    else
        write_file_atomic(out_file, text);
    return 0;
}

} // namespace

Command add_list_command(CLI::App& app, CliContext& ctx) {
    struct State {
        Selection sel;
        bool as_json = false;
    };
    auto s = std::make_shared<State>();
    auto* list = app.add_subcommand("list", "list registered cases (filtered), problems, methods");
    list->add_flag("--json", s->as_json, "machine-readable output");
    add_selection_options(*list, s->sel);
    list->footer("\nExamples:\n  dampsym list --suite stress\n  dampsym list --filter 'osc-*' "
                 "--json\n  dampsym list --shard 1/3 --suite default\n\n" +
                 std::string(kExitCodes));
    return {list, [s, &ctx] { return cmd_list(s->as_json, s->sel, ctx.cases_dir, ctx.out); }};
}

Command add_methods_command(CLI::App& app, CliContext& ctx) {
    struct State {
        bool check = false, as_json = false;
        std::vector<std::string> files, plugins;
        std::string export_id, as_id, out_file;
    };
    auto s = std::make_shared<State>();
    auto* methods =
        app.add_subcommand("methods", "list every registered method; --check verifies its "
                                      "coefficients (order conditions, symplecticity, GLM)");
    methods->add_flag("--check", s->check,
                      "run the coefficient-level checks; exit 1 if one disagrees");
    methods->add_flag("--json", s->as_json, "machine-readable output");
    methods
        ->add_option("--methods", s->files,
                     "list (and --check) the methods of these method files instead of the "
                     "built-in ones (docs/method-files.md)")
        ->allow_extra_args(false);
    methods
        ->add_option("--plugin", s->plugins,
                     "list the methods of these C plugin libraries (docs/plugins.md)")
        ->allow_extra_args(false);
    auto* ex = methods->add_option(
        "--export", s->export_id,
        "write the method file of this built-in method (docs/method-files.md; bit for bit the "
        "same steps) to stdout or --out");
    methods->add_option("--as", s->as_id, "with --export: the id the method file gives it")
        ->needs(ex);
    methods->add_option("--out", s->out_file, "with --export: write to this file")->needs(ex);
    ex->excludes(methods->get_option("--check"))->excludes(methods->get_option("--methods"));
    return {methods, [s, &ctx] {
                if (!s->export_id.empty())
                    return cmd_export(s->export_id, s->as_id, s->out_file, ctx.out);
                return cmd_methods(s->check, s->as_json, s->files, s->plugins, ctx.out);
            }};
}

} // namespace dampsym::cli_detail
