"""Time series: one row per quantity, one column per group of at most six methods (a panel never
holds more; the groups of the case's method order, failed runs included, which case_styles
coloured), each panel 260 px tall; lines that cannot be told apart on a panel's scale are named
in a note on it (every one of them, in groups); notes and a panel's legend sit in bands at the
bottom and top of the panel that the y limits keep free of data, wrapped to its width; a run that
failed (no series) is named in its group's legend with its status and step; a series of exact
zeros is drawn on a linear axis and said to be 0; linear panels carry their power of ten in the
label, not in an offset text above the axes."""

import math
from typing import Any, Dict, List, Optional, Tuple

import matplotlib.colors
from matplotlib.lines import Line2D

from . import figdata as fd
from .render import (COLUMNS, PANEL_H, Ctx, Drawn, Json, coincident, dense, layout, pow10, save,
                     sci_scale, subplots, title_of)
from .styles import REFERENCE_GREY

Line = Tuple[str, List[float], List[float]]  # label, t, y as drawn


def run_label(r: Json, multi_dt: bool) -> str:
    return f"{r['method']} h={r['dt']:g}" if multi_dt else r["method"]


def run_colour(ctx: Ctx, r: Json, dts: List[float]) -> Any:
    """The method's colour for the run of the smallest step size; each larger step size of the
    same method a lighter shade of it."""
    c = matplotlib.colors.to_rgb(ctx.style(r["method"])[0])
    if len(dts) < 2:
        return c
    f = 0.55 * dts.index(r["dt"]) / (len(dts) - 1)
    return tuple(x + (1 - x) * f for x in c)


def is_flat(ys: List[List[float]]) -> bool:
    """Whether a panel's values are all equal to ~1e-9 (the momentum factor 1 of an undamped run,
    a run at rest): drawn around their value with the spread written in the panel."""
    vals = [v for y in ys for v in y if math.isfinite(v)]
    if not vals:
        return False
    lo, hi = min(vals), max(vals)
    return hi - lo <= 1e-9 * max(abs(0.5 * (lo + hi)), 1e-300)


def flat_text(ys: List[List[float]]) -> str:
    vals = [v for y in ys for v in y if math.isfinite(v)]
    lo, hi = min(vals), max(vals)
    if lo == hi == 0.0:
        return "every value exactly 0"
    return f"all values within {hi - lo:.1e} of {0.5 * (lo + hi):.12g}"


def has_data(runs: List[Json], key: str, scale: str) -> bool:
    """Whether some run has something to draw under key (a series of exact zeros too: it is drawn
    on a linear axis and said to be 0, never left out)."""
    for r in runs:
        y = (r["series"].get(key) or {}).get("y") or []
        if any(v is not None and math.isfinite(v) for v in y):
            return True
    return False


def drift_lines(ctx: Ctx, ax: Any, case: Json, r: Json, t: List[float], y: List[float],
                colour: Any, first: bool) -> None:
    """d(t) at the maxima (the method's marker), the report's fitted line and the reference's
    d(t)."""
    _, mk, ls = ctx.style(r["method"])
    slope = fd.drift_fit(case, r["method"], r["dt"])
    ax.plot(t, y, mk, color=colour, ms=2.5)
    label = f"{r['method']} d(t) at the maxima of q"
    if slope is not None and len(t) > 1:
        b = sum(y) / len(y) - slope * sum(t) / len(t)
        ax.plot([t[0], t[-1]], [b + slope * t[0], b + slope * t[-1]], ls=ls, color=colour, lw=1)
        label = f"{r['method']} slope {slope:.3g}"
    # the legend's entry: the marker of the maxima and the style of the fitted line
    ax.plot([], [], ls=ls if slope is not None else "none", marker=mk, color=colour, ms=2.5,
            lw=1, label=label)
    ref = r["series"].get("dissipation-drift.d_reference")
    if ref and first:
        ax.plot(ref["t"], ref["y"], "-", color=REFERENCE_GREY, lw=0.8, label="reference")


