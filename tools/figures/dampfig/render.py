"""The drawing context and helpers shared by the figure kinds (matplotlib, Agg).

A Ctx holds everything one drawing process needs (the report, the output directory, the formats,
the styles of the case being drawn, the blank figures kept for reuse): nothing is kept in module
state, so two contexts never share a figure.

Cost (a run with --figures at most 2x one without): log axes get few ticks (matplotlib's tick
objects were most of the drawing time), lines are thinned to min/max per pixel column
(figdata.decimate_columns: the drawn line is the same), legends are placed at fixed spots, dense
lines are rasterised in svg/pdf, PNGs are encoded by figdata.encode_png from buffers reused across
figures, blank figures of a grid are reused (resized) and a figure resized to an earlier figure's
size gets that figure's Agg renderer (reuse_renderer, which a written figure gives back:
release_renderer), text is measured and drawn once per process
(textcache) and laid out once per process (layoutcache), ticks are copied from a template rather
than built (tickclone), an axis's ticks are updated once per draw (tickmemo) and a legend's entries
packed once per draw (legendmemo). Each of these modules is guarded by the SHA-256 of the
matplotlib 3.6.3 code it reasons about, and its test draws figures both ways and compares pixels."""

import ctypes
import io
import math
import os
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.ticker import (FixedLocator, FuncFormatter, MaxNLocator,  # noqa: E402
                               NullFormatter, NullLocator)

from . import mplsource  # noqa: E402
from . import figdata as fd  # noqa: E402
from . import layoutcache  # noqa: E402
from . import legendmemo  # noqa: E402
from . import safeio as sio  # noqa: E402
from . import textcache  # noqa: E402
from . import tickclone  # noqa: E402
from . import tickmemo  # noqa: E402

plt.rcParams.update({"font.size": 9, "axes.titlesize": 9, "legend.fontsize": 7,
                     "figure.dpi": 100, "savefig.dpi": 100, "axes.grid": True, "grid.alpha": 0.3,
                     "svg.fonttype": "none", "mathtext.default": "regular",
                     # blank figures are kept for reuse (up to 30), not leaked: no warning
                     "figure.max_open_warning": 0,
                     # a fixed title position: matplotlib otherwise measures every axes' tick
                     # labels to place its title (a sixth of the drawing time)
                     "axes.titley": 1.0, "axes.titlepad": 4.0})
# text measured, drawn and mathtext parsed once per process (textcache: the same pixels)
textcache.install()
# a text's lines aligned and rotated once per process (layoutcache: the same pixels)
layoutcache.install()
# an axis's ticks updated and measured once per draw, not twice (tickmemo: the same pixels)
tickmemo.install()
# an axis's new ticks copied from one it built (tickclone: the same pixels)
tickclone.install()
# a legend's entries packed once per draw (legendmemo: the same pixels)
legendmemo.install()

Json = Dict[str, Any]
# what a figure function returns per file: (file, caption, quantities drawn on its axes)
Drawn = Tuple[str, str, List[str]]
# pixel columns of a full-width axes: lines are thinned to min/max per column of this many
COLUMNS = 700
# blank figures kept for reuse at most (each holds its axes' memory)
KEEP_BLANK = 30
# Agg renderers kept for figures of the same size at most (reuse_renderer)
KEEP_RENDERERS = 8
# FigureCanvasAgg.get_renderer of matplotlib 3.6.3 (its SHA-256), which reuse_renderer reasons
# about: another version's canvases make their own renderers
GET_RENDERER_KNOWN = mplsource.source_hash(FigureCanvasAgg.get_renderer) == \
    "7469d922d24b685266f842b2d3bcd4589b001766216eeba38bf57d03eefc5eaa"
# a panel at least this tall (inches at 100 dpi: 250 px)
PANEL_H = 2.6


@dataclass
class Ctx:
    report: Json
    out: str
    formats: List[str]
    styles: Dict[str, fd.Style] = field(default_factory=dict)
    blank: Dict[Any, List[Any]] = field(default_factory=dict)
    # x ticks fixed by a figure (a convergence panel's step sizes), by id of their axes
    xticks: Dict[int, List[float]] = field(default_factory=dict)
    # the byte buffers png_bytes reuses from figure to figure
    scratch: List[Any] = field(default_factory=list)
    # Agg renderers of earlier figures by size (reuse_renderer), oldest first
    renderers: Dict[Any, Any] = field(default_factory=dict)

    def style(self, m: str) -> fd.Style:
        """(colour, marker, line style) of method m in the case being drawn."""
        return self.styles[m] if m in self.styles else fd.method_style(m)

    def primary_format(self) -> str:
        """The format report.md embeds: the first of png/svg asked for, else pdf (linked)."""
        return next((f for f in self.formats if f in ("png", "svg")), self.formats[0])


