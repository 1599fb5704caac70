"""Draws the figures of a dampsym report directory (docs/reports.md "Figures").

    /usr/bin/python3 tools/figures/plot.py REPORT_DIR [--jobs N] [--format png|svg|pdf[,...]]

Reads REPORT_DIR/report.json and, when the run was made with --figures, REPORT_DIR/series/*.json;
writes REPORT_DIR/figures/<case>-<kind>.<format>, the list of figures per case with the quantities
each draws (figures/manifest.json, which `dampsym` embeds in report.md) and the paper-figure
gallery REPORT_DIR/figures.md (what the paper's figure shows beside what dampsym's draws). One
process imports matplotlib once and forks N workers, each taking whole cases from a shared queue.
What each figure plots is computed in figdata.py (without matplotlib).

Exit status: 0; 1 a figure could not be drawn; 2 bad input (one line naming the file); 3 an
output that cannot be written; 130/143 on SIGINT/SIGTERM, quietly."""

import argparse
import gc
import json
import os
import pickle
import select
import signal
import struct
import sys
from types import FrameType
from typing import Any, Callable, Dict, List, Optional, Tuple

from . import figdata as fd
from . import papers
from . import render
from . import safeio as sio
from .draw_conv import fig_convergence, fig_stability, fig_trace
from .draw_series import fig_series
from .draw_space import fig_orbit, fig_poincare, fig_portrait, fig_snapshots
from .render import Ctx, Drawn, Json

# (case id, kind, [(file, caption, quantities)], error or None, exit status the error calls for)
Result = Tuple[str, str, List[Drawn], Optional[str], int]
KIND_ORDER = ["convergence", "series", "snapshots", "orbit", "portrait", "poincare", "stability"]


def plan(case: Json, ser: Optional[Json]) -> Tuple[List[str], List[str]]:
    """The kinds of figure to draw for a case: those its data allows, restricted to its
    "figures" key when it has one; and the kinds the key asks for that have no data."""
    runs = ser["runs"] if ser else []
    has: Dict[str, bool] = {
        "convergence": len(case["dt_ladder"]) >= 2 and bool(
            fd.convergence_data(case) or fd.local_convergence_data(case)),
        "series": bool(ser and fd.series_panels(ser, case)),
        "snapshots": any(r["series"].get("snapshots", {}).get("t") for r in runs),
        "orbit": any("orbit" in r["series"] for r in runs),
        "portrait": any("attractor.plane" in r["series"] for r in runs),
        "poincare": any("poincare" in r["series"] for r in runs),
        "stability": any("stability-sweep" in v or "trace-taylor" in v
                         for v in case.get("method_metrics", {}).values()),
    }
    kinds = [k for k in KIND_ORDER if has[k]]
    wanted = fd.case_figure_kinds(case)
    if wanted is None:
        return kinds, []
    return [k for k in kinds if k in wanted], sorted(wanted - set(kinds))


def drawers(ctx: Ctx, index: int) -> Dict[str, Callable[[Json, Any], List[Drawn]]]:
    return {"convergence": lambda c, s: fig_convergence(ctx, c, fd.case_timing(ctx.report,
                                                                                 index)),
            "series": lambda c, s: fig_series(ctx, c, s),
            "orbit": lambda c, s: fig_orbit(ctx, c, s),
            "stability": lambda c, s: fig_trace(ctx, c, s) + fig_stability(ctx, c, s),
            "poincare": lambda c, s: fig_poincare(ctx, c, s),
            "snapshots": lambda c, s: fig_snapshots(ctx, c, s),
            "portrait": lambda c, s: fig_portrait(ctx, c, s)}


def case_methods(case: Json) -> List[str]:
    """The case's methods in the order of its runs (each once)."""
    return list(dict.fromkeys(r["method"] for r in case.get("runs", []) if r.get("method")))


