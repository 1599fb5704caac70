"""Time series: one row per quantity, one column per group of at most six methods (a panel never
holds more), each panel at least 250 px tall; lines that cannot be told apart on a panel's scale
are named in a note on it; linear panels carry their power of ten in the label, not in an offset
text above the axes."""

import math
from typing import Any, List, Tuple

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


def flat_panel(ax: Any, ys: List[List[float]]) -> None:
    """A panel whose values are all equal to ~1e-9 (the momentum factor 1 of an undamped run):
    shown around its value with the spread written in the panel."""
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


def has_data(runs: List[Json], key: str, scale: str) -> bool:
    """Whether some run has something to draw under key."""
    for r in runs:
        y = (r["series"].get(key) or {}).get("y") or []
        if any(v > 0 for v in y) if scale == "log" else len(y) > 0:
            return True
    return False


def drift_lines(ctx: Ctx, ax: Any, case: Json, r: Json, t: List[float], y: List[float],
                colour: Any, first: bool) -> None:
    """d(t) at the maxima, the report's fitted line and the reference's d(t)."""
    _, mk, ls = ctx.style(r["method"])
    ax.plot(t, y, mk, color=colour, ms=2.5)
    slope = fd.drift_fit(case, r["method"], r["dt"])
    if slope is not None and len(t) > 1:
        b = sum(y) / len(y) - slope * sum(t) / len(t)
        ax.plot([t[0], t[-1]], [b + slope * t[0], b + slope * t[-1]], ls=ls, color=colour, lw=1,
                label=f"{r['method']} slope {slope:.3g}")
    ref = r["series"].get("dissipation-drift.d_reference")
    if ref and first:
        ax.plot(ref["t"], ref["y"], "-", color=REFERENCE_GREY, lw=0.8, label="reference")


def zero_note(runs: List[Json], key: str) -> str:
    """Runs whose series under key is exactly 0 wherever defined (nothing to draw on a log axis:
    cse-if's E_n on a Hill problem), named so that their absence is not read as missing data."""
    zero = [r["method"] for r in runs if (r["series"].get(key) or {}).get("y")
            and all(v == 0 for v in r["series"][key]["y"] if v is not None)]
    return f"exactly 0 at every point (not drawn on a log axis): {', '.join(zero)}" if zero else ""


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


def coincidence_text(lines: List[Line], log: bool) -> str:
    """The pairs of lines that coincide on the scale of their panel (one would hide the other),
    as 'a = b to d', or ''."""
    ys = [v for _, _, y in lines for v in y]
    if len(lines) < 2 or not ys:
        return ""
    lo, hi = min(ys), max(ys)
    span = (math.log10(hi) - math.log10(lo)) if log else hi - lo
    notes = []
    for i, a in enumerate(lines):
        for b in lines[i + 1:]:
            d = coincident((a[1], a[2]), (b[1], b[2]), span, log)
            if d >= 0:
                notes.append(f"{a[0]} = {b[0]} to {d:.1g}" + (" decades" if log else ""))
    return "coincide on this scale: " + "; ".join(notes[:3]) if notes else ""


def coincidence_note(ax: Any, lines: List[Line], log: bool, y: float = 0.04) -> None:
    """Names the coinciding pairs of lines in the panel (at its bottom or top right)."""
    text = coincidence_text(lines, log)
    if text:
        ax.text(0.99, y, text, transform=ax.transAxes, ha="right", fontsize=6.5,
                va="bottom" if y < 0.5 else "top", bbox={"facecolor": "w", "alpha": 0.8, "lw": 0})


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


