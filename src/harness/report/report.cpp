#include "harness/report/report.hpp"

#include "diagnostics/order_diagnostic.hpp"
#include "harness/ci/junit.hpp"
#include "harness/report/markdown.hpp"
#include "harness/report/tables.hpp"
#include "harness/user_methods/method_coefficients.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <sys/stat.h>
#include <unistd.h>

namespace dampsym {
namespace {

using json = nlohmann::json;
using namespace report_detail;

// The timings entry of case `ci` (null if absent).
const json* case_timings(const json& report, std::size_t ci) {
    if (!report.contains("timings") || !report["timings"].contains("cases")) return nullptr;
    const json& tc = report["timings"]["cases"];
    if (ci >= tc.size() || tc[ci]["id"] != report["cases"][ci]["id"]) return nullptr;
    return &tc[ci];
}

std::string wall_text(const json& report) {
    std::string out;
    if (report.contains("timings") && report["timings"].contains("wall_seconds"))
        out = num(report["timings"]["wall_seconds"], 3) + " s";
    if (report.contains("provenance") && report["provenance"].contains("jobs"))
        out += (out.empty() ? "" : " ") + std::string("with --jobs ") +
               report["provenance"]["jobs"].dump();
    return out.empty() ? "no timings" : out;
}

std::string text_of(const json& v) {
    if (v.is_string()) return v.get<std::string>();
    if (v.is_null()) return "unknown";
    return v.dump();
}

// The provenance at the top of report.md: what was built, where and how it ran.
void provenance_block(std::ostringstream& os, const json& report) {
    if (!report.contains("provenance")) return;
    const json& p = report["provenance"];
    auto row = [&](const char* label, const std::string& value) {
        os << "| " << label << " | " << md_cell(value) << " |\n";
    };
    os << "| provenance | |\n|---|---|\n";
    if (p.contains("merged_from")) {
        row("merged", std::to_string(p["merged_from"].size()) + " shard reports (" +
                          text_of(p.value("command_line", json())) + ")");
        if (!p["merged_from"].empty() && p["merged_from"][0].is_object()) {
            std::string shards;
            for (const auto& sp : p["merged_from"])
                shards += (shards.empty() ? "" : "; ") + text_of(sp.value("command_line", json())) +
                          " at " + text_of(sp.value("start_utc", json()));
            row("shards", shards);
        }
    }
    const json& src = p.contains("build")                             ? p
                      : p.value("merged_from", json::array()).empty() ? p
                                                                      : p["merged_from"][0];
    if (src.contains("build")) {
        const json& b = src["build"];
        std::string commit = text_of(b.value("git_commit", json()));
        if (b.value("git_dirty", json()) == true) commit += " (dirty)";
        row("version", text_of(src.value("version", json())));
        row("git commit", commit);
        row("compiler", text_of(b.value("compiler", json())));
        row("build type, flags", text_of(b.value("build_type", json())) + ", `" +
                                     text_of(b.value("flags", json())) + "` " +
                                     text_of(b.value("options", json())));
        if (b.contains("libraries")) {
            std::string libs;
            for (auto it = b["libraries"].begin(); it != b["libraries"].end(); ++it)
                libs += (libs.empty() ? "" : ", ") + it.key() + " " + text_of(it.value());
            row("libraries", libs);
        }
    }
    if (src.contains("host")) {
        const json& h = src["host"];
        std::string os_text = h.contains("os")
                                  ? text_of(h["os"].value("name", json())) + " (" +
                                        text_of(h["os"].value("sysname", json())) + " " +
                                        text_of(h["os"].value("release", json())) + ", " +
                                        text_of(h["os"].value("machine", json())) + ")"
                                  : "unknown";
        row("host", os_text);
        row("CPU", text_of(h.value("cpu_model", json())) + ", " +
                       text_of(h.value("cpu_count", json())) + " logical CPUs");
    }
    if (p.contains("start_utc")) row("started (UTC)", text_of(p["start_utc"]));
    if (p.contains("command_line") && !p.contains("merged_from"))
        row("command line", "`" + text_of(p["command_line"]) + "`");
    if (p.contains("cases_dir")) row("cases directory", text_of(p["cases_dir"]));
    if (p.contains("jobs")) row("--jobs", text_of(p["jobs"]));
    if (p.contains("shard") && p["shard"].is_object())
        row("shard", text_of(p["shard"].value("index", json())) + "/" +
                         text_of(p["shard"].value("count", json())) + " (from " +
                         text_of(p["shard"].value("source", json())) + ")");
    os << "\n";
}

} // namespace

static std::string join_names(const json& names) {
    std::string out;
    for (const auto& n : names) out += (out.empty() ? "" : ", ") + n.get<std::string>();
    return out;
}

json summarize(const json& cases) {
    std::int64_t passed = 0, failed = 0, runs = 0, failed_cases = 0, not_run = 0;
    for (const auto& c : cases) {
        if (c.contains("checks_not_run"))
            not_run += static_cast<std::int64_t>(c["checks_not_run"].size());
        bool ok = true;
        for (const auto& ck : c["checks"]) {
            if (ck["passed"].get<bool>()) {
                ++passed;
            } else {
                ++failed;
                ok = false;
            }
        }
        if (!ok) ++failed_cases;
        runs += static_cast<std::int64_t>(c["runs"].size());
    }
    json s = {{"cases", cases.size()},
              {"failed_cases", failed_cases},
              {"runs", runs},
              {"checks_passed", passed},
              {"checks_failed", failed}};
    if (not_run > 0) s["checks_not_run"] = not_run; // only a selection leaves checks not run
    // loaded methods whose coefficients refute their declaration (method_coefficients.hpp),
    // flagged wherever the report is read; the verdicts stay those of the checks (a case may run a
    // deliberately wrong method as a negative control)
    if (const json refuted = refuted_methods(cases); !refuted.empty())
        s["methods_refuted"] = refuted.size();
    return s;
}

std::string report_json_text(const json& report) {
    nlohmann::ordered_json out = nlohmann::ordered_json::object();
    for (const char* k : {"schema_version", "tool", "summary", "cases", "provenance", "timings"})
        if (report.contains(k)) out[k] = nlohmann::ordered_json(report[k]);
    for (auto it = report.begin(); it != report.end(); ++it)
        if (!out.contains(it.key())) out[it.key()] = nlohmann::ordered_json(it.value());
    return out.dump(2) + "\n";
}

const json* run_timing(const json& report, std::size_t case_index, std::size_t run_index) {
    const json* t = case_timings(report, case_index);
    if (!t || run_index >= (*t)["runs"].size()) return nullptr;
    return &(*t)["runs"][run_index];
}

std::string render_markdown(const json& report) {
    return render_markdown(report, json());
}

namespace {

// A table folded in <details> when it is long (more than `fold_rows` lines), else as it is.
std::string folded(const std::string& table, const std::string& summary, int fold_rows = 12) {
    int lines = 0;
    for (char ch : table) lines += ch == '\n';
    if (lines <= fold_rows) return table;
    return "\n<details><summary>" + summary + " (" + std::to_string(lines) + " lines)</summary>\n" +
           table + "\n</details>\n";
}

std::string anchor_of(const std::string& id) {
    std::string a = "case-";
    for (char ch : id) a += (std::isalnum(static_cast<unsigned char>(ch)) || ch == '-') ? ch : '-';
    return a;
}

// Overview: one row per case, failing cases first, with a link to its section.
void overview_table(std::ostringstream& os, const json& report,
                    const std::vector<std::size_t>& order) {
    os << "\n| case | verdict | checks passed | failed | runs | time s | paper |\n"
          "|---|---|---|---|---|---|---|\n";
    for (const std::size_t ci : order) {
        const json& c = report["cases"][ci];
        int pass = 0, fail = 0;
        for (const auto& ck : c["checks"]) (ck["passed"].get<bool>() ? pass : fail)++;
        const json* t = case_timings(report, ci);
        const std::string id = c["id"].get<std::string>();
        std::string src = c["source"].get<std::string>();
        if (src.size() > 48) src = src.substr(0, 45) + "…";
        os << "| [" << md_cell(id) << "](#" << anchor_of(id) << ") | "
           << (fail ? "**FAIL**" : (c["checks"].empty() ? "no checks" : "pass")) << " | " << pass
           << " | " << fail << " | " << c["runs"].size() << " | "
           << (t && t->contains("runs_wall_seconds") ? num((*t)["runs_wall_seconds"], 3) : "—")
           << " | " << md_cell(src) << " |\n";
    }
}

// The heading and the paragraph of a case's section (source, problem, span, reference).
void case_heading(std::ostringstream& os, const json& c) {
    os << "\n<a id=\"" << anchor_of(c["id"].get<std::string>()) << "\"></a>\n";
    os << "\n## " << (case_passed(c) ? "" : "FAILED: ") << c["id"].get<std::string>();
    if (!c["title"].get<std::string>().empty()) os << " — " << c["title"].get<std::string>();
    os << "\n\n";
    if (!c["source"].get<std::string>().empty())
        os << "Source: " << c["source"].get<std::string>() << ". ";
    os << "Problem `" << c["problem"]["id"].get<std::string>() << "` ";
    std::string params;
    for (auto it = c["problem"]["params"].begin(); it != c["problem"]["params"].end(); ++it) {
        if (!params.empty()) params += ", ";
        params += it.key();
        params += " = ";
        if (it.value().is_array() && it.value().size() > 6) {
            params += "[";
            params += std::to_string(it.value().size());
            params += " values]";
        } else {
            params += num(it.value(), 6);
        }
    }
    os << "(" << params << "), t ∈ [" << num(c["t0"]) << ", " << num(c["t_end"])
       << "], reference: " << c["reference"]["kind"].get<std::string>() << ".";
    if (!c["overrides"].empty()) os << " Overrides: `" << c["overrides"].dump() << "`.";
    if (c.contains("no_checks_because"))
        os << " No checks: " << c["no_checks_because"].get<std::string>() << ".";
}

// A case's checks and tables (long tables folded in <details>).
void case_tables(std::ostringstream& os, const json& c, const json* t) {
    os << "\n\n| result | check | method | dt | metric | value | expected | note |\n"
          "|---|---|---|---|---|---|---|---|\n";
    for (const auto& ck : c["checks"])
        if (!ck["passed"].get<bool>()) os << check_line(ck);
    for (const auto& ck : c["checks"])
        if (ck["passed"].get<bool>()) os << check_line(ck);
    if (c.contains("checks_not_run"))
        for (json ck : c["checks_not_run"]) {
            ck["value"] = nullptr;
            ck["message"] = ck["reason"];
            os << check_line(ck, "not run");
        }
    auto part = [&](const std::string& summary, auto&& table) {
        std::ostringstream tos;
        table(tos);
        os << folded(tos.str(), summary);
    };
    part("Measures", [&](std::ostringstream& o) { measures_table(o, c); });
    part("Convergence", [&](std::ostringstream& o) { order_table(o, c, OrderDiagnostic::name); });
    part("Local error",
         [&](std::ostringstream& o) { order_table(o, c, LocalOrderDiagnostic::name); });
    part("Structure metrics per run", [&](std::ostringstream& o) { metrics_table(o, c); });
    part("Stability sweep", [&](std::ostringstream& o) { sweep_table(o, c); });
    part("Work-precision", [&](std::ostringstream& o) { work_precision_table(o, c, t); });
    part("Runs", [&](std::ostringstream& o) { runs_table(o, c, t); });
}

} // namespace

std::string render_markdown(const json& report, const json& figures) {
    std::ostringstream os;
    const json& s = report["summary"];
    os << "# dampsym report\n\n";
    provenance_block(os, report);
    const json refuted = refuted_methods(report["cases"]);
    for (const auto& [id, names] : refuted.items())
        os << "> **⚠ " << id << ": its coefficients refute its declaration** (" << join_names(names)
           << "); every verdict on its runs rests on a method that is not "
           << "what it declares (`dampsym methods --check --methods FILE`).\n\n";
    os << s["cases"] << " cases, " << s["runs"] << " runs: **" << s["checks_passed"]
       << " checks passed, " << s["checks_failed"] << " failed**"
       << (s.contains("checks_not_run")
               ? ", " + s["checks_not_run"].dump() + " not run (a partner method not selected)"
               : std::string())
       << " (" << wall_text(report)
       << ").\n\nCases with a failing check come first; in each case failing checks come first. A "
          "*negative "
          "control* is a check that passes only when the structure check detects a method that "
          "lacks the "
          "property.\n";
    std::vector<std::size_t> order;
    for (std::size_t i = 0; i < report["cases"].size(); ++i)
        if (!case_passed(report["cases"][i])) order.push_back(i);
    for (std::size_t i = 0; i < report["cases"].size(); ++i)
        if (case_passed(report["cases"][i])) order.push_back(i);
    overview_table(os, report, order);
    const bool with_figures = figures.is_object() && figures.contains("cases");
    if (with_figures)
        os << "\nFigures: one or more per case below, drawn by `dampsym plot` "
              "(tools/figures/plot.py); the gallery of the paper figures is "
              "[figures.md](figures.md).\n";
    for (const std::size_t ci : order) {
        const json& c = report["cases"][ci];
        case_heading(os, c);
        // figures: from figures/manifest.json, paths relative to report.md
        if (with_figures && figures["cases"].contains(c["id"].get<std::string>())) {
            os << "\n\n";
            for (const auto& f : figures["cases"][c["id"].get<std::string>()]) {
                const std::string file = f["file"].get<std::string>();
                const bool pdf = file.size() > 4 && file.substr(file.size() - 4) == ".pdf";
                os << (pdf ? "[" : "![") << f.value("caption", std::string()) << "](" << file
                   << ")\n"; // --figure-format pdf: a link (markdown shows no PDF)
            }
        }
        case_tables(os, c, case_timings(report, ci));
    }
    return os.str();
}

std::string render_case_line(const json& c, const json& seconds) {
    int pass = 0, fail = 0;
    std::vector<std::string> failed;
    for (const auto& ck : c["checks"]) {
        if (ck["passed"].get<bool>()) {
            ++pass;
        } else {
            ++fail;
            failed.push_back(junit_test_name(ck)); // "name [method, dt=0.1]"
        }
    }
    std::ostringstream os;
    char line[200];
    std::snprintf(line, sizeof line, "%-4s %-34s ", fail ? "FAIL" : "ok",
                  c["id"].get<std::string>().c_str());
    os << line;
    if (fail) {
        // the count first, then the first three failing checks with method and dt
        os << fail << " of " << pass + fail << " checks failed: ";
        for (std::size_t i = 0; i < failed.size() && i < 3; ++i) os << (i ? "; " : "") << failed[i];
        if (failed.size() > 3) os << " (+" << failed.size() - 3 << " more)";
    } else {
        std::snprintf(line, sizeof line, "%3d checks", pass);
        os << line;
    }
    if (seconds.is_number()) os << "  " << num(seconds, 3) << " s";
    if (c.contains("checks_not_run"))
        os << "  (" << c["checks_not_run"].size() << " not run: a partner method not selected)";
    if (c.contains("no_checks_because")) os << "  (no checks: stated reason in the report)";
    return os.str() + "\n";
}

std::string render_summary(const json& report) {
    std::ostringstream os;
    for (std::size_t ci = 0; ci < report["cases"].size(); ++ci) {
        const json* t = case_timings(report, ci);
        os << render_case_line(report["cases"][ci],
                               t ? t->value("runs_wall_seconds", json()) : json());
    }
    os << render_totals(report);
    return os.str();
}

std::string render_failed_checks(const json& report, std::size_t limit) {
    std::ostringstream os;
    std::size_t n = 0;
    for (const auto& c : report["cases"])
        for (const auto& ck : c["checks"]) {
            if (ck["passed"].get<bool>()) continue;
            if (n++ >= limit) continue;
            os << "FAILED " << c["id"].get<std::string>() << ": " << junit_test_name(ck) << ": "
               << ck["metric"].get<std::string>() << " = " << num(ck["value"], 6) << ", expected "
               << expected_text(ck)
               << (ck.contains("message") ? " (" + ck["message"].get<std::string>() + ")" : "")
               << "\n";
        }
    if (n > limit) os << "... and " << n - limit << " more failing checks (report.md)\n";
    return os.str();
}

std::string render_totals(const json& report) {
    std::ostringstream os;
    const json& s = report["summary"];
    const json refuted = refuted_methods(report["cases"]);
    for (const auto& [id, names] : refuted.items())
        os << "REFUTED " << id << ": its coefficients refute its declaration (" << names.size()
           << " coefficient checks: " << join_names(names)
           << "; dampsym methods --check --methods FILE)\n";
    os << s["cases"] << " cases, " << s["runs"] << " runs, " << s["checks_passed"]
       << " checks passed, " << s["checks_failed"] << " failed";
    if (s.contains("checks_not_run"))
        os << ", " << s["checks_not_run"] << " not run (a partner method not selected)";
    if (report.contains("timings") && report["timings"].contains("wall_seconds"))
        os << ", " << num(report["timings"]["wall_seconds"], 3) << " s";
    if (report.contains("provenance") && report["provenance"].contains("shard") &&
        report["provenance"]["shard"].is_object()) {
        const json& sh = report["provenance"]["shard"];
        os << " (shard " << text_of(sh.value("index", json())) << "/"
           << text_of(sh.value("count", json())) << " from " << text_of(sh.value("source", json()))
           << ")";
    }
    os << "\n";
    return os.str();
}

namespace {

// What a non-regular file is, for the message refusing to replace it.
const char* file_kind(mode_t mode) {
    if (S_ISLNK(mode)) return "a symbolic link";
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISCHR(mode) || S_ISBLK(mode)) return "a device";
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a regular file";
}

// Creates `path` afresh for writing, never through a symbolic link (O_NOFOLLOW) and never into
// an existing file (O_EXCL: a hard link to another file is not truncated); a leftover of that
// name (a temporary file of a killed run) is unlinked first, which removes the name only.
// Returns the descriptor, or -1 with errno set.
int create_fresh(const std::string& path) {
    const int flags = O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC;
    int fd = ::open(path.c_str(), flags, 0666);
    if (fd < 0 && errno == EEXIST && ::unlink(path.c_str()) == 0)
        fd = ::open(path.c_str(), flags, 0666);
    return fd;
}

// Writes all of `text` to fd; false with errno set on failure.
bool write_all(int fd, const std::string& text) {
    const char* p = text.data();
    std::size_t left = text.size();
    while (left > 0) {
        const ssize_t n = ::write(fd, p, left);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        p += n;
        left -= static_cast<std::size_t>(n);
    }
    return true;
}

} // namespace

