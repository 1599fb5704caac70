#!/usr/bin/python3
"""Draws the figures of a dampsym report directory: the entry point `dampsym plot` and
`dampsym run --figures` run (the package dampfig beside this file does the work; its
cli module documents the arguments and exit statuses).

    /usr/bin/python3 tools/figures/plot.py REPORT_DIR [--jobs N] [--format png|svg|pdf[,...]]"""

import os
import signal
import sys
from types import FrameType
from typing import Optional


def on_stop(sig: int, _frame: Optional[FrameType]) -> None:
    """A signal while matplotlib is being imported (a second): stop quietly, 130/143."""
    os._exit(128 + sig)


<<<<<<< HEAD
# before the imports below (matplotlib takes a second): a signal while importing is quiet too
signal.signal(signal.SIGINT, on_stop)
signal.signal(signal.SIGTERM, on_stop)

import argparse  # noqa: E402
import gc  # noqa: E402
import io  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import multiprocessing  # noqa: E402
import textwrap  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import figdata as fd  # noqa: E402
import safeio as sio  # noqa: E402

import matplotlib  # noqa: E402
import numpy as np  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.colors  # noqa: E402
import matplotlib.ticker  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.ticker import (FixedLocator, FuncFormatter, LogLocator, MaxNLocator,  # noqa: E402
                               NullFormatter, NullLocator)

plt.rcParams.update({"font.size": 9, "axes.titlesize": 9, "legend.fontsize": 7,
                     "figure.dpi": 100, "savefig.dpi": 100, "axes.grid": True, "grid.alpha": 0.3,
                     "svg.fonttype": "none",
                     # a fixed title position: matplotlib otherwise measures every axes' tick
                     # labels to place its title (a sixth of the drawing time)
                     "axes.titley": 1.0, "axes.titlepad": 4.0})

REPORT: Dict[str, Any] = {}
OUT = ""
FORMATS = ["png"]
# pixel columns of a full-width axes (8 in at 100 dpi, less the margins): lines are thinned to
# min/max per column of this many
COLUMNS = 700


def title_of(case, what):
    paper = fd.paper_figure(case)
    return f"{case['id']}: {what}" + (f"  [{paper}]" if paper else "")


def primary_format():
    """The format report.md embeds: the first of png/svg asked for, else pdf (linked)."""
    return next((f for f in FORMATS if f in ("png", "svg")), FORMATS[0])


SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def log_label(x, _pos=None):
    """10⁻³, 2×10⁻³: plain text with Unicode superscripts (matplotlib's default "$10^{-3}$"
    goes through mathtext, whose parser was a third of the drawing time)."""
    if not x > 0:
        return ""
    e = math.floor(math.log10(x) + 1e-9)
    m = x / 10 ** e
    exp = "10" + str(e).translate(SUPERSCRIPT)
    if abs(m - 1) < 1e-6:
        return exp
    return f"{m:.0f}×{exp}" if abs(m - round(m)) < 1e-6 else f"{m:.2g}×{exp}"


LOG_LABEL = FuncFormatter(log_label)


def tidy_log_axis(axis, lo, hi):
    """Few ticks on a log axis: matplotlib's default puts 8 minor ticks in every decade, and its
    tick objects cost most of a figure's drawing time; beyond 1 decade the minor ticks carry no
    label (they overlapped: "3×10⁻³4×10⁻³")."""
    if not (lo > 0 and hi > lo):
        return
    decades = math.log10(hi / lo)
    axis.set_major_formatter(LOG_LABEL)
    axis.set_minor_formatter(NullFormatter())
    if decades > 3:
        axis.set_major_locator(LogLocator(base=10, numticks=7))
        axis.set_minor_locator(NullLocator())
    elif decades >= 1:
        axis.set_major_locator(LogLocator(base=10, numticks=7))
        axis.set_minor_locator(LogLocator(base=10, subs=(2.0, 5.0), numticks=12))
    else:  # less than a decade: 1, 2, 5 × 10^k, finer mantissas when fewer than two fall inside
        # (LogLocator then falls back to linear ticks whose labels overlapped: "1.8×10⁻⁴2×10⁻⁴")
        k0, k1 = math.floor(math.log10(lo)), math.ceil(math.log10(hi))
        for subs in ((1, 2, 5), (1, 1.5, 2, 3, 5, 7), (1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6, 8)):
            ticks = [m * 10.0 ** k for k in range(k0, k1 + 1) for m in subs
                     if lo <= m * 10.0 ** k <= hi]
            if len(ticks) >= 2:
                break
        axis.set_major_locator(FixedLocator(ticks))
        axis.set_minor_locator(NullLocator())


def tidy(fig):
    """Before drawing: few ticks on every axis (each tick is a set of matplotlib objects; they
    were most of the drawing time)."""
    for ax in fig.axes:
        if not ax.axison:
            continue
        for axis, scale, lim in ((ax.xaxis, ax.get_xscale(), ax.get_xlim),
                                 (ax.yaxis, ax.get_yscale(), ax.get_ylim)):
            if scale == "log":
                tidy_log_axis(axis, *sorted(lim()))
            elif scale == "linear":
                axis.set_major_locator(MaxNLocator(nbins=5, steps=[1, 2, 2.5, 5, 10]))


