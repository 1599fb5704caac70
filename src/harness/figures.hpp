// Figures (issue 14; docs/reports.md "Figures" and "Series files"): `dampsym run --figures` writes
// one series file per case, DIR/series/<case id>.json, while the cases run, then draws the figures
// with tools/figures/plot.py (matplotlib, /usr/bin/python3) into DIR/figures/ and rewrites
// DIR/report.md with the figures embedded; `dampsym plot DIR` does the drawing part on an existing
// report directory.
#pragma once

#include <nlohmann/json.hpp>

#include <functional>
#include <ostream>
#include <string>

namespace dampsym {

// A RunOptions::series_sink that writes each case's series to DIR/series/<case id>.json.
std::function<void(const nlohmann::json&)> series_file_sink(const std::string& dir);

// The file formats of the figures (`--figure-format`): a comma list of png, svg, pdf, each once;
// the first of png/svg is embedded in report.md (pdf alone: linked). Returns "" if `formats` is
// valid, else what is wrong with it.
std::string figure_formats_error(const std::string& formats);

// Draws the figures of the report in DIR (report.json, series/ if present) with `jobs` processes
// in `formats` (figure_formats_error), then rewrites DIR/report.md with them embedded and
// DIR/figures.md (the paper-figure gallery). Returns 0, or 3 when the figure script cannot run or
// fails (the message names it).
int make_figures(const std::string& dir, int jobs, const std::string& formats, std::ostream& err);

} // namespace dampsym
