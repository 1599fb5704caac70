#pragma once
// The case file as report.json records it (a case's "file"): absolute, so that a reader in
// another directory finds the file dampsym read (the cross-check takes every input from it,
// verify/xcase.py); the directory dampsym ran in is recorded nowhere else. A name that is not a
// file (a case given as JSON by the C++ or Python API: "<case json>") stays as it is.

#include <filesystem>
#include <string>
#include <system_error>

namespace dampsym {

inline std::string recorded_case_file(const std::string& file) {
    std::error_code ec;
    if (file.empty() || !std::filesystem::is_regular_file(file, ec)) return file;
    const std::filesystem::path p = std::filesystem::absolute(file, ec);
    return ec ? file : p.lexically_normal().string();
}

} // namespace dampsym
