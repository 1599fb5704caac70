#include "harness/figures/figures.hpp"

#include "harness/bounded_read.hpp"
#include "harness/case/case.hpp"
#include "harness/report/provenance.hpp"
#include "harness/report/report.hpp"
#include "harness/run/limits.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <iostream>
#include <memory>
#include <mutex>
#include <set>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

extern char** environ;

namespace dampsym {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

// A name dampsym may write or remove inside its own directories: no '/', not "." or "..", no
// leading '.', characters of A-Z a-z 0-9 . _ - (what output_file_name makes of a case id).
bool plain_file_name(const std::string& s) {
    if (s.empty() || s.size() > 255 || !std::isalnum(static_cast<unsigned char>(s[0])))
        return false;
    for (char c : s)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '_' && c != '-')
            return false;
    return true;
}

// Reads `p`, which must be a regular file (a symbolic link is not followed) of at most `limit`
// bytes, into text. Returns "" or what is wrong.
std::string read_bounded(const fs::path& p, std::uintmax_t limit, std::string& text) {
    const int fd = ::open(p.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0)
        return errno == ELOOP ? "is a symbolic link (only a regular file is read)"
                              : std::string("cannot read: ") + std::strerror(errno);
    struct stat st {};
    std::string error;
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode))
        error = "is not a regular file";
    else if (static_cast<std::uintmax_t>(st.st_size) > limit)
        error = "too large (" + std::to_string(st.st_size) + " bytes; the limit is " +
                std::to_string(limit) + ")";
    text.clear();
    char buf[1 << 16];
    while (error.empty()) {
        const ssize_t n = ::read(fd, buf, sizeof buf);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) error = std::string("cannot read: ") + std::strerror(errno);
        if (n <= 0) break;
        text.append(buf, static_cast<std::size_t>(n));
        if (text.size() > limit) error = "too large (it grew while read)";
    }
    ::close(fd);
    return error;
}

// What is wrong with `d` as one of dampsym's own subdirectories (series/, figures/): "" if it is
// absent or a directory; a symbolic link is refused (it would lead the outputs elsewhere).
std::string own_directory_error(const fs::path& d) {
    struct stat st {};
    if (::lstat(d.c_str(), &st) != 0) return errno == ENOENT ? "" : std::strerror(errno);
    if (S_ISDIR(st.st_mode)) return "";
    return S_ISLNK(st.st_mode) ? "is a symbolic link, not a directory"
                               : "exists and is not a directory";
}

constexpr const char* kManifest = ".dampsym-manifest";
constexpr const char* kManifestHeader =
    "# dampsym: the files it wrote here; its next run into this directory removes them\n";

// The names DIR's manifest lists (plain names only: a line naming anything else is skipped).
std::vector<std::string> listed_outputs(const fs::path& dir) {
    std::string text;
    if (!read_bounded(dir / kManifest, 1 << 22, text).empty()) return {};
    std::vector<std::string> names;
    std::size_t start = 0;
    while (start < text.size()) {
        std::size_t end = text.find('\n', start);
        if (end == std::string::npos) end = text.size();
        const std::string line = text.substr(start, end - start);
        if (plain_file_name(line)) names.push_back(line);
        start = end + 1;
    }
    return names;
}

// Sorted: the same file for any --jobs (the series arrive in the order the cases finish).
void write_manifest(const fs::path& dir, std::vector<std::string> names) {
    std::sort(names.begin(), names.end());
    std::string text = kManifestHeader;
    for (const auto& n : names) text += n + "\n";
    write_file_atomic((dir / kManifest).string(), text);
}

// Removes what an earlier dampsym run wrote into `dir` (its manifest; regular files only, and
// their temporary files), then empties the manifest. Files dampsym did not write stay.
void remove_listed_outputs(const fs::path& dir) {
    for (const auto& name : listed_outputs(dir))
        for (const std::string& n : {name, name + kTemporarySuffix}) {
            const fs::path p = dir / n;
            struct stat st {};
            if (::lstat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode)) ::unlink(p.c_str());
        }
    write_manifest(dir, {});
}

} // namespace

std::string output_file_name(const std::string& id, const std::string& suffix) {
    if (!valid_case_id(id))
        throw OutputError("'" + brief(id) + "' is not a valid case id: it names no output file");
    return id + suffix;
}