def zero_note(runs: List[Json], key: str, multi_dt: bool) -> str:
    """Runs whose series under key is exactly 0 wherever defined (nothing to draw on a log axis:
    cse-if's E_n on a Hill problem), named so that their absence is not read as missing data."""
    zero = [run_label(r, multi_dt) for r in runs if (r["series"].get(key) or {}).get("y")
            and all(v == 0 for v in r["series"][key]["y"] if v is not None)]
    return f"exactly 0 at every point (not drawn on a log axis): {', '.join(zero)}" if zero else ""


def gap_note(runs: List[Json], key: str, multi_dt: bool) -> str:
    """Runs whose series under key has points without a value (skipped as non-finite by the
    C++ series: e^{2Γ} I_n / I_0 − 1 past its round-off resolution), named so that a line that
    stops is not read as the run stopping."""
    parts = []
    for r in runs:
        s = r["series"].get(key) or {}
        n = s.get("nonfinite", 0)
        if not (isinstance(n, int) and n > 0 and s.get("t")):
            continue
        where = f"after t = {s['t'][-1]:.3g}" if s.get("last") is None else f"at {n} points"
        parts.append(f"{run_label(r, multi_dt)} {where}")
    return f"no value (not drawn): {', '.join(parts)}" if parts else ""


def panel_lines(runs: List[Json], ser: Json, key: str, scale: str, dts: List[float],
                log_t: bool = False) -> List[Line]:
    """The runs' series under key, as they will be drawn (log: positive values only; thinned
    per pixel column of a linear time axis)."""
    t0, t1 = ser.get("t0", 0.0), ser.get("t_end", 1.0)
    out: List[Line] = []
    for r in runs:
        s = r["series"].get(key)
        if not s or not s["y"]:
            continue
        t, y = s["t"], s["y"]
        if scale == "log":
            pts = [(a, b) for a, b in zip(t, y) if b is not None and b > 0]
            t, y = [a for a, _ in pts], [b for _, b in pts]
        elif key != "dissipation-drift.d" and not log_t:
            t, y = fd.decimate_columns(t, [v if v is not None else float("nan") for v in y],
                                       t0, t1, COLUMNS)
        if t:
            out.append((run_label(r, len(dts) > 1), t, y))
    return out


def coincidence_text(lines: List[Line], log: bool, factor: float = 1.0) -> str:
    """The lines that coincide on the scale of their panel (one would hide the other), grouped:
    'a = b = c to d' (d the largest difference, times factor: the panel's power of ten), or ''."""
    ys = [v for _, _, y in lines for v in y if math.isfinite(v)]
    if len(lines) < 2 or not ys:
        return ""
    lo, hi = min(ys), max(ys)
    span = (math.log10(hi) - math.log10(lo)) if log else hi - lo
    pairs = []
    for i, a in enumerate(lines):
        for j in range(i + 1, len(lines)):
            d = coincident((a[1], a[2]), (lines[j][1], lines[j][2]), span, log)
            if d >= 0:
                pairs.append((i, j, d))
    notes = [" = ".join(lines[i][0] for i in members) +
             (" (identical)" if d == 0 else f" to {d * (1 if log else factor):.1g}" +
              (" decades" if log else ""))
             for members, d in fd.coincident_clusters(len(lines), pairs)]
    return "coincide on this scale: " + "; ".join(notes) if notes else ""


# text sizes (pixels at 100 dpi) the bands kept free for notes and legends are measured in
NOTE_FONT, NOTE_LINE_PX, NOTE_CHAR_PX = 6.5, 11.0, 5.0
LEGEND_ROW_PX, LEGEND_PAD_PX = 13.0, 10.0


def axes_px(ax: Any) -> Tuple[float, float]:
    """(width, height) of an axes in pixels, from its position in the figure (no drawing)."""
    pos, fig = ax.get_position(), ax.get_figure()
    return pos.width * fig.bbox.width, pos.height * fig.bbox.height