# Blank figures kept for reuse within a worker, by layout: a matplotlib axes and its tick objects
# cost more to build than most figures cost to draw, and two figures of one layout differ only in
# what recycle() removes.
BLANK: Dict[Any, List[Any]] = {}


def subplots(nrows, ncols, figsize, sharex=False, sharey=False):
    key = (nrows, ncols, tuple(round(x, 3) for x in figsize), sharex, sharey)
    if BLANK.get(key):
        return BLANK[key].pop()
    fig, axs = plt.subplots(nrows, ncols, figsize=figsize, sharex=sharex, sharey=sharey,
                            squeeze=False)
    fig._dampsym_key = (key, axs)
    return fig, axs


def recycle(fig):
    """Empties a drawn figure back to its blank layout and keeps it for the next figure of that
    layout (falls back to closing it)."""
    key, axs = getattr(fig, "_dampsym_key", (None, None))
    if key is None:
        plt.close(fig)
        return
    for ax in fig.axes:
        for a in (*ax.lines, *ax.collections, *ax.images, *ax.texts, *ax.patches):
            a.remove()
        if ax.get_legend():
            ax.get_legend().remove()
        ax.set_title("")
        ax.set_xlabel("")
        ax.set_ylabel("")
        ax.set_xscale("linear")
        ax.set_yscale("linear")
        ax.set_aspect("auto")
        ax.axis("on")
        ax.set_autoscale_on(True)
        ax.relim()
        ax.xaxis.set_major_formatter(matplotlib.ticker.ScalarFormatter())
        ax.yaxis.set_major_formatter(matplotlib.ticker.ScalarFormatter())
    for lg in list(fig.legends):
        lg.remove()
    for t in list(fig.texts):  # the suptitle too
        t.remove()
    fig._suptitle = None
    BLANK.setdefault(key, []).append((fig, axs))


def save(fig: Any, case: Dict[str, Any], kind: str) -> str:
    """Writes the figure in every format as figures/<case id>-<kind>.<format> (the id through
    safeio.output_name; each name listed in the manifest before its file is written)."""
    name = sio.output_name(case["id"], f"-{kind}")
    tidy(fig)
    figdir = os.path.join(OUT, "figures")
    for ext in FORMATS:
        sio.note_written(figdir, f"{name}.{ext}")
        if ext == "png":
            data = png_bytes(fig)
        else:
            buf = io.BytesIO()
            fig.savefig(buf, format=ext)
            data = buf.getvalue()
        sio.write_atomic(os.path.join(figdir, f"{name}.{ext}"), data)
    recycle(fig)
    return f"figures/{name}.{primary_format()}"


def png_bytes(fig: Any) -> bytes:
    """The figure as savefig draws it (same dpi and face colour: rcParams savefig.dpi = figure.dpi,
    facecolor "auto"), encoded by figdata.encode_png: RGB when every pixel is opaque."""
    fig.canvas.draw()
    rgba = np.asarray(fig.canvas.buffer_rgba())
    h, w, _ = rgba.shape
    pixels = rgba if (rgba[:, :, 3] != 255).any() else np.ascontiguousarray(rgba[:, :, :3])
    return bytes(fd.encode_png(pixels, w, h, pixels.shape[2]))


def dense(n):
    """Whether a line of n points is rasterised in svg/pdf (a vector file of 10⁴-point lines is
    large and slow to open; png ignores it)."""
    return n > 2000


def layout(fig, bottom=0.1, top=0.9, left=0.09, right=0.98, hspace=0.35, wspace=0.3):
    """Fixed margins (tight_layout costs most of a figure's drawing time)."""
    fig.subplots_adjust(left=left, right=right, bottom=bottom, top=top, hspace=hspace,
                        wspace=wspace)


# The styles of the case being drawn (draw_case sets them: figdata.case_styles).
CASE_STYLES: Dict[str, Tuple[str, str, str]] = {}


def style(m):
    """(colour, marker, line style) of method m (figdata.STYLES; case_styles for the others)."""
    return CASE_STYLES[m] if m in CASE_STYLES else fd.method_style(m)


def method_handles(methods, with_marker=True):
    """Legend entries of methods in their fixed styles."""
    out = []
    for m in methods:
        c, mk, ls = style(m)
        out.append(Line2D([], [], color=c, ls=ls, marker=mk if with_marker else None, ms=4,
                          lw=1.2, label=m))
    return out


