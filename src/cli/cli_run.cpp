// `dampsym run` (cases -> report.json, report.md, JUnit, figures) and `dampsym merge` (shard
// reports -> one report).
#include "cli/cli_detail.hpp"
#include "cli/cli_progress.hpp"

#include "harness/case/case.hpp"
#include "harness/case/recorded_file.hpp"
#include "harness/ci/junit.hpp"
#include "harness/ci/shard.hpp"
#include "harness/figures/figures.hpp"
#include "harness/finite_option.hpp"
#include "harness/report/provenance.hpp"
#include "harness/report/report.hpp"
#include "harness/report/tables.hpp"
#include "harness/run/limits.hpp"
#include "harness/run/progress.hpp"
#include "harness/run/runner.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <unistd.h>

namespace dampsym::cli_detail {
namespace {

namespace fs = std::filesystem;

struct OutputOptions {
    std::string out_dir = "reports";
    std::string junit;        // "" = none
    bool junit_given = false; // --junit was on the command line (an empty FILE is an error)
    std::string annotations;  // "" or "github"
    bool quiet = false;
    bool figures = false;              // run --figures (harness/figures/figures.hpp)
    std::string figure_format = "png"; // --figure-format png|svg|pdf[,...]
};

// A path as the file system would reach it, for comparing two output paths: absolute, with "."
// and ".." and the symbolic links of its existing part resolved.
fs::path resolved(const std::string& p) {
    std::error_code ec;
    const fs::path r = fs::weakly_canonical(fs::absolute(p), ec);
    return ec ? fs::absolute(p).lexically_normal() : r;
}

// Usage errors of the output options (exit 2), before any work: an empty --out or --junit, and a
// --junit FILE that is another output of the same run (report.json, report.md; with --figures
// figures.md or a file under series/ or figures/), which it would silently overwrite.
void check_output_options(const OutputOptions& o) {
    if (o.out_dir.empty()) throw InputError("--out: empty directory name");
    if (!o.junit_given) return;
    if (o.junit.empty()) throw InputError("--junit: empty file name");
    const fs::path junit = resolved(o.junit);
    const fs::path dir = resolved(o.out_dir);
    std::vector<fs::path> taken = {dir / "report.json", dir / "report.md"};
    if (o.figures) taken.push_back(dir / "figures.md");
    for (const auto& t : taken) {
        std::error_code ec;
        if (junit == t || fs::equivalent(junit, t, ec))
            throw InputError("--junit: " + o.junit + " is " + t.string() +
                             ", another output of this run");
    }
    if (o.figures &&
        (junit.parent_path() == dir / "series" || junit.parent_path() == dir / "figures"))
        throw InputError("--junit: " + o.junit + " is inside " + junit.parent_path().string() +
                         ", which --figures writes");
}

// Writes the reports and prints the summary; returns the exit status of the checks. `streamed`:
// the case lines were printed as the cases finished (run), so only the failing ones are
// repeated here, in case order; else (merge) every case's line is printed. -q prints every
// failing check (at most 50) and the totals.
int finish_report(const json& report, const OutputOptions& o, bool streamed, std::ostream& out,
                  std::ostream& err) {
    write_reports(report, o.out_dir);
    if (!o.junit.empty()) write_file_atomic(o.junit, render_junit(report));
    if (o.annotations == "github") github_annotations(report, out);
    github_step_summary(report, err);
    if (o.quiet) {
        out << render_failed_checks(report, 50) << render_totals(report);
    } else if (!streamed) {
        out << render_summary(report);
    } else {
        const json& cases = report["cases"];
        if (report["summary"]["failed_cases"].get<std::int64_t>() > 0) {
            out << "\nFailed cases (report.md lists every check):\n";
            for (std::size_t i = 0; i < cases.size(); ++i)
                if (!report_detail::case_passed(cases[i]))
                    out << render_case_line(cases[i], json());
        }
        out << render_totals(report);
    }
    if (!o.quiet)
        out << "Reports: " << o.out_dir << "/report.json, " << o.out_dir << "/report.md"
            << (o.junit.empty() ? "" : ", " + o.junit) << "\n";
    return report["summary"]["checks_failed"].get<std::int64_t>() == 0 ? 0 : 1;
}

// The line of a case as it finishes (-q: failing cases only), flushed at once, so that a log
// that is not a terminal shows it then, not at the end of the run.
std::function<void(const json&)> case_line_printer(const OutputOptions& o, std::ostream& out) {
    return [&o, &out](const json& c) {
        if (o.quiet && report_detail::case_passed(c)) return;
        double seconds = 0.0;
        for (const auto& r : c["runs"])
            if (r.contains("wall_seconds")) seconds += r["wall_seconds"].get<double>();
        out << render_case_line(c, seconds) << std::flush;
    };
}

// The cases directory in use when it is not ./verify/cases although that exists (a run from
// another checkout than the binary's source tree reads the binary's cases, not the ones here).
void note_other_cases_dir(const std::string& cases_dir, std::ostream& err) {
    std::error_code ec;
    const fs::path here = fs::path("verify") / "cases";
    if (!fs::is_directory(here, ec) || fs::equivalent(here, cases_dir, ec)) return;
    err << "note: cases from " << cases_dir << " (--cases, DAMPSYM_CASES or this binary's source "
        << "tree), not ./verify/cases; give --cases verify/cases to run those\n";
}

// The shard in use, and where it came from (--shard or a CI engine's variables).
void print_shard(const Selected& selected, const OutputOptions& o, std::ostream& out) {
    if (!selected.shard || o.quiet) return;
    out << "shard " << selected.shard->index << "/" << selected.shard->count << " (from "
        << selected.shard->source << "): " << selected.cases.size() << " of "
        << selected.all_ids.size() << " selected cases\n"
        << std::flush;
}

// A case's predicted run time and whether it is measured: the case's own measured seconds
// (case_costs.json, ci/case_costs.sh) when it runs as its file says (no --set), else the fixed
// per-component estimate (case_predicted_seconds: 30 ns per component and step, 300 implicit).
static std::pair<double, bool> estimated_seconds(const CaseSpec& c, const json& measured) {
    const auto it = measured.find(c.id);
    if (c.overrides.empty() && it != measured.end() && it->is_number() && it->get<double>() >= 0.0)
        return {it->get<double>(), true};
    return {case_predicted_seconds(c), false};
}

int cmd_run(const Selection& sel, const OutputOptions& o, int jobs, double time_budget,
            const CliLimits& limits, const std::vector<std::string>& sets,
            const std::string& cases_dir, const std::vector<std::string>& command_line,
            std::ostream& out, std::ostream& err) {
    for (const auto& s : sets) parse_override(s); // usage errors before any work
    check_output_options(o);
    const Selected selected = select_cases(sel, sets, cases_dir, true, true);
    check_output_dir(o.out_dir); // an unwritable --out fails before any case runs (exit 3)
    if (!o.junit.empty()) check_output_file(o.junit);
    if (o.figures)
        if (const std::string e = figure_dirs_error(o.out_dir); !e.empty()) throw OutputError(e);
    // memory limit (the grid is stored with --figures), SIGINT/SIGTERM (harness/run/limits.hpp)
    before_run(selected.cases, jobs, limits, o.figures);
    print_shard(selected, o, out);
    note_other_cases_dir(cases_dir, err);
    const json measured = measured_case_costs(sel, cases_dir);
    for (const auto& c : selected.cases) {
        const auto [secs, from_costs] = estimated_seconds(c, measured);
        if (secs < 10.0) continue;
        char line[256];
        std::snprintf(line, sizeof line,
                      "note: case '%s' runs %.3g steps; predicted duration about %.0f s (%s)\n",
                      c.id.c_str(), case_total_steps(c), secs,
                      from_costs ? "its measured run time, case_costs.json"
                                 : "rough estimate, diagnostics and references extra");
        err << line << std::flush;
    }
    // the figure script imports matplotlib while the cases run; it draws when told (figures.hpp)
    std::unique_ptr<EarlyFigureScript> early;
    if (o.figures) early = std::make_unique<EarlyFigureScript>(o.out_dir, jobs, o.figure_format);
    const auto start = std::chrono::system_clock::now();
    json report;
    std::vector<std::string> output_errors; // streaming outputs that failed (limits.hpp)
    {
        ProgressLine progress(!o.quiet && &err == &std::cerr && isatty(STDERR_FILENO) == 1,
                              case_line_printer(o, out));
        RunOptions ro;
        ro.jobs = jobs;
        ro.time_budget = time_budget;
        ro.case_timeout = limits.case_timeout; // limits.hpp
        if (o.figures) // figures hook; a failed write is recorded, not fatal
            ro.series_sink = recording_output_errors(series_file_sink(o.out_dir), output_errors);
        report = run_cases(selected.cases, ro, progress.callback());
    }
    if (!output_errors.empty()) report["output_errors"] = output_errors; // recorded, not fatal
    report["provenance"] = make_provenance(command_line, jobs, start);
    report["provenance"]["cases_dir"] = fs::absolute(cases_dir).lexically_normal().string();
    // what was run, so that merge refuses shards of different selections or overrides; the
    // method files absolute, as a case's file, for a reader in another directory (the
    // cross-check steps their methods)
    std::vector<std::string> method_files;
    for (const auto& f : sel.method_files) method_files.push_back(recorded_case_file(f));
    report["provenance"]["selection"] = {{"targets", sel.targets}, {"suites", sel.suites},
                                         {"filters", sel.filters}, {"problems", sel.problems},
                                         {"methods", sel.methods}, {"method_files", method_files},
                                         {"plugins", sel.plugins}, {"sets", sets}};
    if (selected.shard)
        report["provenance"]["shard"] = {{"index", selected.shard->index},
                                         {"count", selected.shard->count},
                                         {"source", selected.shard->source},
                                         {"selected", selected.all_ids}};
    mark_interrupted(report);
    const int status = exit_status_after_run(finish_report(report, o, true, out, err));
    if (!output_errors.empty()) { // the report is written; the outputs are not
        for (const auto& e : output_errors) err << "dampsym: " << e << "\n";
        return 3;
    }
    if (o.figures && !stop_requested()) {
        // figures hook: draw, then report.md again with the figures; a signal while
        // drawing stops the script and gives 130/143 (make_figures)
        if (const int rc = make_figures(o.out_dir, jobs, o.figure_format, err, early.get());
            rc != 0)
            return rc;
        if (!o.quiet)
            out << "Figures: " << o.out_dir << "/figures/, " << o.out_dir << "/figures.md\n";
    }
    return status;
}

int cmd_merge(const std::string& out_dir, const std::vector<std::string>& inputs, bool allow_mixed,
              const OutputOptions& o, const std::vector<std::string>& command_line,
              std::ostream& out, std::ostream& err) {
    if (out_dir.empty()) throw InputError("OUT_DIR: empty directory name");
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
    const json merged = merge_reports(reports, inputs, prov, allow_mixed);
    OutputOptions mo = o;
    mo.out_dir = out_dir;
    mo.junit = out_dir + "/junit.xml";
    const int status = finish_report(merged, mo, false, out, err);
    if (merged.contains("interrupted")) { // a shard stopped by a signal: the merge is incomplete
        err << "dampsym: merge: a shard was interrupted ("
            << merged["interrupted"].value("signal", "") << "); the merged report is incomplete\n";
        return 1;
    }
    return status;
}

} // namespace

Command add_run_command(CLI::App& app, CliContext& ctx) {
    struct State {
        Selection sel;
        std::vector<std::string> sets;
        OutputOptions oo;
        int jobs = 1;
        double time_budget = RunOptions{}.time_budget;
        CliLimits limits;
    };
    auto s = std::make_shared<State>();
    auto* run =
        app.add_subcommand("run", "run cases (default: the default suite) and write reports");
    run->add_option("cases", s->sel.targets, "case ids or case files (.json)");
    add_selection_options(*run, s->sel);
    run->add_option("--out", s->oo.out_dir,
                    "directory for report.json and report.md (default: reports)");
    CLI::Option* junit = run->add_option("--junit", s->oo.junit,
                                         "also write JUnit XML (one testcase per check) to FILE");
    run->add_option("--jobs,-j", s->jobs, "worker threads (results do not depend on it)")
        ->check(CLI::Range(1, 4096));
    run->add_option("--time-budget", s->time_budget,
                    "seconds of timed repetitions per run of a step ladder (work-precision; "
                    "0 = off; default 0.02)")
        ->check(finite_number())
        ->check(CLI::Range(0.0, 60.0));
    add_limit_options(*run, s->limits); // --case-timeout, --max-memory (harness/run/limits.hpp)
    run->add_option("--set", s->sets, "override a case field, e.g. --set problem.gamma=0.3")
        ->take_all();
    run->add_option("--substitute", s->sel.substitutes,
                    "OLD=NEW: method NEW stands in for OLD in the selected cases and their checks "
                    "(e.g. --methods mine.json --substitute csv1=my-csv1); repeatable")
        ->allow_extra_args(false);
    run->add_option("--annotations", s->oo.annotations,
                    "github: print ::error lines for failing checks")
        ->check(CLI::IsMember({"github"}));
    run->add_flag("--quiet,-q", s->oo.quiet, "only errors and the final totals line");
    run->add_flag("--figures", s->oo.figures,
                  "keep time series (DIR/series/) and draw the figures into DIR/figures/, "
                  "embedded in report.md (docs/reports.md)");
    run->add_option("--figure-format", s->oo.figure_format,
                    "with --figures: png (default), svg or pdf, or a comma list (the first of "
                    "png/svg is embedded in report.md)")
        ->check(figure_format_validator());
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
    return {run, [s, &ctx, junit] {
                s->oo.junit_given = junit->count() > 0;
                return cmd_run(s->sel, s->oo, s->jobs, s->time_budget, s->limits, s->sets,
                               ctx.cases_dir, ctx.command_line, ctx.out, ctx.err);
            }};
}

Command add_merge_command(CLI::App& app, CliContext& ctx) {
    struct State {
        std::string out_dir;
        std::vector<std::string> inputs;
        bool allow_mixed = false;
        OutputOptions oo;
    };
    auto s = std::make_shared<State>();
    auto* merge = app.add_subcommand(
        "merge", "merge shard reports into one report.json, report.md and junit.xml");
    merge->add_option("OUT_DIR", s->out_dir, "directory for the merged reports")->required();
    merge->add_option("IN_DIR", s->inputs, "shard report directories (or report.json files)")
        ->required();
    merge->add_option("--annotations", s->oo.annotations, "github: ::error lines for failures")
        ->check(CLI::IsMember({"github"}));
    merge->add_flag("--quiet,-q", s->oo.quiet, "only errors and the final totals line");
    merge->add_flag("--allow-mixed", s->allow_mixed,
                    "merge reports of different commits, build types, --set overrides or "
                    "selections (refused otherwise); the merged provenance lists the differences "
                    "under \"mixed\"");
    merge->footer("\nExamples:\n  dampsym merge reports shard1 shard2 shard3\n\n"
                  "The merged report's part before \"provenance\" is byte-identical to that of "
                  "the unsharded run.\n\n" +
                  std::string(kExitCodes));
    return {merge, [s, &ctx] {
                return cmd_merge(s->out_dir, s->inputs, s->allow_mixed, s->oo, ctx.command_line,
                                 ctx.out, ctx.err);
            }};
}

} // namespace dampsym::cli_detail