def draw_panel(ctx: Ctx, ax: Any, case: Json, runs: List[Json], panel: Tuple[str, str, str],
               lines: List[Line], k: int, dts: List[float]) -> None:
    """One panel: the lines (divided by 10^k, which the label states), notes on coinciding and
    all-zero runs."""
    key, label, scale = panel
    by_label = {run_label(r, len(dts) > 1): r for r in runs}
    base = 0.0 if scale == "log" else offset_base([y for _, _, y in lines])
    if base:  # values 0.9900498... apart by 1e-8: drawn as their difference from the base
        k = sci_scale([[v - base for v in y] for _, _, y in lines])
    for i, (lab, t, y) in enumerate(lines):
        r = by_label[lab]
        c = run_colour(ctx, r, dts)
        yy = [(v - base) / 10.0 ** k for v in y]
        if key == "dissipation-drift.d":
            drift_lines(ctx, ax, case, r, t, yy, c, i == 0)
        else:
            ax.plot(t, yy, "-", color=c, lw=0.9, rasterized=dense(len(t)))
    if scale == "log" and lines:
        ax.set_yscale("log")
    elif lines and not base:
        flat_panel(ax, [[v / 10.0 ** k for v in y] for _, _, y in lines])
    coincidence_note(ax, lines, scale == "log")
    zero = zero_note(runs, key) if scale == "log" else ""
    if zero:
        ax.text(0.01, 0.96, zero, transform=ax.transAxes, va="top", fontsize=6.5,
                bbox={"facecolor": "w", "alpha": 0.8, "lw": 0})
    ax.set_ylabel(label + (f" − {base:.12g}" if base else "") + (f"  [×{pow10(k)}]" if k else ""),
                  fontsize=7.5)
    if scale != "log":
        ax.ticklabel_format(axis="y", useOffset=False)
    if key == "dissipation-drift.d":
        ax.legend(loc="upper right", ncol=2, fontsize=6)


def fig_series(ctx: Ctx, case: Json, ser: Json) -> List[Drawn]:
    runs = [r for r in ser["runs"] if r["series"]]
    panels = [p for p in fd.series_panels(ser, case) if has_data(runs, p[0], p[2])]
    keys = [p[0] for p in panels]
    # a measure of the whole state's absolute error is error.abs itself: drawn once
    same = "measure-pointwise.state.abs" in keys and "error.abs" in keys
    if same:
        panels = [p for p in panels if p[0] != "measure-pointwise.state.abs"]
    if not panels:
        return []
    dts = sorted({r["dt"] for r in runs})
    methods = [m for m in dict.fromkeys(r["method"] for r in runs)]
    cols = fd.groups(methods)
    width = 8.0 if len(cols) == 1 else 5.0 * len(cols)
    height = 1.3 + PANEL_H * len(panels)
    # one y scale per row (sharey="row"): the groups of a quantity compare at a glance
    fig, axs = subplots(ctx, len(panels), len(cols), (width, height), sharex=True,
                        sharey=("row" if len(cols) > 1 else False))
    for i, panel in enumerate(panels):
        per_group = [[r for r in runs if r["method"] in g] for g in cols]
        lines = [panel_lines(g, ser, panel[0], panel[2], dts, fd.growth_in_time(case))
                 for g in per_group]
        k = 0 if panel[2] == "log" else sci_scale([y for ls in lines for _, _, y in ls])
        for j, gruns in enumerate(per_group):
            draw_panel(ctx, axs[i, j], case, gruns, panel, lines[j], k, dts)
    for j, group in enumerate(cols):
        gruns = [r for r in runs if r["method"] in group]
        axs[-1, j].set_xlabel("time t" + (" (log: the claim is a growth rate in t)"
                                            if fd.growth_in_time(case) else ""))
        if fd.growth_in_time(case):
            axs[-1, j].set_xscale("log")
        handles = [Line2D([], [], color=run_colour(ctx, r, dts), lw=1.6,
                          label=run_label(r, len(dts) > 1)) for r in gruns]
        axs[0, j].legend(handles=handles, loc="lower center", bbox_to_anchor=(0.5, 1.0),
                         ncol=min(len(handles), 6 if len(dts) == 1 else 3), fontsize=7,
                         frameon=False)
    fig.suptitle(title_of(case, "time series"), y=1 - 0.1 / height, va="top")
    layout(fig, bottom=0.5 / height, top=1 - 0.8 / height, left=0.9 / width, hspace=0.12,
           wspace=0.28)
    quantities = [q for p in panels for q in fd.series_quantities(case, p[0])]
    if same:
        quantities += fd.series_quantities(case, "measure-pointwise.state.abs")
    return [(save(ctx, fig, case, "series"), "time series", quantities)]


