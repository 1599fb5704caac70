#include "harness/figures.hpp"

#include "harness/bounded_read.hpp"
#include "harness/case.hpp"
#include "harness/provenance.hpp"
#include "harness/report.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

namespace dampsym {

namespace fs = std::filesystem;
using json = nlohmann::json;

std::function<void(const json&)> series_file_sink(const std::string& dir) {
    const fs::path sdir = fs::path(dir) / "series";
    std::error_code ec;
    fs::remove_all(sdir, ec); // series of an earlier run with other cases must not linger
    fs::create_directories(sdir, ec);
    if (ec) throw OutputError(sdir.string() + ": cannot create directory: " + ec.message());
    return [sdir](const json& s) {
        if (!s.is_object() || !s.contains("case")) return;
        write_file_atomic((sdir / (s["case"].get<std::string>() + ".json")).string(), s.dump());
    };
}

namespace {

std::string shell_quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

json read_json_file(const fs::path& p) {
    std::string text; // a FIFO, device or oversized file reads as no file (bounded_read.hpp)
    try {
        text = read_regular_file(p.string(), kMaxReportBytes, "report");
    } catch (const InputError&) {
        return nullptr;
    }
    json j = json::parse(text, nullptr, false);
    return j.is_discarded() ? json(nullptr) : j;
}

} // namespace

std::string figure_formats_error(const std::string& formats) {
    std::vector<std::string> seen;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = formats.find(',', start);
        const std::string f =
            formats.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        if (f != "png" && f != "svg" && f != "pdf")
            return "'" + f + "' is not a figure format (png, svg, pdf, comma-separated)";
        for (const auto& g : seen)
            if (g == f) return "figure format '" + f + "' listed twice";
        seen.push_back(f);
        if (comma == std::string::npos) return "";
        start = comma + 1;
    }
}

int make_figures(const std::string& dir, int jobs, const std::string& formats, std::ostream& err) {
    const fs::path report = fs::path(dir) / "report.json";
    if (!fs::exists(report)) {
        err << "dampsym: " << report.string() << ": no report to plot\n";
        return 3;
    }
    // the figure script would hang on a FIFO and exhaust memory on a huge file: bad input
    if (const auto why = not_regular_reason(report.string(), false); !why.empty()) {
        err << "dampsym: report " << quote_for_message(report.string()) << ": " << why << "\n";
        return 2;
    }
    if (fs::file_size(report) > kMaxReportBytes) {
        err << "dampsym: report " << quote_for_message(report.string()) << ": more than the "
            << (kMaxReportBytes >> 20) << " MiB limit\n";
        return 2;
    }
    const char* py_env = std::getenv("DAMPSYM_PYTHON");
    const std::string python = py_env && *py_env ? py_env : "/usr/bin/python3";
    const fs::path script = fs::path(source_dir()) / "tools" / "figures" / "plot.py";
    if (!fs::exists(script)) {
        err << "dampsym: " << script.string() << ": figure script not found\n";
        return 3;
    }
    const std::string cmd = shell_quote(python) + " " + shell_quote(script.string()) + " " +
                            shell_quote(dir) + " --jobs " + std::to_string(std::max(1, jobs)) +
                            " --format " + shell_quote(formats);
    const int rc = std::system(cmd.c_str());
    if (rc != 0) {
        err << "dampsym: figure script failed (exit " << rc << "): " << cmd << "\n";
        return 3;
    }
    // report.md again, now with the figures the script listed in figures/manifest.json
    const json manifest = read_json_file(fs::path(dir) / "figures" / "manifest.json");
    const json rep = read_json_file(report);
    if (rep.is_null() || manifest.is_null()) {
        err << "dampsym: " << dir << ": report.json or figures/manifest.json unreadable\n";
        return 3;
    }
    write_file_atomic((fs::path(dir) / "report.md").string(), render_markdown(rep, manifest));
    return 0;
}

} // namespace dampsym
