// The C++ API (include/dampsym/dampsym.hpp): the command line's selection, runner, matrix and
// coefficient checks behind type-erased entry points, each error rethrown as the API's InputError
// or OutputError with the command line's message.
#include "dampsym/dampsym.hpp"

#include "cli/cli.hpp"
#include "cli/cli_detail.hpp"
#include "core/method.hpp"
#include "harness/case/case.hpp"
#include "harness/matrix/matrix.hpp"
#include "harness/report/provenance.hpp"
#include "harness/report/report.hpp"
#include "harness/run/runner.hpp"
#include "harness/user_methods/method_files.hpp"
#include "harness/user_methods/plugins.hpp"
#include "methods/coefficient_checks.hpp"

#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <limits>
#include <mutex>
#include <sstream>

namespace dampsym::api {
namespace {

using json = nlohmann::json;

// Loading methods and parsing cases write the process's method registry; the API's callers may be
// several threads (Python threads, with the GIL released during runs), so these steps take turns.
// The runs themselves go on concurrently (they only read the rows of methods loaded before).
std::mutex& registry_mutex() {
    static std::mutex m;
    return m;
}

// The command line's errors as the API's (same message; the exit status is the type).
template <class F>
auto translated(F&& f) -> decltype(f()) {
    try {
        return f();
    } catch (const dampsym::InputError& e) {
        throw api::InputError(e.what());
    } catch (const dampsym::OutputError& e) {
        throw api::OutputError(e.what());
    }
}

std::string cases_dir_of(const Options& o) {
    return o.cases_dir.empty() ? cli_detail::default_cases_dir() : o.cases_dir;
}

// As `dampsym run`: the methods/ folder beside the cases directory, --methods, then --plugin.
void load_sources(const Options& o) {
    load_method_folder(method_folder_beside(cases_dir_of(o)));
    for (const auto& f : o.method_files) load_method_file(f);
    for (const auto& lib : o.plugins) load_plugin(lib);
}

// The cases of the targets, in their order: JSON texts parsed here (file "<case json>"), ids and
// paths selected as `dampsym run ID|FILE` selects them.
std::vector<CaseSpec> cases_of(const std::vector<std::string>& targets, const Options& o) {
    const std::lock_guard<std::mutex> lock(registry_mutex());
    load_sources(o);
    std::vector<CaseSpec> cases;
    for (const auto& t : targets) {
        if (!t.empty() && t.front() == '{') {
            const std::string source = "<case json>";
            cases.push_back(parse_case(parse_json_checked(t, source), source, {}));
            continue;
        }
        cli_detail::Selection sel;
        sel.targets = {t};
        sel.shard = "none";
        for (auto& c : cli_detail::select_cases(sel, {}, cases_dir_of(o), true, false).cases)
            cases.push_back(std::move(c));
    }
    if (cases.empty()) throw dampsym::InputError("no case given");
    check_unique_ids(cases);
    return cases;
}

std::vector<std::string> ids_of(const std::vector<const MethodInfo*>& rows) {
    std::vector<std::string> out;
    for (const MethodInfo* m : rows) out.emplace_back(m->id);
    return out;
}

double number_or_nan(const json& v) {
    return v.is_number() ? v.get<double>() : std::numeric_limits<double>::quiet_NaN();
}

std::vector<MatrixRow> rows_of(const json& matrix) {
    std::vector<MatrixRow> rows;
    for (const auto& m : matrix["methods"]) {
        MatrixRow row{m["id"].get<std::string>(), m["order"].get<int>(), {}};
        for (const auto& [property, c] : m["cells"].items()) {
            MatrixCell cell;
            cell.property = property;
            cell.verdict = c.value("verdict", "");
            cell.role = c.value("role", "");
            cell.claimed = c.value("claimed", false);
            cell.agrees = c.value("agrees", true);
            const json value = c.contains("value") ? c["value"] : json();
            cell.value = number_or_nan(value);
            cell.value_text = value.dump();
            row.cells.push_back(std::move(cell));
        }
        rows.push_back(std::move(row));
    }
    return rows;
}

// The SIGINT/SIGTERM dispositions of the caller, restored when the command line returns (it
// installs its own stop handlers for the run; a host such as Python keeps its own).
class KeepStopSignals {
public:
    KeepStopSignals() {
        sigaction(SIGINT, nullptr, &int_);
        sigaction(SIGTERM, nullptr, &term_);
    }
    ~KeepStopSignals() {
        sigaction(SIGINT, &int_, nullptr);
        sigaction(SIGTERM, &term_, nullptr);
    }
    KeepStopSignals(const KeepStopSignals&) = delete;
    KeepStopSignals& operator=(const KeepStopSignals&) = delete;

private:
    struct sigaction int_ {
    }, term_{};
};

} // namespace

std::string version() {
    return version_string();
}

RunResult run(const std::vector<std::string>& targets, const Options& options) {
    return translated([&] {
        const std::vector<CaseSpec> cases = cases_of(targets, options);
        const auto start = std::chrono::system_clock::now();
        json series = json::array();
        std::mutex series_mutex;
        dampsym::RunOptions ro;
        ro.jobs = options.jobs;
        ro.time_budget = options.time_budget;
        if (options.keep_series)
            ro.series_sink = [&](const json& s) {
                const std::lock_guard<std::mutex> lock(series_mutex);
                series.push_back(s);
            };
        json report = run_cases(cases, ro);
        std::vector<std::string> command_line = {"dampsym.api.run"};
        for (const auto& t : targets)
            command_line.push_back(!t.empty() && t.front() == '{' ? "<case json>" : t);
        report["provenance"] = make_provenance(command_line, options.jobs, start);
        report["provenance"]["cases_dir"] =
            std::filesystem::absolute(cases_dir_of(options)).lexically_normal().string();
        RunResult r;
        r.report_json = report_json_text(report);
        r.series_json = series.dump();
        r.exit_status = report["summary"]["checks_failed"].get<std::int64_t>() == 0 ? 0 : 1;
        return r;
    });
}

const MatrixCell* MatrixRow::cell(std::string_view property) const {
    for (const auto& c : cells)
        if (c.property == property) return &c;
    return nullptr;
}

Matrix matrix(const std::vector<std::string>& method_globs, const Options& options) {
    return translated([&] {
        std::vector<const MethodInfo*> methods;
        std::vector<CaseSpec> battery;
        {
            const std::lock_guard<std::mutex> lock(registry_mutex());
            load_sources(options);
            methods = matrix_methods(method_globs);
            if (methods.empty())
                throw dampsym::InputError(
                    "--method: no built-in or loaded method matches the given glob(s)");
            battery = matrix_battery(methods);
        }
        const auto start = std::chrono::system_clock::now();
        dampsym::RunOptions ro;
        ro.jobs = options.jobs;
        ro.time_budget = 0.0; // as `dampsym matrix`: the matrix reads no timing
        json report = run_cases(battery, ro);
        std::vector<std::string> command_line = {"dampsym.api.matrix"};
        command_line.insert(command_line.end(), method_globs.begin(), method_globs.end());
        report["provenance"] = make_provenance(command_line, options.jobs, start);
        json m = judge_matrix(methods, report);
        m["provenance"] = report["provenance"];
        Matrix out;
        out.rows = rows_of(m);
        out.matrix_json = m.dump(2) + "\n";
        out.report_json = report_json_text(report);
        out.exit_status = matrix_exit_status(m);
        return out;
    });
}

std::string load_method(const std::string& json_text, const std::string& source) {
    return translated([&] {
        const std::lock_guard<std::mutex> lock(registry_mutex());
        return std::string(load_method_text(json_text, source).at(0)->id);
    });
}

std::vector<std::string> load_method_file(const std::string& path) {
    return translated([&] {
        const std::lock_guard<std::mutex> lock(registry_mutex());
        return ids_of(dampsym::load_method_file(path));
    });
}

std::vector<std::string> load_plugin(const std::string& path) {
    return translated([&] {
        const std::lock_guard<std::mutex> lock(registry_mutex());
        return ids_of(dampsym::load_plugin(path));
    });
}

std::vector<std::string> register_plugin_methods(const dampsym_plugin_descriptor& descriptor,
                                                 const std::string& source) {
    return translated([&] {
        const std::lock_guard<std::mutex> lock(registry_mutex());
        return ids_of(dampsym::register_plugin_methods(source, descriptor));
    });
}

std::vector<CoefficientCheck> check_method(const std::string& id) {
    const MethodInfo* m = find_method(id);
    if (!m)
        throw api::InputError("unknown method '" + brief(id) + "' (dampsym methods lists them)");
    std::vector<CoefficientCheck> out;
    for (const auto& c : method_checks(*m))
        out.push_back(CoefficientCheck{c.name, c.what, c.expected, c.holds, c.agrees(), c.value,
                                       c.tolerance});
    return out;
}

int cli(const std::vector<std::string>& args, std::string& out, std::string& err) {
    std::vector<const char*> argv = {"dampsym"};
    for (const auto& a : args) argv.push_back(a.c_str());
    std::ostringstream o, e;
    int status = 0;
    {
        const KeepStopSignals keep;
        status = run_cli(static_cast<int>(argv.size()), argv.data(), o, e);
    }
    out = o.str();
    err = e.str();
    return status;
}

} // namespace dampsym::api
