#pragma once
// The case file as report.json records it (a case's "file"): absolute, so that a reader in
// another directory finds the file dampsym read (the cross-check takes every input from it,
// verify/xcase.py); the directory dampsym ran in is recorded nowhere else.

#include <filesystem>
#include <string>
#include <system_error>

namespace dampsym {

inline std::string recorded_case_file(const std::string& file) {
    if (file.empty()) return file;
    std::error_code ec;
    const std::filesystem::path p = std::filesystem::absolute(file, ec);
    return ec ? file : p.lexically_normal().string();
}

} // namespace dampsym