def conv_axis(ax, data, ylabel):
    notes = []
    for m, d in data.items():
        c, mk, ls = style(m)
        pts = d["points"]
        dropped = {h for h, _ in d.get("dropped", [])}
        ax.plot([h for h, _ in pts], [e for _, e in pts], color=c, ls=ls, lw=0.8, alpha=0.5)
        kept = [(h, e) for h, e in pts if h not in dropped]
        gone = [(h, e) for h, e in pts if h in dropped]
        label = m
        if "fit" in d:
            f = d["fit"]
            label = f"{m} p = {f['slope']:.3f}"
            ax.plot(f["line_h"], f["line_error"], color=c, ls="-", lw=2.2, alpha=0.45)
        ax.plot([h for h, _ in kept], [e for _, e in kept], mk, color=c, label=label, ms=5)
        if gone:
            ax.plot([h for h, _ in gone], [e for _, e in gone], mk, mfc="none", mec=c, ms=6)
            for h, why in d["dropped"]:
                notes.append(f"{m} dt={h:g}: {why}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("step size h (time units of the problem)")
    ax.set_ylabel(ylabel)
    handles, labels = ax.get_legend_handles_labels()
    if notes:
        handles.append(Line2D([], [], marker="o", mfc="none", mec="k", ls="none"))
        labels.append("hollow: dropped from the fit")
    handles.append(Line2D([], [], color="k", ls="-", lw=2.2, alpha=0.45))
    labels.append("fitted slope over the window")
    ax.legend(handles, labels, loc="best", ncol=2 if len(labels) > 8 else 1, fontsize=6.5)
    return notes


def wp_axes(axs, data):
    for m, pts in data.items():
        c, mk, ls = style(m)
        pts = sorted(pts, key=lambda p: p["dt"])
        axs[0].plot([p["seconds"] for p in pts], [p["error"] for p in pts], marker=mk, ls=ls,
                    color=c, label=m, ms=4, lw=1)
        axs[1].plot([p["rhs_evals"] for p in pts], [p["error"] for p in pts], marker=mk, ls=ls,
                    color=c, label=m, ms=4, lw=1)
    for ax, xl in zip(axs, ["bare-loop wall time (s, min of N repetitions)",
                            "right-hand-side evaluations"]):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(xl)
        ax.set_ylabel("final error ‖z_N − z(t_end)‖")
        ax.set_title("work-precision")
    axs[1].legend(loc="best", fontsize=6.5, ncol=2 if len(data) > 8 else 1)


def fig_convergence(case, ser, timing):
    """Convergence (and the local error, B Fig 3.2), with work-precision beside it when the
    ladder was timed: one figure, so one save."""
    glob = fd.convergence_data(case)
    loc = fd.local_convergence_data(case)
    wp = fd.work_precision_data(case, timing)
    panels = [p for p in [(glob, "global error ‖z_N − z(t_end)‖ at t_end"),
                          (loc, "local error (one step)")] if p[0]]
    n = len(panels) + (2 if wp else 0)
    fig, axs = subplots(1, n, (5.2 * n, 4.8))
    notes = []
    for ax, (data, ylabel) in zip(axs[0], panels):
        notes += conv_axis(ax, data, ylabel)
        ax.set_title("convergence (error vs h, log–log)")
    if wp:
        wp_axes(axs[0][len(panels):], wp)
    fig.suptitle(title_of(case, "convergence" + (" and work-precision" if wp else "")))
    if notes:
        text = "; ".join(notes)
        if len(text) > 300:
            text = text[:297] + "…"
        fig.text(0.01, 0.01, "dropped: " + text, fontsize=6, wrap=True)
    layout(fig, bottom=0.17 if notes else 0.11, top=0.88, left=0.06 / n + 0.03, wspace=0.3)
    return [(save(fig, case, "convergence"), "convergence" + (" and work-precision" if wp else ""))]


def run_label(case, r, multi_dt):
    return f"{r['method']} h={r['dt']:g}" if multi_dt else r["method"]


def run_colour(r, dts):
    """The method's colour for the run of the smallest step size in dts; each larger step size of
    the same method a lighter shade of it (runs of one method at several h told apart)."""
    c = matplotlib.colors.to_rgb(style(r["method"])[0])
    steps = sorted(dts)
    if len(steps) < 2:
        return c
    f = 0.55 * steps.index(r["dt"]) / (len(steps) - 1)
    return tuple(x + (1 - x) * f for x in c)


def flat_panel(ax, ys):
    """A panel whose values are all equal to ~1e-9 (e.g. the momentum factor 1 of an undamped
    run): matplotlib would label it with an offset like "1e−12+1"; show it around its value with
    the spread written in the panel instead."""
    vals = [v for y in ys for v in y]
    if not vals:
        return
    lo, hi = min(vals), max(vals)
    mid = 0.5 * (lo + hi)
    if hi - lo > 1e-9 * max(abs(mid), 1e-300):
        return
    pad = max(abs(mid) * 1e-3, 1e-12)
    ax.set_ylim(mid - pad, mid + pad)
    ax.text(0.01, 0.06, f"all values within {hi - lo:.1e} of {mid:.12g}", transform=ax.transAxes,
            fontsize=6.5)


def has_data(runs, key, scale):
    """Whether some run has something to draw under key (a panel whose series are all empty,
    e.g. the momentum factor of a crystal at rest, where it is undefined, is left out)."""
    for r in runs:
        y = (r["series"].get(key) or {}).get("y") or []
        if any(v > 0 for v in y) if scale == "log" else len(y) > 0:
            return True
    return False


def fig_series(case, ser):
    runs = [r for r in ser["runs"] if r["series"]]
    panels = [p for p in fd.series_panels(ser) if has_data(runs, p[0], p[2])]
    if not panels:
        return []
    dts = sorted({r["dt"] for r in runs})
    multi_dt = len(dts) > 1
    colours = {}
    height = 1.1 + 1.9 * len(panels)
    fig, axs = subplots(len(panels), 1, (8, height), sharex=True)
    t0, t1 = ser.get("t0", 0.0), ser.get("t_end", 1.0)
    shown = []
    for ax, (key, label, scale) in zip(axs[:, 0], panels):
        logged = False
        drawn = []
        for r in runs:
            s = r["series"].get(key)
            if not s or not s["y"]:
                continue
            _, mk, ls = style(r["method"])
            c = run_colour(r, dts)
            t, y = s["t"], s["y"]
            if scale == "log":
                pts = [(a, b) for a, b in zip(t, y) if b > 0]
                if not pts:
                    continue
                t, y = [a for a, _ in pts], [b for _, b in pts]
                logged = True
            lab = run_label(case, r, multi_dt)
            if lab not in shown:
                shown.append(lab)
                colours[lab] = c
            if key == "dissipation-drift.d":
                ax.plot(t, y, mk, color=c, ms=2.5)
                slope = fd.drift_fit(case, r["method"], r["dt"])
                if slope is not None and len(t) > 1:
                    b = sum(y) / len(y) - slope * sum(t) / len(t)
                    ax.plot([t[0], t[-1]], [b + slope * t[0], b + slope * t[-1]], ls=ls,
                            color=c, lw=1, label=f"{r['method']} slope {slope:.3g}")
                ref = r["series"].get("dissipation-drift.d_reference")
                if ref and r is runs[0]:
                    ax.plot(ref["t"], ref["y"], "-", color="0.5", lw=0.8, label="reference")
            else:
                t, y = fd.decimate_columns(t, y, t0, t1, COLUMNS)
                # solid: a dashed line through a noisy series of 10³ points is unreadable (the
                # method's line style is used where lines are sparse: convergence, d(t) fits)
                ax.plot(t, y, "-", color=c, lw=0.9, rasterized=dense(len(t)))
            drawn.append(y)
        if logged:
            ax.set_yscale("log")
        else:
            flat_panel(ax, drawn)
        # long labels (invariant names) in two lines: one line ran into the next panel's
        ax.set_ylabel(textwrap.fill(label, 32), fontsize=7)
        if key == "dissipation-drift.d":
            ax.legend(loc="upper right", ncol=2, fontsize=6)
    axs[-1, 0].set_xlabel("time t (time units of the problem)")
    # one legend for the runs (the same in every panel), under the title
    handles = []
    for lab in shown:
        handles.append(Line2D([], [], color=colours[lab], ls="-", lw=1.6, label=lab))
    ncol = min(len(handles), 4 if multi_dt else 6)
    rows = max(1, -(-len(handles) // max(1, ncol)))
    top = 1 - (0.62 + 0.17 * rows) / height
    fig.legend(handles=handles, loc="upper center", ncol=max(1, ncol), fontsize=7,
               bbox_to_anchor=(0.5, 1 - 0.42 / height), frameon=False)
    fig.suptitle(title_of(case, "time series"), y=1 - 0.12 / height, va="top")
    layout(fig, bottom=0.5 / height, top=top, left=0.12, hspace=0.12)
    return [(save(fig, case, "series"), "time series")]


def orbit_coords(problem, states):
    """[(x, y, label)] to draw for a problem's states (columns of one numpy array: 10⁴ samples of
    36 numbers went through zip(*states) in a second)."""
    if not states:
        return []
    col = np.asarray(states, dtype=float).T
    if problem == "outer-solar-system":
        nb = len(col) // 6
        return [(col[3 * k], col[3 * k + 1], f"body {k}") for k in range(nb)]
    return [(col[0], col[1], "")]


AXES = {"kepler": ("q1", "q2"), "hill": ("q1", "q2"), "lotka-volterra": ("u", "v"),
        "pendulum": ("q (rad)", "p"), "oscillator": ("q", "p"),
        "outer-solar-system": ("x (AU)", "y (AU)"), "rigid-body": ("z1", "z2")}


def fig_orbit(case, ser):
    runs = [r for r in ser["runs"] if "orbit" in r["series"]]
    if not runs:
        return []
    problem = case["problem"]["id"]
    n = len(runs)
    cols = min(4, n)
    rows = (n + cols - 1) // cols
    # at least 7 in wide: the title names the case, the paper figure and what is grey
    fig, axs = subplots(rows, cols, (max(7.0, 3.6 * cols), 3.4 * rows + 0.6))
    for ax in axs.flat[n:]:
        ax.axis("off")
    xl, yl = AXES.get(problem, ("z1", "z2"))
    greys = set()
    for ax, r in zip(axs.flat, runs):
        c, _, _ = style(r["method"])
        ref = r["series"].get("orbit_reference")
        if ref and "same_as_run" in ref:  # written once per case (case_series_json)
            ref = ser["runs"][ref["same_as_run"]]["series"]["orbit_reference"]
        if ref:
            for x, y, _ in orbit_coords(problem, ref["states"]):
                ax.plot(x, y, "-", color="0.6", lw=2.2, alpha=0.6, rasterized=dense(len(x)))
        for x, y, lab in orbit_coords(problem, r["series"]["orbit"]["states"]):
            ax.plot(x, y, "-", color=c, lw=0.6, rasterized=dense(len(x)))
        ax.plot([r["series"]["orbit"]["states"][0][0]], [r["series"]["orbit"]["states"][0][1]],
                "k.", ms=5)
        if ref:
            greys.add("the exact solution" if ref.get("exact") else "the reference")
        ax.set_title(f"{r['method']} h={r['dt']:g}")
        ax.set_xlabel(xl)
        ax.set_ylabel(yl)
        if problem in ("kepler", "outer-solar-system", "hill"):
            ax.set_aspect("equal", adjustable="datalim")
    fig.suptitle(title_of(case, "orbits" + (f" (grey: {' / '.join(sorted(greys))})"
                                            if greys else "")))
    height = 3.4 * rows + 0.6
    layout(fig, bottom=0.5 / height, top=1 - 0.75 / height, left=0.75 / fig.get_figwidth(),
           hspace=0.45, wspace=0.35)
    return [(save(fig, case, "orbit"), "orbits")]


def fig_portrait(case, ser):
    """B Fig 5.10's right panels: the attractor diagnostic's probe as a point of its plane
    ((Re, Im) ψ(0, t) for the driven NLS) over the whole run, one panel per run; the first half
    (the transient, outside the attractor statistics) light, the second half in the method's
    colour."""
    runs = [r for r in ser["runs"] if "attractor.plane" in r["series"]]
    if not runs:
        return []
    n = len(runs)
    cols = min(3, n)
    rows = (n + cols - 1) // cols
    fig, axs = subplots(rows, cols, (max(7.0, 3.8 * cols), 3.6 * rows + 0.6), sharex=True,
                        sharey=True)
    for ax in axs.flat[n:]:
        ax.axis("off")
    t_half = 0.5 * (ser.get("t0", 0.0) + ser.get("t_end", 0.0))
    for ax, r in zip(axs.flat, runs):
        pl = r["series"]["attractor.plane"]
        c, _, _ = style(r["method"])
        pts = np.asarray(pl["points"], dtype=float).reshape(-1, 2)
        late = np.asarray(pl["t"], dtype=float) >= t_half
        # every output point joined; thinned records (stride > 1) as dots, whose joins would be
        # chords of the fast rotation
        thinned = pl.get("stride", 1) > 1
        for mask, col, lw in ((~late, "0.75", 0.4), (late, c, 0.5)):
            if mask.any():
                ax.plot(pts[mask, 0], pts[mask, 1], "." if thinned else "-", color=col, lw=lw,
                        ms=0.8, rasterized=dense(int(mask.sum())))
        ax.plot([0.0], [0.0], "k+", ms=6)
        ax.set_title(f"{r['method']} h={r['dt']:g}")
        ax.set_xlabel(pl["names"][0])
        ax.set_ylabel(pl["names"][1])
        ax.set_aspect("equal", adjustable="box")
    fig.suptitle(title_of(case, "probe in its plane (grey: first half of the run)"))
    height = 3.6 * rows + 0.6
    layout(fig, bottom=0.55 / height, top=1 - 0.75 / height, left=0.75 / fig.get_figwidth(),
           hspace=0.45, wspace=0.3)
    return [(save(fig, case, "portrait"), "probe portrait")]


MAP_CMAP = ListedColormap(["#c7e9c0", "#fdd49e", "#9ecae1", "#fb6a4a"])


def fig_stability(case, ser):
    data = fd.stability_data(case, ser)
    if not data:
        return []
    n = len(data)
    cols = min(3, n)
    rows = (n + cols - 1) // cols
    fig, axs = subplots(rows, cols, (4.6 * cols, 4.0 * rows + 0.9))
    for ax in axs.flat[n:]:
        ax.axis("off")
    for ax, (m, d) in zip(axs.flat, data.items()):
        if "map" in d:
            mp = d["map"]
            hs, gs = mp["h"], mp["gamma"]
            dh = (hs[1] - hs[0]) / 2 if len(hs) > 1 else 0.5
            dg = (gs[1] - gs[0]) / 2 if len(gs) > 1 else 0.5
            ax.imshow(mp["code"], origin="lower", aspect="auto", cmap=MAP_CMAP, vmin=-0.5,
                      vmax=3.5, interpolation="nearest",
                      extent=(hs[0] - dh, hs[-1] + dh, gs[0] - dg, gs[-1] + dg))
            fb = mp.get("F_formula_boundary")
            if fb:
                pts = [(h, g) for g, h in zip(fb["gamma"], fb["h"]) if h is not None]
                if pts:
                    ax.plot([h for h, _ in pts], [g for _, g in pts], "k-", lw=1.4,
                            label="F closed form (first h where it fails)")
        emp = [(h, g) for g, h in zip(d["gamma"], d["h_F_empirical"]) if h is not None]
        pbu = [(h, g) for g, h in zip(d["gamma"], d["h_power_unbounded"]) if h is not None]
        if emp:
            ax.plot([h for h, _ in emp], [g for _, g in emp], "wo", mec="k", ms=4,
                    label="empirical: first h with |½trM| ≥ e^{−γh}")
        if pbu:
            ax.plot([h for h, _ in pbu], [g for _, g in pbu], "x", color="#08306b", ms=5,
                    label="first h with M not power-bounded")
        ax.set_title(f"{m} (ω = {d['omega']:g})")
        ax.set_xlabel("step size h")
        ax.set_ylabel("damping γ")
    handles, labels = axs.flat[0].get_legend_handles_labels()
    from matplotlib.patches import Patch
    handles += [Patch(color=MAP_CMAP(i), label=t) for i, t in
                enumerate(["F holds, power-bounded", "F fails, power-bounded",
                           "F holds, not power-bounded", "F fails, not power-bounded"])]
    fig.legend(handles=handles, loc="lower center", ncol=3, fontsize=7)
    fig.suptitle(title_of(case, "stability map in (h, γ)"))
    height = 4.0 * rows + 0.9
    layout(fig, bottom=1.2 / height, top=1 - 0.6 / height, left=0.07, hspace=0.4, wspace=0.3)
    return [(save(fig, case, "stability"), "stability map")]


def fig_poincare(case, ser):
    runs = [r for r in ser["runs"] if "poincare" in r["series"]]
    if not runs:
        return []
    ref = next((r["series"]["poincare_reference"] for r in runs
                if "poincare_reference" in r["series"]), None)
    panels = ([("reference (certified GSL)", ref, "0.2")] if ref else []) + [
        (f"{r['method']} h={r['dt']:g}", r["series"]["poincare"], style(r["method"])[0])
        for r in runs]
    cols = min(3, len(panels))
    rows = (len(panels) + cols - 1) // cols
    fig, axs = subplots(rows, cols, (4.2 * cols, 3.8 * rows + 0.5), sharex=True, sharey=True)
    for ax in axs.flat[len(panels):]:
        ax.axis("off")
    for ax, (name, pts, c) in zip(axs.flat, panels):
        ax.scatter(pts["q"], pts["p"], s=0.6, color=c, lw=0, rasterized=True)
        ax.set_title(name)
        ax.set_xlabel("q mod 2π (rad)")
        ax.set_ylabel("p")
    fig.suptitle(title_of(case, "Poincaré section at t = t0 + kT"))
    height = 3.8 * rows + 0.5
    layout(fig, bottom=0.5 / height, top=1 - 0.6 / height, left=0.08, hspace=0.35, wspace=0.15)
    return [(save(fig, case, "poincare"), "Poincaré sections")]


def fig_snapshots(case, ser):
    """B Fig 5.4: the field u(x) of each run and the PDE's own solution (grey) at the output
    times, one panel per time (series "snapshots" of the pde-error diagnostic)."""
    runs = [r for r in ser["runs"] if r["series"].get("snapshots", {}).get("t")]
    if not runs:
        return []
    first = runs[0]["series"]["snapshots"]
    times, n = first["t"], len(first["t"])
    cols = min(5, n)
    rows = (n + cols - 1) // cols
    fig, axs = subplots(rows, cols, (3.0 * cols + 0.6, 2.8 * rows + 0.9), sharex=True,
                        sharey=True)
    for ax in axs.flat[n:]:
        ax.axis("off")
    for k, ax in enumerate(axs.flat[:n]):
        x = first["x"] or list(range(len(first["pde"][k])))
        ax.plot(x, first["pde"][k], "-", color="0.6", lw=2.6, alpha=0.7)
        for r in runs:
            sn = r["series"]["snapshots"]
            if k < len(sn["u"]):
                c, _, ls = style(r["method"])
                ax.plot(x, sn["u"][k], ls if ls != ":" else "--", color=c, lw=1.0)
        ax.set_title(f"t = {times[k]:g}")
        ax.set_xlabel("x")
        if k % cols == 0:
            ax.set_ylabel("u(x, t)")
    handles = [Line2D([], [], color="0.6", lw=2.6, alpha=0.7, label="solution of the PDE")]
    handles += method_handles([r["method"] for r in runs], with_marker=False)
    fig.legend(handles=handles, loc="upper center", ncol=min(6, len(handles)),
               bbox_to_anchor=(0.5, 1 - 0.45 / (2.8 * rows + 0.9)), frameon=False, fontsize=8)
    fig.suptitle(title_of(case, "snapshots"))
    height = 2.8 * rows + 0.9
    layout(fig, bottom=0.5 / height, top=1 - 0.85 / height, left=0.55 / fig.get_figwidth(),
           hspace=0.35, wspace=0.12)
    return [(save(fig, case, "snapshots"), "snapshots")]


def plan(case, ser):
    """The kinds of figure to draw for a case: those its data allows, restricted to its
    "figures" key when it has one (figdata.case_figure_kinds)."""
    kinds = []
    mm = case.get("method_metrics", {})
    if len(case["dt_ladder"]) >= 2 and (fd.convergence_data(case)
                                        or fd.local_convergence_data(case)):
        kinds.append("convergence")
    if ser and fd.series_panels(ser):
        kinds.append("series")
    wanted = fd.case_figure_kinds(case)
    # a run keeps orbit samples only for a case that draws them (the problem's default or the
    # case's "figures" key: the runner's case_draws_orbit)
    if ser and any("orbit" in r["series"] for r in ser["runs"]):
        kinds.append("orbit")
    if ser and any("poincare" in r["series"] for r in ser["runs"]):
        kinds.append("poincare")
    if ser and any(r["series"].get("snapshots", {}).get("t") for r in ser["runs"]):
        kinds.append("snapshots")
    if ser and any("attractor.plane" in r["series"] for r in ser["runs"]):
        kinds.append("portrait")
    if any("stability-sweep" in v for v in mm.values()):
        kinds.append("stability")
    if wanted is None:
        return kinds, []
    return [k for k in kinds if k in wanted], sorted(wanted - set(kinds))


DRAW = {"convergence": lambda c, s, i: fig_convergence(c, s, fd.case_timing(REPORT, i)),
        "series": lambda c, s, i: fig_series(c, s), "orbit": lambda c, s, i: fig_orbit(c, s),
        "stability": lambda c, s, i: fig_stability(c, s),
        "poincare": lambda c, s, i: fig_poincare(c, s),
        "snapshots": lambda c, s, i: fig_snapshots(c, s),
        "portrait": lambda c, s, i: fig_portrait(c, s)}


def case_methods(case):
    """The case's methods in the order of its runs (each once)."""
    out = []
    for r in case.get("runs", []):
        if r.get("method") and r["method"] not in out:
            out.append(r["method"])
    return out


# What draw_case returns per figure: (case id, kind, [(file, caption)], error or None, the exit
# status the error calls for: 1 a figure failed, 2 bad input).
Result = Tuple[str, str, List[Tuple[str, str]], Optional[str], int]


def draw_case(i: int) -> List[Result]:
    """Every figure of case i, in a worker: reads only this case's series file (bounded:
    safeio.SERIES_LIMIT). An output that cannot be written (OutputProblem) ends the script."""
    case = REPORT["cases"][i]
    CASE_STYLES.clear()
    CASE_STYLES.update(fd.case_styles(case_methods(case)))
    try:
        ser = fd.load_series(OUT, case["id"])
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
    for kind in kinds:
        try:
            out.append((case["id"], kind, DRAW[kind](case, ser, i), None, 0))
        except sio.OutputProblem:
            raise
        except Exception as e:  # one bad figure must not hide the others; reported, exit 1
            plt.close("all")
            BLANK.clear()
            out.append((case["id"], kind, [], f"{type(e).__name__}: {e}", 1))
    return out


def gallery(manifest):
    """figures.md: every case that names a paper figure or table, with its figures and checks."""
    rows = []
    for c in REPORT["cases"]:
        paper = fd.paper_figure(c)
        if not paper:
            continue
        figs = manifest["cases"].get(c["id"], [])
        checks = c["checks"]
        passed = sum(1 for k in checks if k["passed"])
        verdict = ("no checks" if not checks else
                   "pass" if passed == len(checks) else f"**FAIL** ({len(checks) - passed})")
        names = []
        for k in checks:
            if k["name"] not in names:
                names.append(k["name"])
        held = "; ".join(names[:3]) + (f"; … ({len(names) - 3} more)" if len(names) > 3 else "")
        imgs = " ".join(f'<a href="{f["file"]}"><img src="{f["file"]}" width="220" '
                        f'alt="{f["caption"]}"></a>' for f in figs) or "(no figure: " \
            "the case reduces to numbers, see report.md)"
        claim = c["title"].replace("|", "/")
        rows.append((paper, c["id"], claim, imgs, held.replace("|", "/"), verdict))
    rows.sort()
    out = ["# Paper figures and tables reproduced by dampsym", "",
           "Every case whose source names a figure or table of F (Floyd 2014), B (Bhatt 2016), "
           "HLW (Hairer–Lubich–Wanner ch. I) or BS (Butcher's slides) — docs/references.md. "
           "Drawn by `dampsym plot` (tools/figures/plot.py) from report.json and the run's "
           "series files; the case section in [report.md](report.md) has the full checks.", "",
           "| paper | case | what the paper claims (case title) | dampsym's figure | checks that "
           "hold it | verdict |", "|---|---|---|---|---|---|"]
    for paper, cid, claim, imgs, held, verdict in rows:
        out.append(f"| {paper} | [{cid}](report.md#case-{cid}) | {claim} | {imgs} | {held} | "
                   f"{verdict} |")
    return "\n".join(out) + "\n"


def load_report(path: str) -> Dict[str, Any]:
    """report.json: a regular file of at most safeio.REPORT_LIMIT bytes, its case ids valid (as
    a case file's) and the keys plot.py reads of each case of the right types
    (safeio.validate_report). InputProblem naming the file and the key."""
    try:
        report = sio.load_json(path, sio.REPORT_LIMIT)
    except FileNotFoundError:
        raise sio.InputProblem(f"{path}: no report to plot") from None
    problem = sio.validate_report(report, path)
    if problem:
        raise sio.InputProblem(problem)
    return report


def series_cost(i: int) -> int:
    """Largest series file first (with a ladder's convergence figure), so that the workers
    finish together."""
    case = REPORT["cases"][i]
    try:
        size = os.lstat(fd.series_path(OUT, case["id"])).st_size
    except OSError:
        size = 0
    return size + 200000 * (len(case["dt_ladder"]) >= 2)


def draw_all(cases: List[int], jobs: int) -> List[Result]:
    # Python's cyclic garbage collector ran every 700 allocations and scanned matplotlib's many
    # artist objects again and again (a tenth of the drawing time): the objects built so far
    # (modules, report.json) are frozen out of its scans, and it runs every 50 000 allocations
    # (the same peak memory, ~190 MB per process, measured).
    gc.freeze()
    gc.set_threshold(50000, 50, 100)
    cases.sort(key=lambda i: -series_cost(i))
    if jobs > 1 and len(cases) > 1:
        with multiprocessing.get_context("fork").Pool(min(jobs, len(cases))) as pool:
            return [r for rs in pool.imap_unordered(draw_case, cases, chunksize=1) for r in rs]
    return [r for i in cases for r in draw_case(i)]


def write_results(results: List[Result]) -> int:
    """figures/manifest.json and figures.md from what was drawn; the exit status (2 if a series
    file was bad input, else 1 if a figure failed, else 0)."""
    order = {k: n for n, k in enumerate(["convergence", "series", "snapshots", "orbit",
                                         "portrait", "poincare", "stability"])}
    manifest: Dict[str, Any] = {"formats": FORMATS, "cases": {}}
    status = 0
    for cid, kind, out, error, code in sorted(results, key=lambda r: (r[0], order[r[1]])):
        if error:
            status = max(status, code)
            print(f"plot.py: {cid} {kind}: {error}", file=sys.stderr)
        for f, caption in out:
            manifest["cases"].setdefault(cid, []).append(
                {"file": f, "caption": f"{cid}: {caption}", "kind": kind})
    figdir = os.path.join(OUT, "figures")
    # the workers listed their files as they drew them: the same manifest for any --jobs
    sio.write_manifest(figdir, sorted(set(sio.listed(figdir))))
    sio.write_atomic(os.path.join(figdir, "manifest.json"), json.dumps(manifest, indent=1).encode())
    sio.write_atomic(os.path.join(OUT, "figures.md"), gallery(manifest).encode())
    n = sum(len(v) for v in manifest["cases"].values())
    failed = sum(1 for r in results if r[3])
    print(f"plot.py: {n} figures, each as {' and '.join(FORMATS)}, in "
          f"{os.path.join(OUT, 'figures')}"
          + (f", {failed} failed" if failed else ""))
    return status


def main() -> int:
    global REPORT, OUT, FORMATS
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("report_dir")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--format", default="png",
                    help="png, svg or pdf, or a comma list (the first of png/svg is embedded)")
    ap.add_argument("--filter", default="", help="only cases whose id contains this")
    a = ap.parse_args()
    OUT = a.report_dir
    FORMATS = a.format.split(",")
    bad = [f for f in FORMATS if f not in ("png", "svg", "pdf")]
    if bad or len(set(FORMATS)) != len(FORMATS):
        print(f"plot.py: --format {a.format}: give png, svg or pdf, each once", file=sys.stderr)
        return 2
    try:
        REPORT = load_report(os.path.join(OUT, "report.json"))
        figdir = os.path.join(OUT, "figures")
        sio.own_directory(figdir)
        sio.remove_listed(figdir)  # the figures of earlier runs; nothing dampsym did not write
        cases = [i for i, c in enumerate(REPORT["cases"]) if a.filter in c["id"]]
        return write_results(draw_all(cases, a.jobs))
    except sio.InputProblem as e:
        print(f"plot.py: {e}", file=sys.stderr)
        return 2
    except sio.OutputProblem as e:
        print(f"plot.py: {e}", file=sys.stderr)
        return 3
    except OSError as e:
        print(f"plot.py: {e.filename or OUT}: {e.strerror}", file=sys.stderr)
        return 3
    except Exception as e:  # one line, never a traceback (a report the schema let through)
        print(f"plot.py: {OUT}: internal error: {type(e).__name__}: {str(e)[:200]}",
              file=sys.stderr)
        return 3


=======
>>>>>>> fg
if __name__ == "__main__":
    signal.signal(signal.SIGINT, on_stop)
    signal.signal(signal.SIGTERM, on_stop)
    # the script's directory is on sys.path when run as a script: the package imports plainly
    from dampfig.cli import main
    sys.exit(main())
