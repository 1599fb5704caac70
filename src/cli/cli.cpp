#include "cli/cli.hpp"

#include "cli/cli_detail.hpp"
#include "cli/cli_progress.hpp"

#include "harness/case.hpp"
#include "harness/compare.hpp"
#include "harness/figures.hpp"
#include "harness/junit.hpp"
#include "harness/limits.hpp"
#include "harness/problem_info.hpp"
#include "harness/progress.hpp"
#include "harness/provenance.hpp"
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
using namespace cli_detail;

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