def title_of(case: Json, what: str) -> str:
    paper = fd.paper_figure(case)
    return f"{case['id']}: {what}" + (f"  [{paper}]" if paper else "")


SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def log_label(x: float, _pos: Optional[int] = None, digits: int = 2) -> str:
    """10⁻³, 2×10⁻³: plain text with Unicode superscripts (mathtext in tick labels was a third of
    the drawing time); the mantissa rounded to `digits` significant digits first, so that a label
    reads as the value it rounds to (0.9999999 and 1.000002 are both 10⁰, 9.99×10⁻³ is 10⁻²)."""
    if not x > 0:
        return ""
    e = math.floor(math.log10(x) + 1e-9)
    m = float(f"{x / 10 ** e:.{digits}g}")
    if m >= 10:
        m, e = m / 10, e + 1
    exp = "10" + str(e).translate(SUPERSCRIPT)
    if m == 1:
        return exp
    return f"{m:.0f}×{exp}" if m == round(m) else f"{m:.{digits}g}×{exp}"


def distinct_digits(ticks: Sequence[float]) -> int:
    """The fewest significant digits (at least 2) at which the ticks' log_labels all differ: two
    step sizes 2 % apart (a stability threshold's runs at 0.99 h* and 1.01 h*) were both
    labelled 1.3×10⁰."""
    want = len(set(ticks))
    return next((d for d in range(2, 17) if len({log_label(t, None, d) for t in ticks}) == want),
                17)


def log_formatter(ticks: Sequence[float]) -> Any:
    digits = distinct_digits(ticks)
    return FuncFormatter(lambda x, pos: log_label(x, pos, digits))


def pow10(e: int) -> str:
    return "10" + str(e).translate(SUPERSCRIPT)