def draw_case(ctx: Ctx, i: int) -> List[Result]:
    """Every figure of case i: reads only this case's series file. An output that cannot be
    written (OutputProblem) ends the script."""
    import matplotlib.pyplot as plt
    case = ctx.report["cases"][i]
    ctx.styles = fd.case_styles(case_methods(case))
    try:
        ser = fd.load_series(ctx.out, case["id"])
    except sio.InputProblem as e:
        return [(case["id"], "series", [], str(e), 2)]
    except OSError as e:
        return [(case["id"], "series", [], f"series file unreadable: {e}", 2)]
    try:
        kinds, missing = plan(case, ser)
    except Exception as e:  # data the validation does not reach (a run's metrics): reported
        return [(case["id"], "convergence", [], f"cannot plan its figures: "
                 f"{type(e).__name__}: {e}", 1)]
    out: List[Result] = [(case["id"], k, [], "listed in the case's \"figures\" but there is "
                          "nothing to draw (no data of this kind: a run without --figures?)", 1)
                         for k in missing]
    draw = drawers(ctx, i)
    for kind in kinds:
        try:
            out.append((case["id"], kind, draw[kind](case, ser), None, 0))
        except sio.OutputProblem:
            raise
        except Exception as e:  # one bad figure must not hide the others; reported, exit 1
            plt.close("all")
            ctx.blank.clear()
            out.append((case["id"], kind, [], f"{type(e).__name__}: {e}", 1))
    return out


def series_cost(ctx: Ctx, i: int) -> int:
    """Size of a case's series file (+ a ladder's convergence figure): the work of its case."""
    case = ctx.report["cases"][i]
    try:
        size = os.lstat(fd.series_path(ctx.out, case["id"])).st_size
    except OSError:
        size = 0
    return size + 200000 * (len(case["dt_ladder"]) >= 2)


