"""The work-precision figure (docs/benchmarks.md "Work-precision") from the data of
bench/work_precision.py: one row per problem, error against CPU time (left) and against force
evaluations (right), log-log, every series a solver (dampsym's methods, Boost.Odeint, GSL, scipy),
the legend of the row beside it.

load() checks the data (InputProblem naming the file and the key: exit 2); draw() needs
matplotlib. Nothing here depends on a problem's or a solver's id: labels come from the data."""

import json
import math
import textwrap
from typing import Any, Dict, List, Optional, Tuple, Union

from . import safeio as sio
from .styles import MARKERS, PALETTE, STYLES

Json = Dict[str, Any]
SCHEMA = "dampsym-work-precision/1"
DATA_LIMIT = 16 << 20
# Line style by library: dampsym's methods solid, the peers each their own.
LIBRARY_LINES = {"dampsym": "-", "Boost.Odeint": "--", "GSL": "-.", "scipy": ":"}
# Nine colours for at most nine series a row: the palette and Tol's olive.
COLOURS = PALETTE + ["#999933"]


def _fail(path: str, key: str, why: str) -> sio.InputProblem:
    return sio.InputProblem(f"{path}: {key}: {why}")


def _num(v: Any, path: str, key: str, positive: bool = False) -> float:
    """A finite number (> 0 when positive, >= 0 otherwise), else InputProblem."""
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise _fail(path, key, f"expected a finite number, got {json.dumps(v)[:40]}")
    if v < 0 or (positive and v == 0):
        raise _fail(path, key, f"must be {'> 0' if positive else '>= 0'}, got {v}")
    return float(v)


def _obj(d: Any, key: str, kind: Union[type, Tuple[type, ...]], path: str, where: str) -> Any:
    if not isinstance(d, dict) or key not in d:
        raise _fail(path, f"{where}.{key}".lstrip("."), "missing")
    if not isinstance(d[key], kind):
        names = [k.__name__ for k in (kind if isinstance(kind, tuple) else (kind,))]
        raise _fail(path, f"{where}.{key}".lstrip("."), f"expected {' or '.join(names)}")
    return d[key]


def _check_point(pt: Any, path: str, where: str) -> None:
    if not isinstance(pt, dict):
        raise _fail(path, where, "expected an object")
    if "failed" in pt:
        _obj(pt, "failed", str, path, where)
        return
    _num(_obj(pt, "cpu_seconds", (int, float), path, where), path, f"{where}.cpu_seconds", True)
    _num(_obj(pt, "force_evals", int, path, where), path, f"{where}.force_evals", True)
    _num(_obj(pt, "error", (int, float), path, where), path, f"{where}.error")