def place_note(ax: Any, texts: List[str], top: bool) -> float:
    """The notes wrapped to the axes' width at its bottom (or top), on a white ground; returns
    the pixels they take (the band the data must keep free)."""
    texts = [t for t in texts if t]
    if not texts:
        return 0.0
    width, _ = axes_px(ax)
    chars = int((width - 8) / NOTE_CHAR_PX)
    lines = [ln for t in texts for ln in fd.wrap_lines(t, chars)]
    ax.text(0.01, 0.985 if top else 0.015, "\n".join(lines), transform=ax.transAxes,
            ha="left", va="top" if top else "bottom", fontsize=NOTE_FONT, linespacing=1.15,
            bbox={"facecolor": "w", "alpha": 0.8, "lw": 0, "pad": 1.0})
    return len(lines) * NOTE_LINE_PX + 6


def coincidence_note(ax: Any, lines: List[Line], log: bool, top: bool = False,
                     factor: float = 1.0) -> float:
    """Names the coinciding lines in the panel (bottom or top band; their difference times
    factor, the panel's power of ten); returns its pixels."""
    return place_note(ax, [coincidence_text(lines, log, factor)], top)


def fit_bands(axes: List[Any], los: List[float], his: List[float], bottom_px: float,
              top_px: float, log: bool) -> None:
    """Limits of a row of panels (one shared y scale) that keep the bands of its notes and
    legends free of data."""
    if not los:
        return
    _, height = axes_px(axes[0])
    lim = fd.band_limits(min(los), max(his), bottom_px / height, top_px / height, log)
    for ax in axes:
        ax.set_ylim(*lim)


def offset_base(values: List[List[float]]) -> float:
    """The value a linear panel's values are drawn relative to when their spread is below 10⁻⁴
    of their size (else 0): their midpoint rounded to the spread's precision, so that the tick
    labels need no offset text (which ran into the panel above)."""
    vals = [v for y in values for v in y if math.isfinite(v)]
    if not vals:
        return 0.0
    lo, hi = min(vals), max(vals)
    mid, spread = 0.5 * (lo + hi), hi - lo
    if not spread > 0 or spread >= 1e-4 * abs(mid):
        return 0.0
    digits = max(0, -math.floor(math.log10(spread)) + 1)
    return round(mid, digits)


Notes = Dict[str, Any]  # per panel: "bottom", "top" (texts), "legend" (rows), "lo", "hi"


