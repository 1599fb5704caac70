// Helpers for the in-process command-line tests (test_cli.cpp, test_report.cpp): a temporary
// directory removed on scope exit, case files copied from tests/data, and run_cli with captured
// output.
#pragma once

#include "cli/cli.hpp"
#include "test_paths.hpp"

#include <atomic>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unistd.h>
#include <vector>

namespace dampsym_test {

namespace fs = std::filesystem;

inline const fs::path test_data{test_data_dir()};

// A fresh directory under the system temporary directory, removed with everything in it.
class TempDir {
public:
    TempDir() {
        static std::atomic<int> counter{0};
        std::random_device rd;
        for (int attempt = 0; attempt < 100; ++attempt) {
            const fs::path p = fs::temp_directory_path() /
                               ("dampsym-test-" + std::to_string(::getpid()) + "-" +
                                std::to_string(counter++) + "-" + std::to_string(rd()));
            if (fs::create_directory(p)) {
                path_ = p;
                return;
            }
        }
        throw std::runtime_error("cannot create a temporary directory");
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    const fs::path& path() const { return path_; }
    std::string str() const { return path_.string(); }
    fs::path operator/(const std::string& name) const { return path_ / name; }

private:
    fs::path path_;
};

// Copies tests/data/<relative> into dir and returns the copy's path.
inline fs::path copy_data(const std::string& relative, const fs::path& dir) {
    const fs::path src = test_data / relative;
    const fs::path dst = dir / src.filename();
    fs::copy_file(src, dst, fs::copy_options::overwrite_existing);
    return dst;
}

inline void write_text(const fs::path& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text;
    if (!out) throw std::runtime_error("cannot write " + path.string());
}

inline std::string read_text(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("cannot read " + path.string());
    std::stringstream buf;
    buf << in.rdbuf();
    return buf.str();
}

inline nlohmann::json read_json(const fs::path& path) {
    return nlohmann::json::parse(read_text(path));
}

struct CliResult {
    int status;
    std::string out, err;
};

// Runs dampsym::run_cli in-process; args exclude the program name.
inline CliResult run(std::vector<std::string> args) {
    args.insert(args.begin(), "dampsym");
    std::vector<const char*> argv;
    for (const auto& a : args) argv.push_back(a.c_str());
    argv.push_back(nullptr);
    std::ostringstream out, err;
    const int status = dampsym::run_cli(static_cast<int>(args.size()), argv.data(), out, err);
    return {status, out.str(), err.str()};
}

inline std::string describe(const std::vector<std::string>& args, const CliResult& r) {
    std::string cmd = "dampsym";
    for (const auto& a : args) cmd += " " + a;
    return cmd + "\n  exit " + std::to_string(r.status) + "\n  stdout: " + r.out +
           "\n  stderr: " + r.err;
}

} // namespace dampsym_test