def _check_problem(p: Any, path: str, where: str) -> None:
    for k in ("id", "case"):
        _obj(p, k, str, path, where)
    _num(_obj(p, "t_end", (int, float), path, where), path, f"{where}.t_end")
    ref = _obj(p, "reference", dict, path, where)
    _obj(ref, "name", str, path, f"{where}.reference")
    _num(_obj(ref, "error_estimate", (int, float), path, f"{where}.reference"), path,
         f"{where}.reference.error_estimate")
    fs = _obj(ref, "final_state", list, path, f"{where}.reference")
    for i, v in enumerate(fs):
        _num(abs(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else v, path,
             f"{where}.reference.final_state[{i}]")
    series = _obj(p, "series", list, path, where)
    if not series:
        raise _fail(path, f"{where}.series", "empty")
    for j, s in enumerate(series):
        sw = f"{where}.series[{j}]"
        for k in ("solver", "library", "kind"):
            _obj(s, k, str, path, sw)
        if s["kind"] not in ("fixed", "adaptive"):
            raise _fail(path, f"{sw}.kind", f"'fixed' or 'adaptive', got {s['kind']!r}")
        for i, pt in enumerate(_obj(s, "points", list, path, sw)):
            _check_point(pt, path, f"{sw}.points[{i}]")


def validate(data: Any, path: str) -> Json:
    """The data if it is a work-precision file, else InputProblem naming the key."""
    if not isinstance(data, dict):
        raise _fail(path, "(top level)", "expected an object")
    if data.get("schema") != SCHEMA:
        raise _fail(path, "schema", f"expected {SCHEMA!r}, got {data.get('schema')!r}")
    _obj(data, "machine", dict, path, "")
    problems = _obj(data, "problems", list, path, "")
    if not problems:
        raise _fail(path, "problems", "empty")
    for i, p in enumerate(problems):
        _check_problem(p, path, f"problems[{i}]")
    return data


def load(path: str) -> Json:
    try:
        raw = sio.read_bounded(path, DATA_LIMIT)
    except FileNotFoundError:
        raise sio.InputProblem(f"{path}: no such file") from None
    try:
        data = json.loads(raw)
    except ValueError as e:
        raise sio.InputProblem(f"{path}: not JSON ({e})") from None
    return validate(data, path)


def series_label(s: Json) -> str:
    """'<library> <solver without the library's prefix> (fixed h | adaptive)'."""
    lib, name = s["library"], s["solver"]
    short = name.split("-", 1)[1] if "-" in name and lib != "dampsym" else name
    return f"{lib} {short} ({'fixed h' if s['kind'] == 'fixed' else 'adaptive'})"


Style = Tuple[str, str, str]


def solver_styles(problems: List[Json]) -> Dict[str, Style]:
    """(colour, marker, line style) of every solver, the same in every row, and no colour or
    marker twice within a row: dampsym's methods their usual colour and marker (styles.STYLES)
    when free, every other solver the first colour and marker free in all its rows."""
    rows = [{s["solver"] for s in p["series"]} for p in problems]
    out: Dict[str, Style] = {}
    for p in problems:
        for s in p["series"]:
            name = s["solver"]
            if name in out:
                continue
            near = [out[o] for r in rows if name in r for o in r if o in out]
            pref = STYLES.get(name) if s["library"] == "dampsym" else None
            colours = ([PALETTE[pref[0]]] if pref else []) + COLOURS
            markers = ([pref[1]] if pref else []) + MARKERS
            used_c, used_m = {st[0] for st in near}, {st[1] for st in near}
            colour = next((c for c in colours if c not in used_c), colours[len(out) % 9])
            marker = next((m for m in markers if m not in used_m), markers[len(out) % 9])
            out[name] = (colour, marker, LIBRARY_LINES.get(s["library"], "-"))
    return out


def drawn_points(s: Json) -> List[Json]:
    """The points of a series that can be drawn on log axes (not failed, error > 0)."""
    return [p for p in s["points"] if "failed" not in p and p["error"] > 0]


def reference_floor(p: Json) -> Optional[float]:
    """The reference's certified error estimate relative to |z_ref(t_end)| (None for an exact
    reference): errors below it are not resolved."""
    ref = p["reference"]
    norm = math.hypot(*ref["final_state"]) if ref["final_state"] else 0.0
    if ref["error_estimate"] <= 0 or norm <= 0:
        return None
    return float(ref["error_estimate"]) / norm


def row_title(p: Json) -> str:
    """'<id>: case <case> (<params>), t_end = T'."""
    params = ", ".join(f"{k} = {v:g}" if isinstance(v, (int, float)) else f"{k} = {v}"
                       for k, v in sorted(p.get("params", {}).items()))
    return f"{p['id']}: case {p['case']} ({params}), t_end = {p['t_end']:g}"


def draw_row(axes: Any, legend_ax: Any, p: Json, styles: Dict[str, Style]) -> None:
    """One problem: error against CPU time (axes[0]) and force evaluations (axes[1]); the legend
    (and the reference) in legend_ax."""
    floor = reference_floor(p)
    handles = []
    for s in p["series"]:
        colour, marker, line = styles[s["solver"]]
        pts = drawn_points(s)
        err = [q["error"] for q in pts]
        for ax, key in zip(axes, ("cpu_seconds", "force_evals")):
            (h,) = ax.plot([q[key] for q in pts], err, color=colour, marker=marker,
                           linestyle=line, linewidth=1.6, markersize=6,
                           markerfacecolor=colour if s["kind"] == "fixed" else "white",
                           label=series_label(s))
        handles.append(h)
    for ax in axes:
        if floor is not None:
            handles_ref = ax.axhline(floor, color="#8c8c8c", linestyle=(0, (2, 2)), linewidth=1.2,
                                     label="reference's error estimate (relative)")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.grid(True, which="major", alpha=0.35)
        ax.tick_params(labelsize=10)
        ax.set_ylabel("relative error at t_end", fontsize=11)
    if floor is not None:
        handles.append(handles_ref)
    axes[0].set_xlabel("CPU time of one integration [s]", fontsize=11)
    axes[1].set_xlabel("force evaluations", fontsize=11)
    axes[0].set_title(row_title(p), fontsize=11, loc="left")
    legend_ax.axis("off")
    ref = "\n".join(textwrap.wrap("reference: " + p["reference"]["name"], 44))
    legend_ax.legend(handles=handles, loc="center left", fontsize=9, title=ref,
                     title_fontsize=9, frameon=False, borderaxespad=0.0)


def figure_notes(data: Json) -> str:
    """The footnote: what is measured, on which machine."""
    m = data["machine"]
    load = m.get("load_avg_cpp")
    load_txt = ", ".join(f"{x:.1f}" for x in load) if isinstance(load, list) else "?"
    return (f"One run, one machine: {m.get('cpu', '?')}, {m.get('cpus', '?')} CPUs, load average "
            f"{load_txt} (1/5/15 min). Time: CPU time of one integration, minimum over "
            "repetitions; C++: the bare loop (Google Benchmark), scipy: the solve_ivp call "
            "(includes its Python overhead). Error: |z - z_ref|_2 / |z_ref|_2 at t_end. "
            "Filled markers: fixed step h = h0/2^k; open: adaptive, rtol = 1e-3 ... 1e-12, "
            "atol = 1e-3 rtol." + "".join(
                f" {s['solver']} on {p['id']}: ladder stopped {s['ladder_stopped']}."
                for p in data["problems"] for s in p["series"]
                if isinstance(s.get("ladder_stopped"), str)))


def draw(data: Json, out: str) -> None:
    """The figure of all problems into `out` (format from its suffix)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rows = len(data["problems"])
    styles = solver_styles(data["problems"])
    height = 4.4 * rows + 1.8  # inches: 4.4 a row, 0.7 for the title, 1.1 for the notes
    fig = plt.figure(figsize=(15.0, height), dpi=100)
    grid = fig.add_gridspec(rows, 3, width_ratios=[1.0, 1.0, 0.72], wspace=0.25, hspace=0.45,
                            left=0.055, right=0.995, top=1 - 0.85 / height, bottom=1.5 / height)
    for r, p in enumerate(data["problems"]):
        axes = [fig.add_subplot(grid[r, 0]), fig.add_subplot(grid[r, 1])]
        draw_row(axes, fig.add_subplot(grid[r, 2]), p, styles)
    fig.suptitle("Work-precision: dampsym's conformal methods beside Boost.Odeint, GSL and scipy",
                 fontsize=13, y=1 - 0.12 / height, va="top")
    fig.text(0.055, 0.08 / height, "\n".join(textwrap.wrap(figure_notes(data), 175)), fontsize=9.5,
             va="bottom", ha="left")
    try:
        fig.savefig(out)
    except OSError as e:
        raise sio.OutputProblem(f"{out}: {e.strerror or e}") from None
    finally:
        plt.close(fig)
