// Figures (docs/reports.md "Figures" and "Series files"): `dampsym run --figures` writes
// one series file per case, DIR/series/<case id>.json, while the cases run, then draws the figures
// with tools/figures/plot.py (matplotlib, /usr/bin/python3) into DIR/figures/ and rewrites
// DIR/report.md with the figures embedded; `dampsym plot DIR` does the drawing part on an existing
// report directory.
//
// Outputs stay in the report directory (docs/reports.md "Figures"): a case id becomes a file name
// only through output_file_name (a valid case id, so no '/', no "..", no absolute path), a report's
// ids are validated when it is loaded for drawing (load_figure_report, as a case file's), series/
// and figures/ must be directories of DIR (not symbolic links), and dampsym removes only what it
// wrote there itself: each directory keeps a manifest, DIR/series/.dampsym-manifest and
// DIR/figures/.dampsym-manifest (one file name a line), and a run removes the files an earlier
// run listed, never another file. The figure script runs in a process group of its own and stops
// with dampsym (SIGINT 130, SIGTERM 143; harness/run/limits.hpp).
#pragma once

#include "harness/bounded_read.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <ostream>
#include <string>

namespace dampsym {

// Size limits of what is read back for drawing (report.json, figures/manifest.json; plot.py reads
// series files up to its own SERIES_LIMIT): kMaxReportBytes of harness/bounded_read.hpp.

// The file name of a case's output: `id` + `suffix`, for a valid case id (valid_case_id: at most
// 100 characters of A-Z a-z 0-9 . _ -, the first a letter or digit); any other id is refused
// (OutputError): a name never leads out of its directory.
std::string output_file_name(const std::string& id, const std::string& suffix);

// A RunOptions::series_sink that writes each case's series to DIR/series/<case id>.json, after
// removing the series files an earlier run listed in DIR/series/.dampsym-manifest (no other
// file). Throws OutputError if DIR/series exists and is not a directory (or is a symbolic link).
std::function<void(const nlohmann::json&)> series_file_sink(const std::string& dir);

// What is wrong with DIR/series and DIR/figures as outputs ("" if each is absent or a directory,
// not a symbolic link): checked by `run --figures` before any case runs.
std::string figure_dirs_error(const std::string& dir);

// DIR/report.json, read for drawing: a regular file of at most kMaxReportBytes, JSON, "cases" an
// array whose ids are valid case ids, each once. Throws InputError naming the file and key.
nlohmann::json load_figure_report(const std::string& dir);

// The file formats of the figures (`--figure-format`): a comma list of png, svg, pdf, each once;
// the first of png/svg is embedded in report.md (pdf alone: linked). Returns "" if `formats` is
// valid, else what is wrong with it.
std::string figure_formats_error(const std::string& formats);

// Draws the figures of the report in DIR (report.json, series/ if present) with `jobs` processes
// in `formats` (figure_formats_error), then rewrites DIR/report.md with them embedded and
// DIR/figures.md (the paper-figure gallery). Returns 0; 2 for bad input (a malformed report, a
// figures/ that is not a directory, an oversized series file: one line naming the file); 3 when
// the figure script cannot run, fails or cannot write (the message names it); 130/143 when a
// SIGINT/SIGTERM stopped it (the stop handlers must be installed: install_stop_handlers).
// Throws InputError for an empty DIR or a report it cannot draw from (load_figure_report).
// EarlyFigureScript: the figure script of `run --figures` started before the cases run, so that
// its second of importing matplotlib overlaps them (the cost of --figures, docs/reports.md
// "Cost"). It waits for one line "go" on its standard input before it reads anything; make_figures
// sends it once report.json is written, and the drawing is then exactly that of a script started
// at that moment. Destroyed without it (an early return, a signal), it closes the script's input,
// on which the script exits without drawing, and waits for it. While it lives, a SIGINT/SIGTERM
// is forwarded to it (set_stop_child_group), as to a drawing script.
class EarlyFigureScript {
public:
    // Starts the script (DAMPSYM_PYTHON or /usr/bin/python3) when it exists and can start; else
    // started() is false and make_figures starts one itself (and reports why it cannot).
    EarlyFigureScript(const std::string& dir, int jobs, const std::string& formats);
    ~EarlyFigureScript();
    EarlyFigureScript(const EarlyFigureScript&) = delete;
    EarlyFigureScript& operator=(const EarlyFigureScript&) = delete;
    bool started() const { return pid_ > 0; }
    // Tells the script to draw and waits for it: its wait status.
    int draw();

private:
    int pid_ = -1;
    int fd_ = -1; // our end of the script's standard input (a socket: no SIGPIPE)
    void finish() noexcept;
};

// `early`: a script started with the run (used instead of starting one when it started).
int make_figures(const std::string& dir, int jobs, const std::string& formats, std::ostream& err,
                 EarlyFigureScript* early = nullptr);

} // namespace dampsym
