// Method files (docs/method-files.md): JSON method definitions loaded at run time, for
// every family whose method is data — RK (explicit or implicit, optionally under the integrating
// factor B(2.5)), partitioned RK, exponential RK B(2.7) and partitioned exponential RK B(2.14) with
// coefficient functions built from a fixed φ-function vocabulary, and general linear methods with
// their starting method. A loaded method becomes a MethodInfo row (src/methods/runtime_methods.hpp)
// that find_method returns after the built-in catalog, so the runner, the kernels chosen by
// std::visit (src/harness/registry.hpp) and every diagnostic treat it like a built-in row.
//
// Sources: `dampsym run|methods --methods FILE`, a case's "method_files" (paths relative to the
// case file) and every *.json of a `methods/` folder beside the cases directory. A file is loaded
// once per process (by canonical path); loading it again is a no-op.
//
// Every error is an InputError "FILE: KEY: what" (exit 2); nothing of a bad file is registered.
#pragma once

#include "core/method.hpp"
#include "methods/coefficient_checks.hpp"

#include <string>
#include <string_view>
#include <vector>

namespace dampsym {

// Loads every method of the file (throws InputError naming the file and the key) and returns
// them (also when the file was loaded before).
std::vector<const MethodInfo*> load_method_file(const std::string& path);
// Validates a method file's text exactly as load_method_file validates a file's contents (the JSON
// limits of parse_json_checked, keys, coefficients and their expressions, claims, the id neither
// built in nor loaded already) without registering anything; returns the method's id. Throws
// InputError naming `file` and the key. For the fuzz target tests/fuzz/fuzz_method.cpp: fuzzing
// load_method_file would register every valid input, so the registry would grow without bound
// and later inputs with a registered id would stop at the duplicate-id check.
std::string check_method_text(const std::string& text, const std::string& file);
// Loads a method file's text (the Python module's Tableau, src/api/) with every check of
// load_method_file; `source` stands for the file in messages and in method_file_of.
std::vector<const MethodInfo*> load_method_text(const std::string& text, const std::string& source);
// Loads every *.json file of `dir` in name order; a missing directory loads nothing.
void load_method_folder(const std::string& dir);
// The file a loaded method came from ("" for a built-in or unknown id).
std::string method_file_of(std::string_view id);
// Registers a row defined elsewhere (a C plugin's method, harness/user_methods/plugins.hpp) like a
// method file's: its id and citation are copied into stable storage and `source` is reported as its
// file. The caller has checked that the id is neither built in nor loaded (file_defining).
const MethodInfo* register_runtime_method(const MethodInfo& row, const std::string& source);
// The file (or plugin library) that defines a loaded id, "" if none.
std::string loaded_method_source(std::string_view id);
// The `methods/` folder beside a cases directory (verify/cases -> verify/methods).
std::string method_folder_beside(const std::string& cases_dir);

} // namespace dampsym
