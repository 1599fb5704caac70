// `dampsym compare BASE NEW`: final states, metrics, order fits and check verdicts of two
// reports (harness/report/compare.hpp).
#include "cli/cli_detail.hpp"

#include "harness/bounded_read.hpp"
#include "harness/case/case.hpp"
#include "harness/finite_option.hpp"
#include "harness/report/compare.hpp"

#include <filesystem>

namespace dampsym::cli_detail {

namespace fs = std::filesystem;

json read_report(const std::string& arg) {
    const fs::path p = fs::is_directory(arg) ? fs::path(arg) / "report.json" : fs::path(arg);
    // regular files of at most kMaxReportBytes only: a FIFO would hang, /dev/zero never end
    const json j =
        json::parse(read_regular_file(p.string(), kMaxReportBytes, "report"), nullptr, false);
    if (j.is_discarded())
        throw InputError("report " + quote_for_message(p.string()) + ": malformed JSON");
    return j;
}

namespace {

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

} // namespace

Command add_compare_command(CLI::App& app, CliContext& ctx) {
    struct State {
        std::string base, next;
        CompareOptions opt;
        bool as_json = false;
    };
    auto s = std::make_shared<State>();
    auto* compare = app.add_subcommand(
        "compare", "compare two reports: final states, metrics, order fits, check verdicts");
    compare->add_option("BASE", s->base, "base report.json (or its directory)")->required();
    compare->add_option("NEW", s->next, "new report.json (or its directory)")->required();
    compare->add_option("--rtol", s->opt.rtol, "relative tolerance (default 0: bitwise)")
        ->check(finite_number())
        ->check(CLI::NonNegativeNumber);
    compare->add_option("--atol", s->opt.atol, "absolute tolerance (default 0)")
        ->check(finite_number())
        ->check(CLI::NonNegativeNumber);
    compare->add_flag("--ignore-timings", s->opt.ignore_timings,
                      "omit the (information-only) wall-time table");
    compare->add_flag("--json", s->as_json, "JSON instead of Markdown");
    compare->footer("\nExamples:\n  dampsym compare base/report.json reports/report.json\n"
                    "  dampsym compare base reports --rtol 1e-12 --json > diff.json\n\n"
                    "Exit status: 0 nothing moved, 1 something moved (rows listed), 2 bad input.");
    return {compare,
            [s, &ctx] { return cmd_compare(s->base, s->next, s->opt, s->as_json, ctx.out); }};
}

} // namespace dampsym::cli_detail
