// The memory side of the run's limits (declared in limits.hpp): --max-memory's default and
// parser, the output-grid plan (stored or streamed, grid_plan) and the per-case memory estimate
// that refuses a case before it allocates (check_memory).
#include "diagnostics/diagnostic.hpp"
#include "harness/case/case.hpp"
#include "harness/case/figures_key.hpp"
#include "harness/problem_info.hpp"
#include "harness/run/case_job.hpp"
#include "harness/run/limits.hpp"
#include "methods/exponential_tableaux.hpp"
#include "methods/families.hpp"
#include "methods/glm_coefficients.hpp"
#include "methods/tableaux.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <type_traits>
#include <unistd.h>
#include <variant>
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

// The stage count s of a method row (1 for a hand-written scheme or a row without stages): an
// implicit method's Newton matrices are (s d) × (s d).
double method_stages(const std::string& id) {
    const MethodInfo* m = find_method(id);
    if (!m) return 1.0;
    const int s =
        visit_family(*m, []<class D>(Family<D>, const D& data) { return Family<D>::stages(data); });
    return std::max(1, s);
}

// The d × d matrices (doubles) a case holds at once, and what dominates. Counts from the peak
// resident size measured on Klein–Gordon at M = 256 (d = 512, one matrix 2 MiB) with csv1, csv2,
// rk4, cimp, gauss1..3 and glifrk2, each with and without the E_n pass (docs/case-keys.md):
// - the problem check of every case (diagnostics/problem_check.hpp): J, D, |J|, |D|: 4 d²
//   (measured 4.4 with an explicit method);
// - per run in flight, an implicit method's Newton iteration: J and the stage system with its LU,
//   3 (s d)² + d² (measured 13 for gauss2, 25.6 for gauss3: model 13, 28);
// - per run in flight, the E_n pass (conformal_symplectic.hpp): Ψ, J⁻¹, J⁻¹Ψ, W and the check
//   of Ψ, 8 d², plus the kernel's step Jacobian: (s + 1) d² for an explicit kernel, 12 (s d)² for
//   an implicit one (measured 7.2 csv1, 12 rk4, 15 cimp, 19.6 gauss1, 45.6 gauss2, 84 gauss3:
//   model 10, 13, 20, 20, 56, 116).
// The problem check and the runs do not overlap: the larger of the two counts.
struct MatrixEstimate {
    double doubles = 0.0;
    std::string what, key;
};
MatrixEstimate estimate_matrices(const CaseSpec& c, double at_once) {
    const double d = std::max(1, c.dim), d2 = d * d;
    bool jacobian_pass = false;
    for (const std::string& name : c.diagnostics)
        if (const DiagnosticInfo* info = find_diagnostic(name))
            jacobian_pass = jacobian_pass || info->needs.jacobian_pass;
    double per_run = 0.0;
    bool implicit_dominates = false;
    for (const std::string& id : c.methods) {
        const MethodInfo* m = find_method(id);
        const bool implicit = m && m->implicit;
        const double s = method_stages(id), sd2 = s * s * d2;
        double n = implicit ? 3.0 * sd2 + d2 : 0.0;
        if (jacobian_pass) n += 8.0 * d2 + (implicit ? 12.0 * sd2 : (s + 1.0) * d2);
        if (n > per_run) {
            per_run = n;
            implicit_dominates = implicit && !jacobian_pass;
        }
    }
    MatrixEstimate e;
    char buf[400];
    const double check = 4.0 * d2;
    if (check >= at_once * per_run) {
        e.doubles = check;
        std::snprintf(buf, sizeof buf,
                      "the problem's Jacobian check: 4 matrices of %d x %d state components", c.dim,
                      c.dim);
        e.key = "problem";
    } else {
        e.doubles = at_once * per_run;
        std::snprintf(buf, sizeof buf,
                      "%s: %.3g matrices of %d x %d state components per run, %g runs at once",
                      jacobian_pass ? "the E_n pass (conformal-symplectic) with its step Jacobians"
                                    : "the implicit methods' Newton matrices",
                      per_run / d2, c.dim, c.dim, at_once);
        e.key = implicit_dominates ? "methods" : "diagnostics";
    }
    e.what = buf;
    return e;
}

