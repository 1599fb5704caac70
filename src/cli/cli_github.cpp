#include "cli/cli_detail.hpp"

#include "harness/bounded_read.hpp"
#include "harness/case/case.hpp"
#include "harness/ci/junit.hpp"
#include "harness/ci/shard.hpp"
#include "harness/problem_info.hpp"
#include "harness/report/compare.hpp"
#include "harness/report/markdown.hpp"
#include "harness/report/provenance.hpp"
#include "harness/report/report.hpp"
#include "harness/run/progress.hpp"
#include "harness/run/runner.hpp"
#include "methods/coefficient_checks.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fnmatch.h>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <optional>
#include <ostream>
#include <sstream>
#include <thread>
#include <unistd.h>

namespace dampsym::cli_detail {

namespace fs = std::filesystem;

// GitHub workflow-command escaping (data; properties also escape ':' and ',').
std::string gh_escape(const std::string& s, bool property) {
    std::string out;
    for (char c : s) {
        if (c == '%')
            out += "%25";
        else if (c == '\r')
            out += "%0D";
        else if (c == '\n')
            out += "%0A";
        else if (property && c == ':')
            out += "%3A";
        else if (property && c == ',')
            out += "%2C";
        else
            out += c;
    }
    return out;
}

// The case file relative to the working directory (the repository root in a workflow).
std::string relative_file(const std::string& file) {
    std::error_code ec;
    const fs::path rel = fs::relative(fs::absolute(file, ec), fs::current_path(ec), ec);
    if (ec || rel.empty() || rel.string().rfind("..", 0) == 0) return file;
    return rel.string();
}

std::string check_text(const json& ck) {
    std::ostringstream os;
    os << ck["metric"].get<std::string>() << " = "
       << (ck["value"].is_null() ? std::string("null") : ck["value"].dump()) << ", expected "
       << ck["op"].get<std::string>() << " " << ck["expected"].dump();
    if (ck.contains("tolerance")) os << " (tol " << ck["tolerance"].dump() << ")";
    if (ck.contains("message")) os << ": " << ck["message"].get<std::string>();
    return os.str();
}

void github_annotations(const json& report, std::ostream& out) {
    for (const auto& c : report["cases"])
        for (const auto& ck : c["checks"]) {
            if (ck["passed"].get<bool>()) continue;
            out << "::error file=" << gh_escape(relative_file(c.value("file", std::string())), true)
                << ",title="
                << gh_escape("dampsym " + c["id"].get<std::string>() + ": " + junit_test_name(ck),
                             true)
                << "::" << gh_escape(check_text(ck), false) << "\n";
        }
}

// Appends totals and failing checks (at most 50) to $GITHUB_STEP_SUMMARY, never the whole report.
void github_step_summary(const json& report, std::ostream& err) {
    const char* path = std::getenv("GITHUB_STEP_SUMMARY");
    if (!path || !*path) return;
    std::ostringstream os;
    const json& s = report["summary"];
    os << "### dampsym: " << (s["checks_failed"].get<std::int64_t>() == 0 ? "passed" : "FAILED")
       << "\n\n"
       << render_totals(report) << "\n";
    int shown = 0, failing = 0;
    for (const auto& c : report["cases"])
        for (const auto& ck : c["checks"]) {
            if (ck["passed"].get<bool>()) continue;
            if (failing++ == 0) os << "| case | check | result |\n|---|---|---|\n";
            if (shown >= 50) continue;
            ++shown;
            os << "| " << md_cell(c["id"].get<std::string>()) << " | "
               << md_cell(junit_test_name(ck)) << " | " << md_cell(check_text(ck)) << " |\n";
        }
    if (failing > shown) os << "\n… and " << failing - shown << " more failing checks.\n";
    // a FIFO would block the open until a reader comes, a device is no summary: regular files
    if (const auto why = not_regular_reason(path, true); !why.empty()) {
        err << "dampsym: warning: GITHUB_STEP_SUMMARY=" << quote_for_message(path) << ": " << why
            << "; not written\n";
        return;
    }
    std::ofstream f(path, std::ios::app);
    f << os.str() << "\n";
    if (!f) err << "dampsym: warning: cannot append to GITHUB_STEP_SUMMARY=" << path << "\n";
}

} // namespace dampsym::cli_detail