std::function<void(const json&)> series_file_sink(const std::string& dir) {
    const fs::path sdir = fs::path(dir) / "series";
    if (const std::string e = own_directory_error(sdir); !e.empty())
        throw OutputError(sdir.string() + ": " + e);
    std::error_code ec;
    fs::create_directories(sdir, ec);
    if (ec) throw OutputError(sdir.string() + ": cannot create directory: " + ec.message());
    remove_listed_outputs(sdir); // series of an earlier run with other cases must not linger
    struct Written {
        std::mutex mutex;
        std::vector<std::string> names;
    };
    auto written = std::make_shared<Written>();
    // Called by the threads that finish cases, each with its own case: the manifest is shared.
    return [sdir, written](const json& s) {
        if (!s.is_object() || !s.contains("case") || !s["case"].is_string()) return;
        const std::string name = output_file_name(s["case"].get<std::string>(), ".json");
        const std::string text = s.dump();
        {
            std::lock_guard<std::mutex> lock(written->mutex);
            written->names.push_back(name);
            write_manifest(sdir, written->names); // listed first: a run killed while writing
        }                                         // the file removes it
        write_file_atomic((sdir / name).string(), text);
    };
}

std::string figure_dirs_error(const std::string& dir) {
    for (const char* sub : {"series", "figures"}) {
        const fs::path d = fs::path(dir) / sub;
        if (const std::string e = own_directory_error(d); !e.empty()) return d.string() + ": " + e;
    }
    return "";
}

json load_figure_report(const std::string& dir) {
    const std::string file = (fs::path(dir) / "report.json").string();
    // a FIFO, device or oversized file is bad input naming what it is (bounded_read.hpp)
    const std::string text = read_regular_file(file, kMaxReportBytes, "report");
    json rep = json::parse(text, nullptr, false);
    if (rep.is_discarded()) throw InputError(file + ": malformed JSON");
    if (!rep.is_object() || !rep.contains("cases") || !rep["cases"].is_array())
        throw InputError(file + ": cases: missing or not an array (not a dampsym report)");
    std::set<std::string> seen;
    for (std::size_t i = 0; i < rep["cases"].size(); ++i) {
        const json& c = rep["cases"][i];
        const std::string key = file + ": cases[" + std::to_string(i) + "].id: ";
        if (!c.is_object() || !c.contains("id") || !c["id"].is_string())
            throw InputError(key + "missing or not a string");
        const std::string id = c["id"].get<std::string>();
        // the same rule as a case file's id (case/parse.cpp): ids name the figure files
        if (!valid_case_id(id))
            throw InputError(key + "'" + brief(id) + "' is not a valid case id (at most " +
                             std::to_string(limits::max_id_length) +
                             " characters of A-Z a-z 0-9 . _ -, starting with a letter or digit)");
        if (!seen.insert(id).second) throw InputError(key + "'" + id + "' listed twice");
    }
    return rep;
}

namespace {

std::string figure_formats_part(const std::string& formats, std::size_t start, std::size_t comma) {
    return formats.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
}

// Starts argv (argv[0] looked up in PATH) in a process group of its own, with `stdin_fd` as its
// standard input when >= 0. Returns its pid, or -1 with `error` set.
pid_t spawn_in_own_group(const std::vector<std::string>& args, int stdin_fd, std::string& error) {
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    posix_spawnattr_t attr;
    posix_spawnattr_init(&attr);
    posix_spawnattr_setpgroup(&attr, 0);
    sigset_t set;
    sigemptyset(&set);
    posix_spawnattr_setsigmask(&attr, &set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    posix_spawnattr_setsigdefault(&attr, &set);
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGMASK |
                                        POSIX_SPAWN_SETSIGDEF);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    if (stdin_fd >= 0) posix_spawn_file_actions_adddup2(&actions, stdin_fd, STDIN_FILENO);
    pid_t pid = 0;
    const int rc = posix_spawnp(&pid, argv[0], &actions, &attr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attr);
    if (rc != 0) {
        error = args[0] + ": cannot start: " + std::strerror(rc);
        return -1;
    }
    return pid;
}

int wait_for(pid_t pid) {
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    return status;
}

// Runs argv in a process group of its own, so that a terminal's Ctrl-C reaches dampsym alone and
// dampsym's stop handlers forward it (set_stop_child_group). Returns the wait status, or -1 with
// `error` set when it cannot start.
int run_in_own_group(const std::vector<std::string>& args, std::string& error) {
    const pid_t pid = spawn_in_own_group(args, -1, error);
    if (pid < 0) return -1;
    set_stop_child_group(pid);
    const int status = wait_for(pid);
    set_stop_child_group(0);
    return status;
}

std::string python_for_figures() {
    const char* py_env = std::getenv("DAMPSYM_PYTHON");
    return py_env && *py_env ? py_env : "/usr/bin/python3";
}

fs::path figure_script() {
    return fs::path(source_dir()) / "tools" / "figures" / "plot.py";
}

std::vector<std::string> figure_script_args(const std::string& dir, int jobs,
                                            const std::string& formats) {
    return {python_for_figures(),
            figure_script().string(),
            dir,
            "--jobs",
            std::to_string(std::max(1, jobs)),
            "--format",
            formats};
}

} // namespace