void check_replaceable(const std::string& path) {
    struct stat st {};
    if (::lstat(path.c_str(), &st) != 0) {
        if (errno == ENOENT) return;
        throw OutputError(path + ": cannot write: " + std::strerror(errno));
    }
    if (!S_ISREG(st.st_mode))
        throw OutputError(path + ": exists and is " + file_kind(st.st_mode) +
                          ": dampsym replaces only a regular file (remove it or choose another "
                          "path)");
}

void write_file_atomic(const std::string& path, const std::string& text) {
    if (path.empty()) throw OutputError("empty output file name");
    check_replaceable(path); // a symlink, device or directory is refused, not replaced
    const std::string tmp = path + kTemporarySuffix;
    const int fd = create_fresh(tmp);
    if (fd < 0) throw OutputError(tmp + ": cannot write: " + std::strerror(errno));
    const bool written = write_all(fd, text);
    const int e = errno;
    if (::close(fd) != 0 || !written) {
        ::unlink(tmp.c_str()); // a full disk keeps no partial file
        throw OutputError(path + ": cannot write: " + std::strerror(written ? errno : e));
    }
    if (::rename(tmp.c_str(), path.c_str()) != 0) {
        const int re = errno;
        ::unlink(tmp.c_str());
        throw OutputError(path + ": cannot write: " + std::strerror(re));
    }
}

