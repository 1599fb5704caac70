// `dampsym matrix` (docs/matrix.md): the method × property matrix of every
// built-in and loaded method, written as DIR/matrix.md and DIR/matrix.json beside the battery's
// ordinary report (DIR/report.json, DIR/report.md).
#include "cli/cli_detail.hpp"

#include "harness/matrix/matrix.hpp"
#include "harness/report/provenance.hpp"
#include "harness/report/report.hpp"
#include "harness/run/limits.hpp"
#include "harness/run/runner.hpp"
#include "harness/user_methods/method_files.hpp"
#include "harness/user_methods/plugins.hpp"

#include <chrono>
#include <memory>

namespace dampsym::cli_detail {
namespace {

struct MatrixArgs {
    std::vector<std::string> method_files; // --methods
    std::vector<std::string> plugins;      // --plugin
    std::vector<std::string> globs;        // --method
    std::string out_dir = "matrix";
    int jobs = 1;
    bool quiet = false;
};

int cmd_matrix(const MatrixArgs& a, const std::string& cases_dir,
               const std::vector<std::string>& command_line, std::ostream& out, std::ostream& err) {
    if (a.out_dir.empty()) throw InputError("--out: empty directory name"); // as run: exit 2
    // as `dampsym run`: the methods/ folder beside the cases directory, then --methods files
    load_method_folder(method_folder_beside(cases_dir));
    for (const auto& f : a.method_files) load_method_file(f); // InputError: exit 2
    // Plugins (`--plugin LIB`) load after the method files: their rows join the
    // same runtime catalog (methods/runtime_methods.hpp), which matrix_methods reads.
    for (const auto& lib : a.plugins) load_plugin(lib); // InputError: exit 2
    const auto methods = matrix_methods(a.globs);
    if (methods.empty())
        throw InputError("--method: no built-in or loaded method matches the given glob(s)");
    check_output_dir(a.out_dir);
    const auto start = std::chrono::system_clock::now();
    const auto cases = matrix_battery(methods);
    RunOptions ro;
    ro.jobs = a.jobs;
    ro.time_budget = 0.0; // no work-precision timing: the matrix reads no timing
    json report = run_cases(cases, ro);
    report["provenance"] = make_provenance(command_line, a.jobs, start);
    write_reports(report, a.out_dir);
    json matrix = judge_matrix(methods, report);
    matrix["provenance"] = report["provenance"];
    const std::string md = render_matrix_markdown(matrix);
    write_file_atomic(a.out_dir + "/matrix.json", matrix.dump(2) + "\n");
    write_file_atomic(a.out_dir + "/matrix.md", "# dampsym method × property matrix\n\n" + md);
    if (!a.quiet) out << md;
    const double secs =
        std::chrono::duration<double>(std::chrono::system_clock::now() - start).count();
    char line[160];
    std::snprintf(line, sizeof line, "%zu methods, %zu battery cases, %.1f s\n", methods.size(),
                  cases.size(), secs);
    out << line << "Matrix: " << a.out_dir << "/matrix.md, " << a.out_dir
        << "/matrix.json (battery report: " << a.out_dir << "/report.json)\n";
    const int status = matrix_exit_status(matrix);
    if (status != 0)
        err << "dampsym matrix: a claimed property fails or a negative control passes where it "
               "must fail (see the marked cells)\n";
    return status;
}

} // namespace

Command add_matrix_command(CLI::App& app, CliContext& ctx) {
    auto a = std::make_shared<MatrixArgs>();
    auto* sub = app.add_subcommand(
        "matrix", "method x property matrix: a fixed battery (order, E_n, conformal laws, "
                  "d(t) drift, stability threshold) for every built-in and loaded method "
                  "(docs/matrix.md)");
    sub->add_option("--methods", a->method_files,
                    "method file(s) (.json, docs/method-files.md) whose methods join the matrix; "
                    "repeatable")
        ->allow_extra_args(false);
    sub->add_option("--plugin", a->plugins,
                    "C plugin library (.so, docs/plugins.md) whose methods join the matrix; "
                    "repeatable")
        ->allow_extra_args(false);
    sub->add_option("--method", a->globs, "glob on method ids (repeatable): only these rows")
        ->allow_extra_args(false);
    sub->add_option("--out", a->out_dir,
                    "directory for matrix.md, matrix.json and the battery's report.json, "
                    "report.md (default: matrix)");
    sub->add_option("--jobs,-j", a->jobs, "worker threads (results do not depend on it)")
        ->check(CLI::Range(1, 4096));
    sub->add_flag("--quiet,-q", a->quiet, "do not print the table");
    sub->footer("\nExamples:\n"
                "  dampsym matrix --jobs 2 --out matrix          every built-in method\n"
                "  dampsym matrix --methods my-method.json --method 'my-*' --method csv1\n\n"
                "Exit status: 0 every claimed property holds and no negative control that must "
                "fail passes, 1 otherwise, 2 bad input or usage, 3 internal or I/O error.");
    return {sub, [a, &ctx] {
                return cmd_matrix(*a, ctx.cases_dir, ctx.command_line, ctx.out, ctx.err);
            }};
}

} // namespace dampsym::cli_detail
