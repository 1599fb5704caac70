// Provenance of a report: what was built (version, git commit and whether the tree was dirty at
// build time, compiler, flags, build type, library versions) and where and how it ran (OS, CPU,
// start time in UTC, command line, --jobs, shard). It varies between runs of the same build, so
// it lives in report.json's "provenance" section, outside the byte-stable part.
#pragma once

#include <chrono>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace dampsym {

struct BuildInfo {
    std::string git_commit; // "unknown" outside a git checkout
    std::string git_dirty;  // "true", "false" or "unknown"
    std::string compiler;   // CMake's compiler id and version
    std::string flags;      // CMAKE_CXX_FLAGS and the build type's flags
    std::string build_type;
    std::string options; // DAMPSYM_* build options (sanitizers, -Werror)
};

// Generated at build time (cmake/build_info.cmake).
const BuildInfo& build_info();

// "dampsym 0.1.0 (git 1a2b3c4d5e6f, dirty)".
std::string version_string();

// The source tree this binary was built from (the default cases directory and the figure
// scripts live there).
std::string source_dir();

// The provenance section: build, libraries, host, start time (UTC), command line and jobs.
nlohmann::json make_provenance(const std::vector<std::string>& command_line, int jobs,
                               std::chrono::system_clock::time_point start);

// ISO 8601 UTC, e.g. "2026-11-23T12:34:56Z".
std::string utc_iso8601(std::chrono::system_clock::time_point t);

} // namespace dampsym
