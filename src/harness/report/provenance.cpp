#include "harness/report/provenance.hpp"

#include <CLI/Version.hpp>
#include <Eigen/Core>
#include <ctime>
#include <fstream>
#include <gsl/gsl_version.h>
#include <sstream>
#include <sys/utsname.h>
#include <thread>
#include <unistd.h>

namespace dampsym {
namespace {

using json = nlohmann::json;

// The value of "key : value" in /proc/cpuinfo (first processor), or "" if absent.
std::string cpuinfo(const std::string& key) {
    std::ifstream in("/proc/cpuinfo");
    for (std::string line; std::getline(in, line);) {
        if (line.rfind(key, 0) != 0) continue;
        const auto colon = line.find(':');
        if (colon == std::string::npos) continue;
        const auto start = line.find_first_not_of(" \t", colon + 1);
        return start == std::string::npos ? "" : line.substr(start);
    }
    return "";
}

// PRETTY_NAME from /etc/os-release, without quotes, or "" if absent.
std::string os_release() {
    std::ifstream in("/etc/os-release");
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("PRETTY_NAME=", 0) != 0) continue;
        std::string v = line.substr(12);
        if (v.size() >= 2 && (v.front() == '"' || v.front() == '\'')) v = v.substr(1, v.size() - 2);
        return v;
    }
    return "";
}

// Joins arguments into one shell-readable line (arguments with special characters quoted).
std::string shell_join(const std::vector<std::string>& args) {
    std::string out;
    for (const auto& a : args) {
        if (!out.empty()) out += ' ';
        const bool plain =
            !a.empty() && a.find_first_not_of("abcdefghijklmnopqrstuvwxyz"
                                              "ABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                              "0123456789-_./=:,+@%") == std::string::npos;
        if (plain) {
            out += a;
            continue;
        }
        out += '\'';
        for (char c : a) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
        out += '\'';
    }
    return out;
}

json build_json() {
    const BuildInfo& b = build_info();
    json dirty = b.git_dirty == "true" ? json(true) : b.git_dirty == "false" ? json(false) : json();
    return {{"git_commit", b.git_commit},
            {"git_dirty", dirty},
            {"compiler", b.compiler},
            {"compiler_version_macro", __VERSION__},
            {"flags", b.flags},
            {"build_type", b.build_type},
            {"options", b.options},
            {"libraries",
             {{"eigen", std::to_string(EIGEN_WORLD_VERSION) + "." +
                            std::to_string(EIGEN_MAJOR_VERSION) + "." +
                            std::to_string(EIGEN_MINOR_VERSION)},
              {"gsl", GSL_VERSION},
              {"nlohmann_json", std::to_string(NLOHMANN_JSON_VERSION_MAJOR) + "." +
                                    std::to_string(NLOHMANN_JSON_VERSION_MINOR) + "." +
                                    std::to_string(NLOHMANN_JSON_VERSION_PATCH)},
              {"cli11", CLI11_VERSION}}}};
}

} // namespace

std::string version_string() {
    const BuildInfo& b = build_info();
    std::string s = std::string("dampsym ") + DAMPSYM_VERSION;
    if (b.git_commit != "unknown") {
        s += " (git " + b.git_commit.substr(0, 12);
        if (b.git_dirty == "true") s += ", dirty";
        s += ")";
    }
    return s;
}

std::string utc_iso8601(std::chrono::system_clock::time_point t) {
    const std::time_t tt = std::chrono::system_clock::to_time_t(t);
    std::tm tm{};
    gmtime_r(&tt, &tm);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
    return buf;
}

json make_provenance(const std::vector<std::string>& command_line, int jobs,
                     std::chrono::system_clock::time_point start) {
    struct utsname u {};
    json os = json::object();
    if (uname(&u) == 0)
        os = {{"sysname", u.sysname}, {"release", u.release}, {"machine", u.machine}};
    os["name"] = os_release();
    char hostname[256] = "";
    if (gethostname(hostname, sizeof hostname) != 0) hostname[0] = '\0';
    hostname[sizeof hostname - 1] = '\0';
    std::string cpu = cpuinfo("model name");
    if (cpu.empty()) cpu = cpuinfo("Model"); // some ARM kernels
    return {{"version", DAMPSYM_VERSION},
            {"build", build_json()},
            {"host",
             {{"os", os},
              {"hostname", hostname},
              {"cpu_model", cpu},
              {"cpu_count", std::thread::hardware_concurrency()}}},
            {"start_utc", utc_iso8601(start)},
            {"command_line", shell_join(command_line)},
            {"jobs", jobs}};
}

} // namespace dampsym