void check_output_dir(const std::string& dir) {
    namespace fs = std::filesystem;
    if (dir.empty()) throw OutputError("--out: empty directory name");
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
        throw OutputError(dir + ": --out: exists and is not a directory");
    fs::create_directories(dir, ec);
    if (ec) throw OutputError(dir + ": --out: cannot create directory: " + ec.message());
    for (const char* name : {"report.json", "report.md"})
        check_replaceable((fs::path(dir) / name).string());
    const std::string probe = (fs::path(dir) / ".dampsym-write-probe").string();
    const int fd = create_fresh(probe);
    if (fd < 0)
        throw OutputError(dir + ": --out: directory is not writable: " + std::strerror(errno));
    ::close(fd);
    ::unlink(probe.c_str());
}

void check_output_file(const std::string& file) {
    namespace fs = std::filesystem;
    if (file.empty()) throw OutputError("empty output file name");
    std::error_code ec;
    const fs::path p(file);
    if (fs::is_directory(p, ec)) throw OutputError(file + ": is a directory");
    check_replaceable(file); // a symlink or device (e.g. /dev/stdout) is refused before any work
    const fs::path parent = p.has_parent_path() ? p.parent_path() : fs::path(".");
    fs::create_directories(parent, ec);
    if (ec) throw OutputError(file + ": cannot create its directory: " + ec.message());
    const std::string probe = (parent / (p.filename().string() + ".dampsym-write-probe")).string();
    const int fd = create_fresh(probe);
    if (fd < 0) throw OutputError(file + ": cannot write: " + std::strerror(errno));
    ::close(fd);
    ::unlink(probe.c_str());
}

void write_reports(const json& report, const std::string& dir) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) throw OutputError(dir + ": cannot create directory: " + ec.message());
    write_file_atomic(dir + "/report.json", report_json_text(report));
    write_file_atomic(dir + "/report.md", render_markdown(report));
}

} // namespace dampsym