def log_ticks(lo: float, hi: float) -> List[float]:
    """Labelled ticks of a log axis over [lo, hi]: every decade (every k-th beyond 6 decades);
    below 2 decades 1, 2, 5 × 10^k, finer mantissas when fewer than three fall inside."""
    k0, k1 = math.floor(math.log10(lo)), math.ceil(math.log10(hi))
    if math.log10(hi / lo) > 2:
        step = max(1, -(-(k1 - k0) // 6))
        return [10.0 ** k for k in range(k0, k1 + 1) if (k - k0) % step == 0]
    ticks: List[float] = []
    for subs in ((1, 2, 5), (1, 1.5, 2, 3, 5, 7), (1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6, 8)):
        ticks = [m * 10.0 ** k for k in range(k0, k1 + 1) for m in subs
                 if lo <= m * 10.0 ** k <= hi]
        if len(ticks) >= 3:
            break
    if len(ticks) < 2:  # a range narrower than 1, 1.2, 1.5, ... apart: nice values inside it,
        # when a few digits tell them apart (a range of 1 ± 1e-6 keeps its one label, 10⁰)
        nice = [t for t in MaxNLocator(nbins=3, steps=[1, 2, 2.5, 5, 10]).tick_values(lo, hi)
                if lo <= t <= hi and t > 0]
        if len(nice) >= 2 and distinct_digits(nice) <= MAX_TICK_DIGITS:
            ticks = nice
    return ticks


# significant digits at most of the nice ticks that label a log range narrower than 1, 1.2, 1.5, ...
MAX_TICK_DIGITS = 4
# tick label sizes at 9 pt and 100 dpi (pixels): width per character of log_label's text, height
TICK_CHAR_PX, TICK_HEIGHT_PX, TICK_GAP_PX = 7.4, 13.0, 6.0


def fit_ticks(ticks: List[float], lo: float, hi: float, pixels: float,
              horizontal: bool) -> List[float]:
    """The log ticks whose labels do not run into each other on an axis of `pixels` over
    [lo, hi]: from the first, each tick whose label clears the last kept one (by width on an x
    axis, height on a y axis) and TICK_GAP_PX; 1.5×10⁻⁶ and 2×10⁻⁶ 46 px apart overlapped."""
    if len(ticks) < 2 or not hi > lo or not pixels > 0:
        return ticks
    span = math.log10(hi) - math.log10(lo)
    digits = distinct_digits(ticks)

    def half(t: float) -> float:
        return (len(log_label(t, None, digits)) * TICK_CHAR_PX if horizontal
                else TICK_HEIGHT_PX) / 2

    kept = [ticks[0]]
    for t in ticks[1:]:
        apart = pixels * (math.log10(t) - math.log10(kept[-1])) / span
        if apart >= half(t) + half(kept[-1]) + TICK_GAP_PX:
            kept.append(t)
    return kept


def axis_pixels(ax: Any) -> Tuple[float, float]:
    """(width, height) of an axes in pixels, from its position (set before drawing)."""
    pos, fig = ax.get_position(), ax.get_figure()
    return pos.width * fig.bbox.width, pos.height * fig.bbox.height


def set_log_ticks(axis: Any, ticks: List[float]) -> None:
    """These labelled ticks on a log axis, no minor ticks."""
    axis.set_major_locator(FixedLocator(ticks))
    axis.set_major_formatter(log_formatter(ticks))
    axis.set_minor_locator(NullLocator())
    axis.set_minor_formatter(NullFormatter())


def tidy(fig: Any, xticks: Dict[int, List[float]]) -> None:
    """Before drawing: few, labelled ticks on every axis (xticks: those fixed by the figure),
    log ticks thinned so that their labels do not overlap."""
    for ax in fig.axes:
        if not ax.axison:
            continue
        width, height = axis_pixels(ax)
        if id(ax) in xticks and ax.get_xscale() == "log":
            x0, x1 = sorted(ax.get_xlim())
            set_log_ticks(ax.xaxis, fit_ticks(sorted(xticks[id(ax)]), x0, x1, width, True))
            lo, hi = sorted(ax.get_ylim())
            set_log_ticks(ax.yaxis, fit_ticks(log_ticks(lo, hi), lo, hi, height, False))
            continue
        for axis, scale, lim, px, horizontal in ((ax.xaxis, ax.get_xscale(), ax.get_xlim, width,
                                                  True),
                                                 (ax.yaxis, ax.get_yscale(), ax.get_ylim, height,
                                                  False)):
            lo, hi = sorted(lim())
            if scale == "log" and lo > 0 and hi > lo:
                set_log_ticks(axis, fit_ticks(log_ticks(lo, hi), lo, hi, px, horizontal))
            elif scale == "linear":
                axis.set_major_locator(MaxNLocator(nbins=5, steps=[1, 2, 2.5, 5, 10]))


def subplots(ctx: Ctx, nrows: int, ncols: int, figsize: Tuple[float, float],
             sharex: bool = False, sharey: Union[bool, str] = False) -> Tuple[Any, Any]:
    """A blank figure of this layout (reused from ctx.blank when one was recycled, resized to
    figsize: every figure sets its margins in figure fractions after drawing, layout())."""
    key = (nrows, ncols, sharex, sharey)
    if ctx.blank.get(key):
        fig, axs = ctx.blank[key].pop()
        fig.set_size_inches(figsize)
        return fig, axs
    fig, axs = plt.subplots(nrows, ncols, figsize=figsize, sharex=sharex, sharey=sharey,
                            squeeze=False)
    fig._dampsym_key = (key, axs)
    return fig, axs


def recycle(ctx: Ctx, fig: Any) -> None:
    """Empties a drawn figure back to its blank layout and keeps it in ctx for the next figure of
    that layout (falls back to closing it)."""
    key, axs = getattr(fig, "_dampsym_key", (None, None))
    release_renderer(ctx.renderers, fig)
    if key is None or sum(len(v) for v in ctx.blank.values()) >= KEEP_BLANK:
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
        # a scale or grid set again costs as much as a changed one (every shared axes and every
        # tick is updated): only what the figure changed is reset
        if ax.get_xscale() != "linear":
            ax.set_xscale("linear")
        if ax.get_yscale() != "linear":
            ax.set_yscale("linear")
        ax.set_aspect("auto")
        ax.axis("on")
        if getattr(ax, "_dampsym_relabelled", False):  # label_above_gaps: sharex's labels back
            ax.xaxis.set_tick_params(labelbottom=False)
            ax._dampsym_relabelled = False
        if not all(a._major_tick_kw.get("gridOn") for a in (ax.xaxis, ax.yaxis)):
            ax.grid(True)  # the default (rcParams above); the stability maps turn it off
        ax.set_autoscale_on(True)
        ax.relim()
        ax.xaxis.set_major_formatter(matplotlib.ticker.ScalarFormatter())
        ax.yaxis.set_major_formatter(matplotlib.ticker.ScalarFormatter())
    for lg in list(fig.legends):
        lg.remove()
    for t in list(fig.texts):  # the suptitle too
        t.remove()
    fig._suptitle = None
    ctx.blank.setdefault(key, []).append((fig, axs))


def label_boxes(ax: Any, renderer: Any) -> List[Any]:
    """The boxes (pixels) of an axes' tick labels and axis labels as last drawn."""
    out: List[Any] = []
    for axis in (ax.xaxis, ax.yaxis):
        ticks = tickmemo.drawn_tick_boxes(axis)
        if ticks is None:  # without the memo (another matplotlib): measured again
            box = axis.get_tightbbox(renderer)
            out += [box] if box is not None else []
            continue
        out += ticks
        if axis.label.get_visible() and axis.label.get_text():
            out.append(axis.label.get_window_extent(renderer))
    return out


def overhang(fig: Any) -> Tuple[float, float, float]:
    """Pixels by which the tick labels and axis labels of the last draw reach beyond the
    figure's left, right and bottom edges (0 where they are inside)."""
    renderer = fig.canvas.get_renderer()
    width = fig.bbox.width
    left = right = bottom = 0.0
    for ax in fig.axes:
        if not ax.axison or not ax.get_visible():
            continue
        for b in label_boxes(ax, renderer):
            if 0 < b.width < math.inf and 0 < b.height < math.inf:
                left, right, bottom = max(left, -b.x0), max(right, b.x1 - width), max(bottom,
                                                                                  -b.y0)
    return left, right, bottom


def legends_below(fig: Any) -> float:
    """Pixels by which a legend (of an axes or the figure) reaches below the figure's bottom
    edge after the last draw: the legends under the panels are placed from estimated sizes."""
    renderer = fig.canvas.get_renderer()
    legends = list(fig.legends) + [ax.get_legend() for ax in fig.axes if ax.get_legend()]
    return max([0.0] + [-lg.get_window_extent(renderer).y0 for lg in legends
                        if lg.get_visible()])


def grow_bottom(fig: Any, pixels: float) -> None:
    """The figure taller by `pixels` at the bottom, every axes keeping its size in pixels."""
    p, h = fig.subplotpars, fig.bbox.height
    new_h = h + pixels
    fig.set_size_inches(fig.get_figwidth(), new_h / fig.dpi)
    fig.subplots_adjust(bottom=(p.bottom * h + pixels) / new_h, top=(p.top * h + pixels) / new_h)


def draw_inside(fig: Any) -> None:
    """Draws the figure on its Agg canvas so that no tick label, axis label or legend is cut off:
    the margins are fixed fractions (layout(), without measuring text), so when a label reaches
    beyond the left, right or bottom edge (a one-column panel with wide log tick labels), that
    margin grows by the overhang and 4 px, and a legend below the bottom edge makes the figure
    taller by as much, and the figure is drawn again (a figure whose labels fit is drawn once,
    as before)."""
    fig.canvas.draw()
    for _ in range(3):
        left, right, bottom = overhang(fig)
        below = legends_below(fig)
        if max(left, right, bottom, below) <= 0.5:
            return
        p, w, h = fig.subplotpars, fig.bbox.width, fig.bbox.height
        fig.subplots_adjust(left=p.left + (left + 4) / w if left > 0.5 else p.left,
                            right=p.right - (right + 4) / w if right > 0.5 else p.right,
                            bottom=p.bottom + (bottom + 4) / h if bottom > 0.5 else p.bottom)
        if below > 0.5:
            grow_bottom(fig, below + 4)
        fig.canvas.draw()


def png_bytes(fig: Any, scratch: Optional[List[Any]] = None, drawn: bool = False) -> bytes:
    """The figure as savefig draws it (drawn: as the canvas holds it), encoded by
    figdata.encode_png: RGB when opaque. scratch (a list, kept by the caller across figures)
    holds two byte buffers reused for the copies: fresh 2-8 MB arrays for every figure cost their
    pages' faults again (a tenth of the process's page faults)."""
    if not drawn:
        fig.canvas.draw()
    rgba = np.asarray(fig.canvas.buffer_rgba())
    h, w, _ = rgba.shape
    channels = 3 if rgba[:, :, 3].min() == 255 else 4
    size = h * (1 + w * channels)
    if scratch is None:
        scratch = []
    if not scratch or scratch[0].size < size:
        scratch[:] = [np.empty(size, dtype=np.uint8), np.empty(size, dtype=np.uint8)]
    # each row prefixed by its filter byte 0 (figdata.encode_png's rows). numpy copies the
    # RGB(A) slice of the buffer slowly (an inner loop of 3 bytes: 10 ms for 2 million pixels);
    # one channel at a time into a packed image, then whole rows into place, takes 2 ms
    packed = scratch[1][:h * w * channels].reshape(h, w, channels)
    for k in range(channels):
        packed[:, :, k] = rgba[:, :, k]
    raw = scratch[0][:size].reshape(h, 1 + w * channels)
    raw[:, 0] = 0
    raw[:, 1:] = packed.reshape(h, w * channels)
    return fd.png_of_filtered_rows(raw.data, w, h, channels)


def drawn_texts(fig: Any) -> List[Any]:
    """The texts a recycled figure keeps, each holding the renderer of its last draw (Text.draw
    keeps it in _renderer): titles, axis labels, offset texts, tick labels."""
    out: List[Any] = list(fig.texts)
    for ax in fig.axes:
        out += [ax.title, ax._left_title, ax._right_title]
        for axis in (ax.xaxis, ax.yaxis):
            out += [axis.label, axis.offsetText]
            for t in (*axis.majorTicks, *axis.minorTicks):
                out += [t.label1, t.label2]
    return out


def release_renderer(pool: Dict[Any, Any], fig: Any) -> None:
    """After a figure is written: its Agg renderer goes back to the pool (reuse_renderer) and
    nothing of the figure holds it any more. A blank figure kept for reuse held its renderer
    until it was drawn again, and its texts held that of their last draw: 36 renderers (150 MB)
    were alive after 80 cases, each new one's buffer faulted in page by page. With KEEP_RENDERERS
    in the pool and the others freed (keep_freed_buffers), a new renderer mostly reuses freed
    memory: a worker's peak memory 310 -> 226 MB, the page faults of drawing the default suite
    144 000 -> 115 000."""
    canvas = fig.canvas
    if type(canvas) is not FigureCanvasAgg or not GET_RENDERER_KNOWN:
        return
    renderer = getattr(canvas, "renderer", None)
    if renderer is None or canvas._lastKey is None:
        return
    pool.pop(canvas._lastKey, None)
    pool[canvas._lastKey] = renderer
    del canvas.renderer  # get_renderer makes or reuse_renderer hands one before the next draw
    canvas._lastKey = None
    for t in drawn_texts(fig):
        t._renderer = None
    while len(pool) > KEEP_RENDERERS:
        pool.pop(next(iter(pool)))


def keep_freed_buffers() -> None:
    """glibc's malloc told to serve allocations up to 256 MB from its heap and to keep freed
    memory there (M_MMAP_THRESHOLD, M_TRIM_THRESHOLD), so that the buffers of a freed renderer
    (2-15 MB, mmap'd by default and unmapped when freed) serve the next one rather than being
    faulted in again (15-25 µs a page on the 2-core VM). With another C library: nothing."""
    mallopt = getattr(ctypes.CDLL(None), "mallopt", None)
    if mallopt is not None:
        mallopt(-3, 1 << 28)  # M_MMAP_THRESHOLD
        mallopt(-1, 1 << 30)  # M_TRIM_THRESHOLD


def reuse_renderer(pool: Dict[Any, Any], fig: Any) -> None:
    """Before a figure is drawn: its canvas gets a renderer of its size kept from an earlier
    figure, and keeps the one it has for a later figure, when its size changed (a new Agg
    renderer, a 2-15 MB buffer, cost 10 ms; the canvas clears it before drawing). At most
    KEEP_RENDERERS are kept. Only where FigureCanvasAgg.get_renderer is the one this reasons
    about (it reuses canvas.renderer while (width, height, dpi) equal canvas._lastKey)."""
    canvas = fig.canvas
    if type(canvas) is not FigureCanvasAgg or not GET_RENDERER_KNOWN:
        return
    w, h = fig.bbox.size
    key = (w, h, fig.dpi)
    if canvas._lastKey == key:
        return
    if canvas._lastKey is not None and getattr(canvas, "renderer", None) is not None:
        pool.pop(canvas._lastKey, None)
        pool[canvas._lastKey] = canvas.renderer
    hit = pool.pop(key, None)
    if hit is not None:
        canvas.renderer, canvas._lastKey = hit, key
    while len(pool) > KEEP_RENDERERS:
        pool.pop(next(iter(pool)))


def save(ctx: Ctx, fig: Any, case: Json, kind: str) -> str:
    """Writes the figure in every format as figures/<case id>-<kind>.<format> (the id through
    safeio.output_name; each name listed in the manifest before its file is written)."""
    name = sio.output_name(case["id"], f"-{kind}")
    tidy(fig, ctx.xticks)
    ctx.xticks.clear()
    reuse_renderer(ctx.renderers, fig)
    draw_inside(fig)  # the margins the labels need, for every format
    figdir = os.path.join(ctx.out, "figures")
    for i, ext in enumerate(ctx.formats):
        sio.note_written(figdir, f"{name}.{ext}")
        if ext == "png":  # the canvas holds draw_inside's drawing until another format draws
            data = png_bytes(fig, ctx.scratch, drawn=i == 0)
        else:
            buf = io.BytesIO()
            fig.savefig(buf, format=ext)
            data = buf.getvalue()
        sio.write_atomic(os.path.join(figdir, f"{name}.{ext}"), data)
    recycle(ctx, fig)
    return f"figures/{name}.{ctx.primary_format()}"


def dense(n: int) -> bool:
    """Whether a line of n points is rasterised in svg/pdf."""
    return n > 2000


def layout(fig: Any, bottom: float = 0.1, top: float = 0.9, left: float = 0.09,
           right: float = 0.98, hspace: float = 0.35, wspace: float = 0.3) -> None:
    """Fixed margins (tight_layout costs most of a figure's drawing time)."""
    fig.subplots_adjust(left=left, right=right, bottom=bottom, top=top, hspace=hspace,
                        wspace=wspace)


def method_handles(ctx: Ctx, methods: Sequence[str], with_marker: bool = True) -> List[Any]:
    """Legend entries of methods in their styles."""
    out = []
    for m in methods:
        c, mk, ls = ctx.style(m)
        out.append(Line2D([], [], color=c, ls=ls, marker=mk if with_marker else None, ms=4,
                          lw=1.2, label=m))
    return out


def sci_scale(values: Sequence[Sequence[float]]) -> int:
    """The power of ten k by which a linear panel's values are divided so that its tick labels
    need no '1e−5' offset text above the axes (which ran into the panel above): 0 when the
    largest |value| is between 10⁻² and 10⁴."""
    big = max((abs(v) for y in values for v in y if math.isfinite(v)), default=0.0)
    if big == 0.0:
        return 0
    k = math.floor(math.log10(big))
    return k if k < -2 or k > 3 else 0


def coincident(a: Tuple[Sequence[float], Sequence[float]],
               b: Tuple[Sequence[float], Sequence[float]], span: float, log: bool) -> float:
    """The largest difference between two drawn series (b interpolated onto a's times; in decades
    on a log panel) when it is below 1 % of the panel's span (the lines cannot be told apart),
    else -1."""
    ta, ya = np.asarray(a[0], float), np.asarray(a[1], float)
    tb, yb = np.asarray(b[0], float), np.asarray(b[1], float)
    if len(ta) < 2 or len(tb) < 2 or not span > 0:
        return -1.0
    if log:
        ya, yb = np.log10(ya), np.log10(yb)
    inside = (ta >= tb[0]) & (ta <= tb[-1])
    if inside.sum() < 2:
        return -1.0
    d = float(np.max(np.abs(ya[inside] - np.interp(ta[inside], tb, yb))))
    return d if d <= 0.01 * span else -1.0


def label_above_gaps(axs: Any, n: int, xlabel: str) -> None:
    """In a grid of panels sharing x whose last row is not full (n panels drawn), the panels
    above an empty slot keep their x tick labels and label: sharex hides them on every row but
    the last, which left those columns without a readable x axis."""
    rows, cols = axs.shape
    for i in range(n):
        if i + cols >= n and i // cols < rows - 1:
            ax = axs.flat[i]
            ax.xaxis.set_tick_params(labelbottom=True)
            ax.set_xlabel(xlabel)
            ax._dampsym_relabelled = True  # hidden again by recycle for the figure's next use
