// The dampsym command line: global options, parsing and dispatch to the subcommands (each in
// its own file, see cli/cli_detail.hpp), and the plot command.
#include "cli/cli.hpp"

#include "cli/cli_detail.hpp"

#include "harness/case/case.hpp"
#include "harness/figures/figures.hpp"
#include "harness/report/provenance.hpp"
#include "harness/report/report.hpp"
#include "harness/run/limits.hpp"
#include "harness/suggest.hpp"

#include <CLI/CLI.hpp>
#include <memory>
#include <ostream>

namespace dampsym {

namespace cli_detail {

const char* const kExitCodes =
    "Exit status: 0 all checks passed (compare: nothing moved), 1 a check "
    "failed (compare: something moved), 2 bad input or usage (one line naming "
    "the file and key; also a case above --max-memory), 3 internal or I/O "
    "error (e.g. an unwritable --out), 130/143 stopped by SIGINT/SIGTERM "
    "(report of what finished written, marked interrupted).";

void add_selection_options(CLI::App& sub, Selection& sel) {
    sub.add_option("--suite", sel.suites,
                   "suite(s) to take cases from; repeatable; 'all' = every case")
        ->allow_extra_args(false);
    sub.add_option("--filter", sel.filters, "glob on case ids (repeatable: any may match)")
        ->allow_extra_args(false);
    sub.add_option("--problem", sel.problems, "glob on problem ids (repeatable)")
        ->allow_extra_args(false);
    sub.add_option("--method", sel.methods,
                   "glob on method ids (repeatable): only these runs and their checks")
        ->allow_extra_args(false);
    sub.add_option("--shard", sel.shard,
                   "K/N: run share K of N (cost-balanced); 'none' ignores TEST_TOTAL_SHARDS, "
                   "CI_NODE_TOTAL and SLURM_ARRAY_TASK_COUNT");
    sub.add_option("--costs", sel.costs,
                   "measured case costs for --shard (default: case_costs.json beside the "
                   "cases directory)");
    // method files (harness/user_methods/method_files.hpp), loaded by select_cases.
    sub.add_option("--methods", sel.method_files,
                   "method file(s) (.json, docs/method-files.md) to load before the cases; "
                   "repeatable")
        ->allow_extra_args(false);
    sub.add_option("--plugin", sel.plugins,
                   "C plugin library (.so, docs/plugins.md) whose methods the cases may name; "
                   "repeatable")
        ->allow_extra_args(false);
}

} // namespace cli_detail

CLI::Validator cli_detail::figure_format_validator() {
    return CLI::Validator([](std::string& v) { return figure_formats_error(v); },
                          "png|svg|pdf[,...]");
}

namespace {

using namespace cli_detail;

// `dampsym plot REPORT_DIR` (harness/figures/figures.hpp): the figures of an existing report.
Command add_plot_command(CLI::App& app, CliContext& ctx) {
    struct State {
        std::string dir;
        int jobs = 2;
        std::string format = "png";
    };
    auto s = std::make_shared<State>();
    auto* plot = app.add_subcommand(
        "plot", "draw the figures of a report directory (REPORT_DIR/figures/, report.md, "
                "figures.md); time series only if it was run with --figures");
    plot->add_option("REPORT_DIR", s->dir, "directory holding report.json")->required();
    plot->add_option("--jobs,-j", s->jobs, "figure processes")->check(CLI::Range(1, 256));
    plot->add_option("--figure-format", s->format,
                     "png (default), svg or pdf, or a comma list (the first of png/svg is "
                     "embedded in report.md)")
        ->check(figure_format_validator());
    return {plot, [s, &ctx] {
                install_stop_handlers(); // SIGINT/SIGTERM stop the script too: 130/143
                return make_figures(s->dir, s->jobs, s->format, ctx.err);
            }};
}

// A parse error: for `dampsym frobnicate` CLI11 says "A subcommand is required"; name the word.
template <std::size_t N>
int parse_error(const Command (&commands)[N], const CLI::ParseError& e, int argc,
                const char* const* argv, std::ostream& err) {
    std::string known;
    for (const auto& c : commands) known += (known.empty() ? "" : ", ") + c.app->get_name();
    const auto is_command = [&](const std::string& a) {
        for (const auto& c : commands)
            if (c.app->check_name(a)) return true;
        return false;
    };
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--cases") {
            ++i;
            continue;
        }
        if (a.empty() || a[0] == '-') continue;
        if (!is_command(a)) {
            std::vector<std::string> names;
            for (const auto& c : commands) names.push_back(c.app->get_name());
            const std::string hint = did_you_mean(a, names);
            err << "dampsym: unknown subcommand '" << brief(a) << "'"
                << (hint.empty() ? "" : "; " + hint) << " (known: " << known
                << "; dampsym --help)\n";
            return 2;
        }
        break;
    }
    err << "dampsym: " << e.what() << "\n";
    return 2;
}

} // namespace

int run_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
    // `dampsym help [COMMAND]`, as git and pip have it: the same as `dampsym [COMMAND] --help`
    if (argc >= 2 && argc <= 3 && std::string(argv[1]) == "help") {
        std::vector<const char*> args{argv[0]};
        if (argc == 3) args.push_back(argv[2]);
        args.push_back("--help");
        return run_cli(static_cast<int>(args.size()), args.data(), out, err);
    }
    CliContext ctx{default_cases_dir(), std::vector<std::string>(argv, argv + argc), out, err};
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
    app.add_option(
        "--cases", ctx.cases_dir,
        "directory of case files (default: $DAMPSYM_CASES, else " + source_dir() +
            "/verify/cases, the verify/cases of the source tree this binary was built from; the "
            "report's provenance names the directory used)");
    const Command commands[] = {
        add_list_command(app, ctx),    add_run_command(app, ctx),   add_plot_command(app, ctx),
        add_compare_command(app, ctx), add_merge_command(app, ctx), add_methods_command(app, ctx),
        add_matrix_command(app, ctx), // dampsym matrix (cli_matrix.cpp)
    };
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
        return parse_error(commands, e, argc, argv, err);
    }
    try {
        for (const auto& c : commands)
            if (*c.app) return c.action();
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