std::string figure_formats_error(const std::string& formats) {
    std::vector<std::string> seen;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = formats.find(',', start);
        const std::string f = figure_formats_part(formats, start, comma);
        if (f != "png" && f != "svg" && f != "pdf")
            return "'" + f + "' is not a figure format (png, svg, pdf, comma-separated)";
        for (const auto& g : seen)
            if (g == f) return "figure format '" + f + "' listed twice";
        seen.push_back(f);
        if (comma == std::string::npos) return "";
        start = comma + 1;
    }
}

EarlyFigureScript::EarlyFigureScript(const std::string& dir, int jobs, const std::string& formats) {
    std::error_code ec;
    if (!fs::exists(figure_script(), ec)) return; // make_figures says so
    int sv[2];
    if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0) return;
    std::vector<std::string> args = figure_script_args(dir, jobs, formats);
    args.push_back("--after-go");
    std::string error;
    const pid_t pid = spawn_in_own_group(args, sv[1], error);
    ::close(sv[1]);
    if (pid < 0) { // make_figures tries again and reports why it cannot
        ::close(sv[0]);
        return;
    }
    pid_ = pid;
    fd_ = sv[0];
    set_stop_child_group(pid_);
}

int EarlyFigureScript::draw() {
    static const char go[] = "go\n";
    // a script that has ended already (a signal) reads nothing: its wait status says so
    (void)!::send(fd_, go, sizeof go - 1, MSG_NOSIGNAL);
    ::close(fd_);
    fd_ = -1;
    const int status = wait_for(pid_);
    set_stop_child_group(0);
    pid_ = -1;
    return status;
}

void EarlyFigureScript::finish() noexcept {
    if (fd_ >= 0) ::close(fd_); // end of input without "go": the script exits, drawing nothing
    fd_ = -1;
    if (pid_ > 0) {
        ::kill(-pid_, SIGTERM); // at once, even while it imports (it exits 143 quietly)
        wait_for(pid_);
        set_stop_child_group(0);
    }
    pid_ = -1;
}

EarlyFigureScript::~EarlyFigureScript() {
    finish();
}

int make_figures(const std::string& dir, int jobs, const std::string& formats, std::ostream& err,
                 EarlyFigureScript* early) {
    if (dir.empty()) throw InputError("REPORT_DIR: empty path");
    load_figure_report(dir); // InputError (exit 2) before the script starts
    if (const std::string e = figure_dirs_error(dir); !e.empty()) throw InputError(e);
    const fs::path script = figure_script();
    if (!fs::exists(script)) {
        err << "dampsym: " << script.string() << ": figure script not found\n";
        return 3;
    }
    // what dampsym printed so far comes before the script's lines (a CI log is a pipe, where
    // std::cout is buffered; the script writes to the same descriptors)
    std::cout.flush();
    std::cerr.flush();
    err.flush();
    std::string error;
    const int st = early && early->started()
                       ? early->draw()
                       : run_in_own_group(figure_script_args(dir, jobs, formats), error);
    if (stop_requested()) { // forwarded to the script, which stopped; report.md stays as it was
        err << "dampsym: figures stopped by a signal (" << dir << "/figures/ is incomplete)\n";
        return 128 + stop_signal();
    }
    const int code = st >= 0 && WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    if (code == 2 || code == 3) return code; // bad input / output: the script named the file
    if (code != 0) {
        err << "dampsym: figure script failed ("
            << (!error.empty()    ? error
                : WIFSIGNALED(st) ? "signal " + std::to_string(WTERMSIG(st))
                                  : "exit " + std::to_string(code))
            << "): " << script.string() << "\n";
        return 3;
    }
    // report.md again, now with the figures the script listed in figures/manifest.json
    const json rep = load_figure_report(dir);
    std::string text;
    const fs::path manifest_file = fs::path(dir) / "figures" / "manifest.json";
    const std::string e = read_bounded(manifest_file, kMaxReportBytes, text);
    const json manifest = e.empty() ? json::parse(text, nullptr, false) : json();
    if (!manifest.is_object()) {
        err << "dampsym: " << manifest_file.string() << ": unreadable ("
            << (e.empty() ? "malformed JSON" : e) << ")\n";
        return 3;
    }
    write_file_atomic((fs::path(dir) / "report.md").string(), render_markdown(rep, manifest));
    return 0;
}

} // namespace dampsym
