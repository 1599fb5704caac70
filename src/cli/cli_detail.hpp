// Internals of the dampsym command line shared by its files: cli.cpp (run_cli: global options,
// parsing, dispatch; the plot command), cli_run.cpp (run, merge), cli_compare.cpp (compare),
// cli_list.cpp (list, methods), cli_select.cpp (case selection), cli_github.cpp (GitHub
// annotations and step summary). Adding a subcommand = one add_*_command function in its own file
// and one line in run_cli.
#pragma once

#include "harness/case/case.hpp"
#include "harness/ci/shard.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace dampsym::cli_detail {

using json = nlohmann::json;

std::string default_cases_dir();

// What to run (or list): case ids or files, or the cases of the cases directory restricted by
// suite, id glob, problem and method; then, for run, one shard of that selection.
struct Selection {
    std::vector<std::string> targets, filters, suites, methods, problems;
    std::string shard; // "K/N", "none", or "" (read the CI engines' variables)
    std::string costs; // measured case costs for sharding ("" = next to the cases directory)
    std::vector<std::string> method_files; // --methods (harness/user_methods/method_files.hpp)
    std::vector<std::string> plugins;      // --plugin (harness/user_methods/plugins.hpp)
    std::vector<std::string> substitutes;  // run --substitute OLD=NEW (docs/case-keys.md)
};

struct Selected {
    std::vector<CaseSpec> cases;      // this shard's
    std::vector<std::string> all_ids; // the whole selection, in order
    std::optional<ShardSpec> shard;
};

std::string describe_selection(const Selection& sel, bool default_suite);

// `default_suite`: the run command's default ("default" when neither a case nor --suite is
// given); list shows every case.
Selected select_cases(const Selection& sel, const std::vector<std::string>& sets,
                      const std::string& cases_dir, bool default_suite, bool sharding);

// The measured seconds per case id ({ID: seconds}): --costs, else case_costs.json beside the
// cases directory (verify/case_costs.json, ci/case_costs.sh), else none. InputError if --costs
// names a missing file or either is malformed.
nlohmann::json measured_case_costs(const Selection& sel, const std::string& cases_dir);

// The --suite, --filter, --problem, --method, --shard and --costs options of list and run.
void add_selection_options(CLI::App& sub, Selection& sel);

// --figure-format's check (harness/figures/figures.hpp figure_formats_error), for run and plot.
CLI::Validator figure_format_validator();

// What every subcommand sees: the global options (bound before parsing, read by the actions
// after it) and the output streams.
struct CliContext {
    std::string cases_dir;                 // --cases
    std::vector<std::string> command_line; // argv, for the report's provenance
    std::ostream& out;
    std::ostream& err;
};

// A subcommand: its CLI11 app, whose options are bound to state the action owns, and the action
// (run after a successful parse when this subcommand was given), which returns the exit status.
struct Command {
    CLI::App* app;
    std::function<int()> action;
};

extern const char* const kExitCodes; // the exit-status paragraph of the help texts

Command add_list_command(CLI::App& app, CliContext& ctx);    // cli_list.cpp
Command add_methods_command(CLI::App& app, CliContext& ctx); // cli_list.cpp
Command add_run_command(CLI::App& app, CliContext& ctx);     // cli_run.cpp
Command add_merge_command(CLI::App& app, CliContext& ctx);   // cli_run.cpp
Command add_compare_command(CLI::App& app, CliContext& ctx); // cli_compare.cpp
Command add_matrix_command(CLI::App& app, CliContext& ctx);  // cli_matrix.cpp

// A report.json (or the report.json in a directory); InputError if unreadable or not JSON.
json read_report(const std::string& arg);

void github_annotations(const json& report, std::ostream& out);
void github_step_summary(const json& report, std::ostream& err);

} // namespace dampsym::cli_detail