// The memory dampsym needs before any case (the program, its libraries, the catalog).
constexpr double kProgramBytes = 64.0 * 1024 * 1024;

struct Parts {
    double grid, ref, sweep, matrices;
};

// What dominates the estimate and the case key to change (the message of check_memory); a part
// is named only when the case has it (osc-orders stores no reference: not blamed on one).
void describe_largest(const CaseSpec& c, MemoryEstimate& est, double points, double at_once,
                      const Parts& p, const MatrixEstimate& mat) {
    char buf[512];
    const double largest = std::max({p.grid + p.ref, p.sweep, p.matrices});
    if (largest < kProgramBytes) { // the program itself dominates: no part is to blame
        est.largest = "dampsym itself, before any case: " + format_bytes(kProgramBytes);
        est.key = "--max-memory";
    } else if (p.sweep == largest) {
        std::snprintf(buf, sizeof buf, "stability sweep: %.3g cells x %zu methods",
                      p.sweep / 64.0 / static_cast<double>(c.methods.size()), c.methods.size());
        est.largest = buf;
        est.key = "stability_sweep";
    } else if (p.matrices == largest) {
        est.largest = mat.what;
        est.key = mat.key;
    } else if (p.grid > 0.0) {
        std::snprintf(buf, sizeof buf,
                      "output grid of %.3g points x %d state components (%g runs at once%s)",
                      points, c.dim, at_once, p.ref > 0.0 ? ", plus the reference on it" : "");
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
}

// What a case holds at once (typed_case.hpp, recorder.hpp, gsl_reference.cpp):
// - per run in flight (at most min(jobs, runs)): the Recorder's output grid, (points+1) × dim
//   doubles, when the grid is stored (grid_plan);
// - per case: the reference on the grid when it is stored, (points+1) × dim doubles held three
//   times (the certified solve, its certifier, the case's copy), its times (points+1 doubles, three
//   times) and the reference cache's key (~26 characters per time);
// - the stability sweep: its rows (about 64 bytes per (γ, h) cell);
// - the d × d matrices (estimate_matrices).
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
    const MatrixEstimate mat = estimate_matrices(c, at_once);
    const double matrix_bytes = mat.doubles * 8.0;
    est.bytes = kProgramBytes + grid_bytes + ref_bytes + sweep_bytes + matrix_bytes;
    describe_largest(c, est, points, at_once, {grid_bytes, ref_bytes, sweep_bytes, matrix_bytes},
                     mat);
    return est;
}

// What to change, for the key that dominates the estimate.
std::string remedy(const std::string& key) {
    if (key == "output_dt") return "raise output_dt (fewer output points) or --max-memory";
    if (key == "t_end") return "lower t_end or raise --max-memory";
    if (key == "stability_sweep") return "coarsen stability_sweep or raise --max-memory";
    if (key == "problem") return "lower the problem's dimension or raise --max-memory";
    if (key == "diagnostics")
        return "lower the problem's dimension or drop conformal-symplectic from diagnostics, or "
               "raise --max-memory";
    if (key == "methods")
        return "lower the problem's dimension or name fewer implicit methods, or raise "
               "--max-memory";
    return "raise --max-memory";
}

void check_memory(const std::vector<CaseSpec>& cases, int jobs, double max_bytes, bool figures) {
    for (const CaseSpec& c : cases) {
        const MemoryEstimate est = estimate_case_memory(c, jobs, figures);
        if (est.bytes <= max_bytes) continue;
        throw InputError(c.file + ": " + est.key + ": case '" + c.id + "' would need about " +
                         format_bytes(est.bytes) + " of memory (" + est.largest +
                         "), above --max-memory " + format_bytes(max_bytes) + "; " +
                         remedy(est.key));
    }
}

} // namespace dampsym