def draw_panel(ctx: Ctx, ax: Any, case: Json, runs: List[Json], panel: Tuple[str, str, str],
               lines: List[Line], k: int, dts: List[float]) -> Notes:
    """One panel: the lines (divided by 10^k, which the label states); returns what its notes
    say (coinciding, all-zero and flat runs) and the range of its data, placed by fig_series once
    the panels' sizes are known."""
    key, label, scale = panel
    log = scale == "log"
    by_label = {run_label(r, len(dts) > 1): r for r in runs}
    base = 0.0 if log else offset_base([y for _, _, y in lines])
    if base:  # values 0.9900498... apart by 1e-8: drawn as their difference from the base
        k = sci_scale([[v - base for v in y] for _, _, y in lines])
    drawn: List[Line] = []
    for i, (lab, t, y) in enumerate(lines):
        r = by_label[lab]
        c = run_colour(ctx, r, dts)
        yy = [(v - base) / 10.0 ** k for v in y]
        drawn.append((lab, t, yy))
        if key == "dissipation-drift.d":
            drift_lines(ctx, ax, case, r, t, yy, c, i == 0)
        else:
            ax.plot(t, yy, "-", color=c, lw=0.9, rasterized=dense(len(t)))
    if key == "dissipation-drift.d":
        ref = next((r["series"]["dissipation-drift.d_reference"] for r in runs
                    if r["series"].get("dissipation-drift.d_reference")), None)
        if ref:
            drawn.append(("reference", ref["t"], ref["y"]))
    if log and lines:
        ax.set_yscale("log")
    notes: Notes = {"bottom": [coincidence_text(drawn[:len(lines)], log, 10.0 ** k)],
                    "top": [zero_note(runs, key, len(dts) > 1) if log else "",
                            gap_note(runs, key, len(dts) > 1)], "legend": 0}
    flat = not log and is_flat([y for _, _, y in drawn])
    if flat:
        notes["bottom"].append(flat_text([y for _, _, y in drawn]))
    finite = [v for _, _, y in drawn for v in y if math.isfinite(v) and (v > 0 or not log)]
    if finite:
        notes["lo"], notes["hi"] = (min(finite), max(finite))
        if flat:
            notes["lo"] = notes["hi"] = 0.5 * (notes["lo"] + notes["hi"])
    ax.set_ylabel(label + (f" − {base:.12g}" if base else "") + (f"  [×{pow10(k)}]" if k else ""),
                  fontsize=7.5)
    if not log:
        ax.ticklabel_format(axis="y", useOffset=False, style="plain")
    if key == "dissipation-drift.d" and ax.get_legend_handles_labels()[0]:
        n = len(ax.get_legend_handles_labels()[0])
        ax.legend(loc="upper right", ncol=2, fontsize=6)
        notes["legend"] = -(-n // 2)
    return notes
def failed_of(ser: Json, key: Optional[str] = None) -> List[Json]:
    """The runs of a series file that failed (diverged, solve-failed, ...) and so have no series
    at all, or none under `key`."""
    return [r for r in ser["runs"] if r.get("status", "ok") != "ok"
            and (not r["series"] if key is None else key not in r["series"])]


def unseries_label(case: Json, r: Json) -> str:
    """A failed run (no series: diverged, solve-failed, ...) as its legend entry says it."""
    rr: Json = next((x for x in case.get("runs", []) if x.get("method") == r["method"]
                     and x.get("dt") == r["dt"]), {})
    step = rr.get("failed_at_step")
    at = f" at step {step}" if isinstance(step, int) else ""
    return f"{r['method']} h={r['dt']:g}: {rr.get('status', r.get('status', 'failed'))}{at}, " \
        "no series"


def legend_grid(labels: List[List[str]], col_px: float) -> Tuple[int, int]:
    """(columns, rows) of the legends above the groups' columns: as many columns as fit the
    group's width (entries of 7 pt text and a 35 px handle), the rows of the largest legend."""
    longest = max((len(x) for g in labels for x in g), default=1)
    ncol = max(1, int(col_px // (longest * 5.6 + 38)))
    return ncol, max((-(-len(g) // ncol) for g in labels if g), default=1)


def group_legend(ctx: Ctx, case: Json, ax: Any, runs: List[Json], failed: List[Json],
                 dts: List[float], ncol: int) -> None:
    """The legend above a group's column: its runs' colours, then its failed runs (no series)."""
    handles = [Line2D([], [], color=run_colour(ctx, r, dts), lw=1.6,
                      label=run_label(r, len(dts) > 1)) for r in runs]
    handles += [Line2D([], [], color=ctx.style(r["method"])[0], ls="none", marker="x", ms=5,
                       label=unseries_label(case, r)) for r in failed]
    ax.legend(handles=handles, loc="lower center", bbox_to_anchor=(0.5, 1.0), ncol=ncol,
              fontsize=7, frameon=False, borderaxespad=0.3)


def place_row(axes: List[Any], notes: List[Notes], log: bool) -> None:
    """The notes of a row's panels in their bands, and the row's limits keeping them free."""
    bottom = top = 0.0
    for ax, nt in zip(axes, notes):
        bottom = max(bottom, place_note(ax, nt["bottom"], False))
        top = max(top, place_note(ax, nt["top"], True),
                  nt["legend"] * LEGEND_ROW_PX + LEGEND_PAD_PX if nt["legend"] else 0.0)
    los = [nt["lo"] for nt in notes if "lo" in nt]
    fit_bands(axes, los, [nt["hi"] for nt in notes if "hi" in nt], bottom, top, log)


def fig_series(ctx: Ctx, case: Json, ser: Json) -> List[Drawn]:
    runs = [r for r in ser["runs"] if r["series"]]
    failed = failed_of(ser)
    every = fd.series_panels(ser, case)
    panels = [p for p in every if has_data(runs, p[0], p[2])]
    # quantities kept but undefined at every point (e^{2Γ} I_n / I_0 − 1 with I_0 = 0): named
    undefined = [p[1] for p in every if p not in panels]
    keys = [p[0] for p in panels]
    # a measure of the whole state's absolute error is error.abs itself: drawn once
    same = "measure-pointwise.state.abs" in keys and "error.abs" in keys
    if same:
        panels = [p for p in panels if p[0] != "measure-pointwise.state.abs"]
    if not panels:
        return []
    dts = sorted({r["dt"] for r in runs})
    # the groups of the case's methods (failed runs' too): the groups case_styles coloured
    cols = fd.groups(list(dict.fromkeys(r["method"] for r in ser["runs"])))
    per_group = [[r for r in runs if r["method"] in g] for g in cols]
    width = 8.0 if len(cols) == 1 else 5.0 * len(cols)
    ncol, rows = legend_grid([[run_label(r, len(dts) > 1) for r in g] +
                              [unseries_label(case, r) for r in failed if r["method"] in c]
                              for g, c in zip(per_group, cols)], 100 * (width - 1.2) / len(cols))
    top_in, bottom_in, hspace = 0.5 + 0.14 * rows, 0.5 + 0.2 * bool(undefined), 0.12
    height = top_in + bottom_in + PANEL_H * (len(panels) + hspace * (len(panels) - 1))
    # one y scale per row (sharey="row"): the groups of a quantity compare at a glance
    fig, axs = subplots(ctx, len(panels), len(cols), (width, height), sharex=True,
                        sharey=("row" if len(cols) > 1 else False))
    layout(fig, bottom=bottom_in / height, top=1 - top_in / height, left=0.9 / width,
           hspace=hspace, wspace=0.28)
    log_t = fd.growth_in_time(case)
    for i, panel in enumerate(panels):
        lines = [panel_lines(g, ser, panel[0], panel[2], dts, log_t) for g in per_group]
        scale = panel[2] if panel[2] != "log" or any(ls for ls in lines) else "linear"
        k = 0 if scale == "log" else sci_scale([y for ls in lines for _, _, y in ls])
        if scale != panel[2]:  # a log quantity exactly 0 everywhere: drawn as zeros, said so
            lines = [panel_lines(g, ser, panel[0], "linear", dts, log_t) for g in per_group]
        notes = [draw_panel(ctx, axs[i, j], case, g, (panel[0], panel[1], scale), lines[j], k,
                            dts) for j, g in enumerate(per_group)]
        place_row(list(axs[i]), notes, scale == "log")
    for j, group in enumerate(cols):
        axs[-1, j].set_xlabel("time t" + (" (log: the claim is a growth rate in t)"
                                            if log_t else ""))
        if log_t:
            axs[-1, j].set_xscale("log")
        group_legend(ctx, case, axs[0, j], per_group[j],
                     [r for r in failed if r["method"] in group], dts, ncol)
    fig.suptitle(title_of(case, "time series"), y=1 - 0.1 / height, va="top")
    if undefined:
        fig.text(0.01, 0.01, "not drawn, no finite value at any point: " + "; ".join(undefined),
                 fontsize=7, va="bottom")
    quantities = [q for p in panels for q in fd.series_quantities(case, p[0])]
    if same:
        quantities += fd.series_quantities(case, "measure-pointwise.state.abs")
    return [(save(ctx, fig, case, "series"), "time series", quantities)]
