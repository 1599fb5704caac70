// The memory side of issue 17's limits (declared in limits.hpp): --max-memory's default and
// parser, the output-grid plan (stored or streamed, grid_plan) and the per-case memory estimate
// that refuses a case before it allocates (check_memory).
#include "diagnostics/diagnostic.hpp"
#include "harness/case.hpp"
#include "harness/case_figures.hpp"
#include "harness/case_job.hpp"
#include "harness/limits.hpp"
#include "harness/problem_info.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <unistd.h>
#include <vector>

namespace dampsym {

double default_max_memory() {
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
    if (pages <= 0 || page <= 0) return 4.0 * 1024 * 1024 * 1024; // unknown: 4 GiB
    return 0.5 * static_cast<double>(pages) * static_cast<double>(page);
}

double parse_memory_size(const std::string& text) {
    const std::string what = "--max-memory " + brief(text) +
                             ": expected a size in bytes with an optional suffix K, M, G or T "
                             "(powers of 1024), e.g. 8G";
    if (text.empty()) throw InputError(what);
    errno = 0;
    char* end = nullptr;
    const double x = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || errno == ERANGE || !std::isfinite(x) || !(x > 0.0))
        throw InputError(what);
    std::string suffix(end);
    if (suffix.size() == 3 && suffix.substr(1) == "iB") // KiB, MiB, ...
        suffix.resize(1);
    else if (suffix.size() == 2 && (suffix[1] == 'B' || suffix[1] == 'b')) // KB, MB, ...
        suffix.pop_back();
    double scale = 1.0;
    if (suffix.empty() || suffix == "B" || suffix == "b")
        scale = 1.0;
    else if (suffix == "K" || suffix == "k")
        scale = 1024.0;
    else if (suffix == "M" || suffix == "m")
        scale = 1024.0 * 1024;
    else if (suffix == "G" || suffix == "g")
        scale = 1024.0 * 1024 * 1024;
    else if (suffix == "T" || suffix == "t")
        scale = 1024.0 * 1024 * 1024 * 1024;
    else
        throw InputError(what);
    return x * scale;
}

std::string format_bytes(double bytes) {
    char buf[64];
    if (bytes >= 1024.0 * 1024 * 1024)
        std::snprintf(buf, sizeof buf, "%.1f GiB", bytes / (1024.0 * 1024 * 1024));
    else if (bytes >= 1024.0 * 1024)
        std::snprintf(buf, sizeof buf, "%.1f MiB", bytes / (1024.0 * 1024));
    else
        std::snprintf(buf, sizeof buf, "%.0f KiB", bytes / 1024.0);
    return buf;
}

GridPlan grid_plan(const CaseSpec& c, std::int64_t points, bool has_exact, bool figures) {
    GridPlan p;
    // A "growth" measure is a least-squares fit over all its points (MeasureAccumulator keeps
    // them).
    bool streamable =
        !figures && std::none_of(c.measures.begin(), c.measures.end(), [](const MeasureSpec& m) {
            return m.over == MeasureStat::growth;
        });
    bool reference_grid = false;
    for (const std::string& name : c.diagnostics) {
        const DiagnosticInfo* d = find_diagnostic(name);
        if (!d) continue;
        if (d->needs.grid || (d->needs.grid_if_points && points > 1)) {
            p.grid = true;
            if (!d->needs.streams) streamable = false;
        }
        reference_grid = reference_grid || d->needs.reference_grid;
    }
    p.store_grid = p.grid && !streamable;
    p.store_reference = p.grid && (p.store_grid || !has_exact || reference_grid);
    return p;
}

// What a case holds at once (typed_case.hpp, recorder.hpp, gsl_reference.cpp):
// - per run in flight (at most min(jobs, runs)): the Recorder's output grid, (points+1) × dim
//   doubles, when the grid is stored (grid_plan);
// - per case: the reference on the grid when it is stored, (points+1) × dim doubles held three
//   times (the certified solve, its certifier, the case's copy), its times (points+1 doubles, three
//   times) and the reference cache's key (~26 characters per time);
// - the stability sweep: its rows (about 64 bytes per (γ, h) cell).
// A streamed grid (grid_plan) costs nothing per point.
MemoryEstimate estimate_case_memory(const CaseSpec& c, int jobs, bool figures) {
    MemoryEstimate est;
    const double dim = std::max(1, c.dim);
    const std::int64_t intervals = detail::output_points(c);
    const double points = static_cast<double>(intervals) + 1.0;
    const ProblemInfo* prob = find_problem(c.problem_id);
    // as the runner: a case with "figures": false keeps no series (runner.cpp set_figures)
    const GridPlan plan =
        grid_plan(c, intervals, prob && prob->has_exact, figures && !case_figures_off(c));
    bool reference = false;
    for (const std::string& name : c.diagnostics)
        if (const DiagnosticInfo* d = find_diagnostic(name))
            reference = reference || d->needs.reference;
    const double runs = static_cast<double>(c.methods.size() * c.dts.size());
    const double at_once = std::max(1.0, std::min<double>(std::max(1, jobs), runs));
    double grid_bytes = 0.0, ref_bytes = 0.0, sweep_bytes = 0.0;
    if (plan.store_grid) grid_bytes = at_once * points * dim * 8.0;
    if (reference && plan.store_reference)
        ref_bytes = 3.0 * points * (dim + 1.0) * 8.0 + 26.0 * points;
    if (c.sweep) {
        const auto cells = [](const Range3& r) {
            return std::floor((r.to - r.from) / r.step + 1e-9) + 1.0;
        };
        sweep_bytes = static_cast<double>(c.methods.size()) * cells(c.sweep->gamma) *
                      cells(c.sweep->h) * 64.0;
    }
    est.bytes = 64.0 * 1024 * 1024 + grid_bytes + ref_bytes + sweep_bytes; // + the program itself
    char buf[512];
    if (sweep_bytes > grid_bytes + ref_bytes) {
        std::snprintf(buf, sizeof buf, "stability sweep: %.3g cells x %zu methods",
                      sweep_bytes / 64.0 / static_cast<double>(c.methods.size()), c.methods.size());
        est.largest = buf;
        est.key = "stability_sweep";
    } else if (grid_bytes > 0.0) {
        std::snprintf(buf, sizeof buf,
                      "output grid of %.3g points x %d state components (%g runs at once%s)",
                      points, c.dim, at_once, ref_bytes > 0.0 ? ", plus the reference on it" : "");
        est.largest = buf;
        est.key = c.output_dt ? "output_dt" : "t_end";
    } else {
        // The runs stream the grid; the certified numerical reference is stored (grid_plan).
        std::snprintf(buf, sizeof buf,
                      "certified reference on the output grid of %.3g points x %d state "
                      "components; the runs compare on the fly, but a numerical reference is "
                      "stored: docs/case-keys.md",
                      points, c.dim);
        est.largest = buf;
        est.key = c.output_dt ? "output_dt" : "t_end";
    }
    return est;
}

void check_memory(const std::vector<CaseSpec>& cases, int jobs, double max_bytes, bool figures) {
    for (const CaseSpec& c : cases) {
        const MemoryEstimate est = estimate_case_memory(c, jobs, figures);
        if (est.bytes <= max_bytes) continue;
        throw InputError(c.file + ": " + est.key + ": case '" + c.id + "' would need about " +
                         format_bytes(est.bytes) + " of memory (" + est.largest +
                         "), above --max-memory " + format_bytes(max_bytes) + "; raise " + est.key +
                         (est.key == "output_dt" ? " (fewer output points)" : "") +
                         " or --max-memory");
    }
}

} // namespace dampsym
