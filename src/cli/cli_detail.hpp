// Internals of the dampsym command line shared by its files (cli.cpp: run_cli and the run,
// compare and merge commands; cli_select.cpp: case selection; cli_list.cpp: list and methods;
// cli_github.cpp: GitHub annotations and step summary).
#pragma once

#include "harness/case.hpp"
#include "harness/shard.hpp"

#include <nlohmann/json.hpp>

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

int cmd_list(bool as_json, const Selection& sel, const std::string& cases_dir, std::ostream& out);
int cmd_methods(bool check, bool as_json, std::ostream& out);

void github_annotations(const json& report, std::ostream& out);
void github_step_summary(const json& report, std::ostream& err);

} // namespace dampsym::cli_detail