INDEX = struct.Struct("<I")  # a case index in the work queue
# Queue writes of at most PIPE_BUF bytes are atomic, and a whole number of indices: every read of
# INDEX.size bytes by a worker then takes exactly one index (or none, at the end).
QUEUE_CHUNK = (select.PIPE_BUF // INDEX.size) * INDEX.size


def queue_order(ctx: Ctx, cases: List[int]) -> List[int]:
    """The cases as the workers take them: the largest (series_cost) first, so that the last
    ones taken are small and the workers end together."""
    return sorted(cases, key=lambda i: (-series_cost(ctx, i), i))


def next_case(queue: int) -> Optional[int]:
    """The next case index from the shared queue (a pipe), None when it is empty and closed."""
    data = os.read(queue, INDEX.size)
    return INDEX.unpack(data)[0] if len(data) == INDEX.size else None


def child(ctx: Ctx, queue: int, wfd: int) -> None:
    """A worker: draws the cases it takes from the queue, one at a time, until it is empty, and
    sends the results (pickled) through wfd; never returns. Which worker draws which case
    depends on timing; what each figure holds does not (every cache of the drawing is keyed by
    its full input)."""
    try:
        results: List[Result] = []
        while (i := next_case(queue)) is not None:
            results += draw_case(ctx, i)
        msg: Tuple[str, Any] = ("ok", results)
    except sio.OutputProblem as e:
        msg = ("output", str(e))
    except BaseException as e:  # noqa: B036 - reported by the parent as an internal error
        msg = ("error", f"{type(e).__name__}: {str(e)[:200]}")
    with os.fdopen(wfd, "wb") as f:
        f.write(pickle.dumps(msg))
    os._exit(0)


def fill_queue(queue: int, order: List[int]) -> None:
    """Writes the case indices into the queue in atomic chunks, then closes it (a worker that
    died leaves the others to take its share)."""
    data = b"".join(INDEX.pack(i) for i in order)
    try:
        for k in range(0, len(data), QUEUE_CHUNK):
            os.write(queue, data[k:k + QUEUE_CHUNK])
    except BrokenPipeError:  # every worker has ended: the results say why
        pass
    finally:
        os.close(queue)


def draw_all(ctx: Ctx, cases: List[int], jobs: int, workers: List[int]) -> List[Result]:
    """Every figure of the cases, in `jobs` forked workers (their pids kept in `workers` for the
    signal handler) that take the cases one at a time from a shared queue: a static split by
    series size left one worker with half again the other's drawing. Python's cyclic collector
    scanned matplotlib's many artists again and again: what exists now is frozen out of its scans
    and it runs every 50 000 allocations. Freed Agg buffers stay in the heap for the next
    renderer (render.keep_freed_buffers)."""
    render.keep_freed_buffers()
    gc.freeze()
    gc.set_threshold(50000, 50, 100)
    if jobs <= 1 or len(cases) <= 1:
        return [r for i in cases for r in draw_case(ctx, i)]
    qr, qw = os.pipe()
    pipes = []
    for _ in range(min(jobs, len(cases))):
        rfd, wfd = os.pipe()
        pid = os.fork()
        if pid == 0:
            os.close(rfd)
            os.close(qw)
            child(ctx, qr, wfd)
        os.close(wfd)
        workers.append(pid)
        pipes.append((pid, rfd))
    os.close(qr)
    fill_queue(qw, queue_order(ctx, cases))
    return collect(pipes)


def collect(pipes: List[Tuple[int, int]]) -> List[Result]:
    """The workers' results, read from their pipes; an output problem or an internal error of
    any worker raised after all have ended."""
    results: List[Result] = []
    problems: List[Tuple[str, str]] = []
    for pid, rfd in pipes:
        with os.fdopen(rfd, "rb") as f:
            data = f.read()
        os.waitpid(pid, 0)
        kind, payload = pickle.loads(data) if data else ("error", "a worker died")
        if kind == "ok":
            results += payload
        else:
            problems.append((kind, payload))
    for kind, text in problems:
        raise sio.OutputProblem(text) if kind == "output" else RuntimeError(text)
    return results


def verdict_of(case: Json) -> str:
    checks = case["checks"]
    passed = sum(1 for k in checks if k["passed"])
    return ("no checks" if not checks else
            "pass" if passed == len(checks) else f"**FAIL** ({len(checks) - passed})")


def gallery_row(c: Json, figs: List[Json], paper: str) -> str:
    """One row of figures.md: the paper's figure (what it shows) beside dampsym's (the files and
    the quantities drawn), the checks that hold the claim and the verdict."""
    names = list(dict.fromkeys(k["name"] for k in c["checks"]))
    held = "; ".join(names[:3]) + (f"; … ({len(names) - 3} more)" if len(names) > 3 else "")
    imgs = " ".join(f'<a href="{f["file"]}"><img src="{f["file"]}" width="220" '
                    f'alt="{f["caption"]}"></a>' for f in figs) or \
        "(no figure: the case reduces to numbers, see report.md)"
    ours = "; ".join(f"{f['kind']}: " + ", ".join(f["quantities"]) for f in figs) or "—"
    cells = [paper, f"[{c['id']}](report.md#case-{c['id']})", papers.describe(paper),
             c["title"], ours, imgs, held, verdict_of(c)]
    return "| " + " | ".join(x.replace("|", "\\|") if i != 1 else x
                             for i, x in enumerate(cells)) + " |"


def gallery(report: Json, manifest: Json) -> str:
    """figures.md: every case that names a paper figure or table, the paper's figure described
    beside dampsym's figures and what they draw."""
    rows = sorted((fd.paper_figure(c), c["id"], c) for c in report["cases"] if fd.paper_figure(c))
    out = ["# Paper figures and tables reproduced by dampsym", "",
           "Every case whose source names a figure or table of F (Floyd 2014), B (Bhatt 2016), "
           "HLW (Hairer–Lubich–Wanner ch. I) or BS (Butcher's slides) — docs/references.md. "
           "'The paper's figure' says what the paper draws (axes, range, the feature its text "
           "reads from it); 'dampsym draws' lists per figure the quantities on its axes (metric "
           "or series names of report.json and the series files, as figures/manifest.json). "
           "Drawn by `dampsym plot` (tools/figures) from report.json and the run's series files; "
           "the case section in [report.md](report.md) has the full checks.", "",
           "| paper | case | the paper's figure | the claim (case title) | dampsym draws | "
           "dampsym's figure | checks that hold it | verdict |",
           "|---|---|---|---|---|---|---|---|"]
    out += [gallery_row(c, manifest["cases"].get(cid, []), paper) for paper, cid, c in rows]
    return "\n".join(out) + "\n"


def write_results(ctx: Ctx, results: List[Result]) -> int:
    """figures/manifest.json and figures.md from what was drawn; the exit status (2 if a series
    file was bad input, else 1 if a figure failed, else 0)."""
    order = {k: n for n, k in enumerate(KIND_ORDER)}
    manifest: Json = {"formats": ctx.formats, "cases": {}}
    status = 0
    for cid, kind, out, error, code in sorted(results, key=lambda r: (r[0], order[r[1]])):
        if error:
            status = max(status, code)
            print(f"plot.py: {cid} {kind}: {error}", file=sys.stderr)
        for f, caption, quantities in out:
            manifest["cases"].setdefault(cid, []).append(
                {"file": f, "caption": f"{cid}: {caption}", "kind": kind,
                 "quantities": quantities})
    figdir = os.path.join(ctx.out, "figures")
    # the workers listed their files as they drew them: the same manifest for any --jobs
    sio.write_manifest(figdir, sorted(set(sio.listed(figdir))))
    sio.write_atomic(os.path.join(figdir, "manifest.json"), json.dumps(manifest, indent=1).encode())
    sio.write_atomic(os.path.join(ctx.out, "figures.md"), gallery(ctx.report, manifest).encode())
    n = sum(len(v) for v in manifest["cases"].values())
    failed = sum(1 for r in results if r[3])
    print(f"plot.py: {n} figures, each as {' and '.join(ctx.formats)}, in {figdir}"
          + (f", {failed} failed" if failed else ""))
    return status


def load_report(path: str) -> Json:
    """report.json: a regular file of at most safeio.REPORT_LIMIT bytes, its case ids valid and
    the keys read here of the right types (safeio.validate_report); InputProblem otherwise."""
    try:
        report = sio.load_json(path, sio.REPORT_LIMIT)
    except FileNotFoundError:
        raise sio.InputProblem(f"{path}: no report to plot") from None
    problem = sio.validate_report(report, path)
    if problem:
        raise sio.InputProblem(problem)
    return dict(report)


def stop_handler(workers: List[int]) -> Callable[[int, Optional[FrameType]], None]:
    """SIGINT/SIGTERM: stop at once and quietly, with the workers (a file is renamed into place
    whole, so none is half-written); exit 130/143."""
    def on_stop(sig: int, _frame: Optional[FrameType]) -> None:
        for pid in workers:
            try:
                os.kill(pid, sig)
            except OSError:
                pass
        os._exit(128 + sig)
    return on_stop


def run(a: argparse.Namespace, formats: List[str], workers: List[int]) -> int:
    report = load_report(os.path.join(a.report_dir, "report.json"))
    ctx = Ctx(report=report, out=a.report_dir, formats=formats)
    figdir = os.path.join(a.report_dir, "figures")
    sio.own_directory(figdir)
    sio.remove_listed(figdir)  # the figures of earlier runs; nothing dampsym did not write
    cases = [i for i, c in enumerate(report["cases"]) if a.filter in c["id"]]
    return write_results(ctx, draw_all(ctx, cases, a.jobs, workers))


def main(argv: Optional[List[str]] = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("report_dir")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--format", default="png",
                    help="png, svg or pdf, or a comma list (the first of png/svg is embedded)")
    ap.add_argument("--filter", default="", help="only cases whose id contains this")
    ap.add_argument("--after-go", action="store_true",
                    help="read nothing until a line 'go' arrives on standard input; exit 0 "
                         "without drawing at its end (dampsym run --figures starts the script "
                         "with the run so that matplotlib is imported while the cases run)")
    a = ap.parse_args(argv)
    formats = a.format.split(",")
    if [f for f in formats if f not in ("png", "svg", "pdf")] or len(set(formats)) != len(formats):
        print(f"plot.py: --format {a.format}: give png, svg or pdf, each once", file=sys.stderr)
        return 2
    workers: List[int] = []
    signal.signal(signal.SIGINT, stop_handler(workers))
    signal.signal(signal.SIGTERM, stop_handler(workers))
    if a.after_go and sys.stdin.readline() != "go\n":
        return 0  # dampsym ended (or stopped) before report.json was written: nothing to draw
    try:
        return run(a, formats, workers)
    except sio.InputProblem as e:
        print(f"plot.py: {e}", file=sys.stderr)
        return 2
    except sio.OutputProblem as e:
        print(f"plot.py: {e}", file=sys.stderr)
        return 3
    except OSError as e:
        print(f"plot.py: {e.filename or a.report_dir}: {e.strerror}", file=sys.stderr)
        return 3
    except Exception as e:  # one line, never a traceback (a report the schema let through)
        print(f"plot.py: {a.report_dir}: internal error: {type(e).__name__}: {str(e)[:200]}",
              file=sys.stderr)
        return 3
