// dampsym's C++ API (docs/python.md "From your C++ project"): run cases, the method × property
// matrix and the coefficient checks of a method from another program, with the same code, messages
// and results as the command line. Installed by `cmake --install` with the library and
// dampsymConfig.cmake: find_package(dampsym) and link dampsym::dampsym.
//
// Type-erased on purpose: only the standard library here (no Eigen, no JSON library); reports come
// as JSON text in report.json's format (schema/report.schema.json), the matrix and the checks also
// as plain structs.
//
// Methods are registered for the life of the process (a method file's, a plugin's, a Python
// callable's): a second method with a registered id is bad input. Calls may come from several
// threads only after every method they use is loaded.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

struct dampsym_plugin_descriptor; // include/dampsym/plugin.h

namespace dampsym::api {

// Bad input: the command line's exit status 2, with its message (naming the file and the key).
struct InputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};
// An output that could not be written: the command line's exit status 3.
struct OutputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// The library's version and git commit, as `dampsym --version` prints them.
std::string version();

struct Options {
    int jobs = 1;                          // worker threads (results do not depend on it)
    double time_budget = 0.02;             // run --time-budget (work-precision timing; 0 = off)
    bool keep_series = false;              // run --figures' time series (RunResult::series_json)
    std::vector<std::string> method_files; // --methods FILE (docs/method-files.md)
    std::vector<std::string> plugins;      // --plugin LIB (docs/plugins.md)
    std::string cases_dir;                 // --cases ("" = the command line's default)
};

struct RunResult {
    std::string report_json; // report.json's text, provenance and timings included
    std::string series_json; // [each case's series] (docs/reports.md "Series files"), or "[]"
    int exit_status = 0;     // as `dampsym run`: 0 every check passed, 1 one failed
};

// Runs cases, each target a case id (of the cases directory), a case file's path, or a case's
// JSON text (starting with '{'; relative "method_files" are then relative to the working
// directory). The report before "provenance" is the one `dampsym run` writes for the same cases.
RunResult run(const std::vector<std::string>& targets, const Options& options = {});

// One cell of the matrix (docs/matrix.md "matrix.json").
struct MatrixCell {
    std::string property; // e.g. "order", "En-pendulum"
    std::string verdict;  // "holds", "fails" or "n/a"
    std::string role;     // "claimed", "control" or "n/a"
    bool claimed = false;
    bool agrees = true;     // false exactly for the cells that make the exit status 1
    double value = 0.0;     // the measured value; NaN where none or not a number
    std::string value_text; // the value as JSON text ("null", "\"none\"", a number)
};
struct MatrixRow {
    std::string method;
    int order = 0;
    std::vector<MatrixCell> cells;
    // The cell of a property, or nullptr.
    const MatrixCell* cell(std::string_view property) const;
};
struct Matrix {
    std::vector<MatrixRow> rows;
    std::string matrix_json; // matrix.json's text
    std::string report_json; // the battery's report.json text
    int exit_status = 0;     // as `dampsym matrix`
};
// The matrix of the built-in and loaded methods whose ids match one of the globs (all if none).
Matrix matrix(const std::vector<std::string>& method_globs, const Options& options = {});

// Loads a method file's JSON text (docs/method-files.md) with every check of a file; `source`
// names it in messages. Returns the method's id.
std::string load_method(const std::string& json_text, const std::string& source);
// Loads a method file; returns its methods' ids.
std::vector<std::string> load_method_file(const std::string& path);
// Loads a C plugin (docs/plugins.md); returns its methods' ids.
std::vector<std::string> load_plugin(const std::string& path);

// Registers methods given in the plugin ABI (include/dampsym/plugin.h) without a shared library
// (the Python module's callables, or a C++ step of your own): the checks, probe step and kernel of
// `--plugin`; `source` names them in messages and citations. The descriptor and its methods must
// outlive every run. Returns their ids.
std::vector<std::string> register_plugin_methods(const dampsym_plugin_descriptor& descriptor,
                                                 const std::string& source);

// A coefficient-level check (`dampsym methods --check`, src/methods/coefficient_checks.hpp).
struct CoefficientCheck {
    std::string name; // e.g. "order-conditions-4", "symplectic"
    std::string what;
    bool expected = false; // what the declaration (order, claims) implies
    bool holds = false;    // what the coefficients give
    bool agrees = false;   // expected == holds, or a sufficient condition's inconclusive failure
    double value = 0.0;
    double tolerance = 0.0;
};
// The checks of a built-in or loaded method's family (empty: none applies). InputError for an
// unknown id.
std::vector<CoefficientCheck> check_method(const std::string& id);

// The command line in this process: `args` without the program name; returns the exit status.
int cli(const std::vector<std::string>& args, std::string& out, std::string& err);

} // namespace dampsym::api
