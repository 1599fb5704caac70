"""New ticks copied from one built by matplotlib (the cost of --figures, docs/reports.md
"Cost"): the same pixels, without building every tick from scratch.

matplotlib 3.6 builds a Tick (Axis._get_tick) from the axis's tick keywords and rcParams: three
Line2D and two Text artists, each set property by property (0.3-0.6 ms a tick); an axis builds its
first tick when created and another whenever a draw needs more than it has, 1543 ticks for the
default suite's figures (a tenth of the drawing time). Two XTicks (or YTicks) built from the same
keywords and rcParams differ only in what XTick/YTick.__init__ take from their axes: the tick's
axes and figure, its lines' transforms (the axes' tick1, tick2 and grid transforms) and its
labels' transforms and alignments (get_xaxis_text1_transform etc. of the axes at the tick's pad).
install() wraps Axis._get_tick so that for an XAxis or YAxis a tick is built as before only when
no template of that kind of axis (and axes, major or minor) was built from the same keywords and
rcParams (a snapshot of every value); it is kept untouched as a template, and every tick handed
out is a copy of it placed on its own axes (place(): what __init__ takes from the axes, asked of
the axes again). A copy gets each artist's attribute dictionary copied, with the state an artist
owns made afresh (its callback registry, its sticky edges, a Text's FontProperties, which setters
change in place); everything else it shares with the template is never changed in place by
matplotlib (numbers, strings, tuples, the data arrays and paths, which set_data and recache
replace, the MarkerStyle, which set_marker replaces). Unlike a built tick, a copy does not mark
its axes stale (only interactive redrawing reads that). 12 ticks are built for the default
suite. tests/test_tickclone.py draws figures both ways and compares the pixels, and compares a
copy with a tick built on the same axes attribute by attribute.

Applied only to the matplotlib versions whose constructors it was written against (their code is
checked); any other version builds every tick as before."""

import functools
from typing import Any, Callable, Dict, List, Optional, Tuple

import matplotlib as mpl
from matplotlib import artist as martist
from matplotlib import axis as maxis
from matplotlib import cbook
from matplotlib import lines as mlines
from matplotlib import text as mtext

from . import mplsource

# The SHA-256 of the sources this reasons about (matplotlib 3.6.3): what a tick is built from and
# which of its artists' attributes are objects of their own.
SOURCES_SHA256 = {
    "Axis._get_tick": "35bb40d361b6c1e75ebe5cb39d25def18c81f41d5d1f6c5e8406d892480c4c7b",
    "Tick.__init__": "d1a87c730e84244182108f690009f412543302e1762c82ba8a6c5fc9f255040d",
    "XTick.__init__": "b6ccc66ad7cceca46e4b3e6b14a312f82b8a9c285784bfa526a48ad7c22fc696",
    "YTick.__init__": "f976ab0592090585f10bcd6fb0bcbe18c9248c7e0317c60fc657d8df59ecdb3b",
    "Artist.__init__": "bf274a34c7ac98234ac6ea20d8a13db349ffac0ad8825780f13bec041d8fa60d",
    "Line2D.__init__": "2cf8f81bbe1e43f8cef4d5067267f384f2c77a191fa51298c76ca4a26156e996",
    "Line2D.recache": "ae9358d07f14e6ea9b7b2665501b49f7f93da4b15a819d2930032c7ce1607cd7",
    "Line2D.set_xdata": "57bb9d6bd246cede045df181f279d33b690277572bc509da48c77e93463d0077",
    "Line2D.set_ydata": "3ee56836b3cba47329f8e4b1cdd6b3d3db91b1a7a957d3264972da8805aa8162",
    "Text.__init__": "346f2e60c0a6af71478cf704b7862072cd9b0fa565b4431ae1567e5341193520",
}
# templates kept per kind of axis and tick (different tick keywords: labels hidden or shown)
KEEP = 8
ARTISTS = ("tick1line", "tick2line", "gridline", "label1", "label2")


def sources() -> Dict[str, Any]:
    return {"Axis._get_tick": maxis.Axis._get_tick, "Tick.__init__": maxis.Tick.__init__,
            "XTick.__init__": maxis.XTick.__init__, "YTick.__init__": maxis.YTick.__init__,
            "Artist.__init__": martist.Artist.__init__, "Line2D.__init__": mlines.Line2D.__init__,
            "Line2D.recache": mlines.Line2D.recache, "Line2D.set_xdata": mlines.Line2D.set_xdata,
            "Line2D.set_ydata": mlines.Line2D.set_ydata, "Text.__init__": mtext.Text.__init__}


def copy_artist(a: Any) -> Any:
    """A copy of an artist that owns what the artist's constructor makes for it alone."""
    new = object.__new__(type(a))
    d = dict(a.__dict__)
    d["_callbacks"] = cbook.CallbackRegistry(signals=["pchanged"])
    d["_sticky_edges"] = martist._XYPair([], [])
    if "_fontproperties" in d:
        d["_fontproperties"] = d["_fontproperties"].copy()
    new.__dict__ = d
    return new


def copy_tick(tick: Any) -> Any:
    new = copy_artist(tick)
    for name in ARTISTS:
        setattr(new, name, copy_artist(getattr(tick, name)))
    return new


def snapshot(axis: Any, major: bool) -> Optional[Tuple[Any, ...]]:
    """What a tick of this axis is built from besides its axes (the keywords, every rcParams
    value); None for an axis this does not reason about."""
    if type(axis) not in (maxis.XAxis, maxis.YAxis) or axis._tick_class not in (maxis.XTick,
                                                                                  maxis.YTick):
        return None
    kw = {k: v[:] if type(v) is list else v
          for k, v in (axis._major_tick_kw if major else axis._minor_tick_kw).items()}
    return kw, [v[:] if type(v) is list else v for v in dict.values(mpl.rcParams)]


def same(a: Tuple[Any, ...], b: Tuple[Any, ...]) -> bool:
    try:
        return bool(a == b)
    except (ValueError, TypeError):  # an array among the keywords: built afresh
        return False


def place(tick: Any, axes: Any) -> Any:
    """A copied tick made the tick of `axes` as XTick/YTick.__init__ make it: its axes and
    figure, its lines' transforms from the axes, its labels' transforms and alignments from the
    axes and its pad."""
    tick._axes = axes
    tick.figure = axes.figure
    for name in ARTISTS:
        getattr(tick, name).figure = axes.figure
    transform = getattr(axes, f"get_{tick.__name__[0]}axis_transform")
    for line, which in ((tick.tick1line, "tick1"), (tick.tick2line, "tick2"),
                        (tick.gridline, "grid")):
        line._transform = transform(which)
    for label, (trans, va, ha) in ((tick.label1, tick._get_text1_transform()),
                                   (tick.label2, tick._get_text2_transform())):
        label._transform = trans
        label.set_verticalalignment(va)
        label.set_horizontalalignment(ha)
    return tick


def copied_get_tick(original: Callable[..., Any],
                    templates: Dict[Any, List[Any]]) -> Callable[..., Any]:
    """Axis._get_tick handing out copies of templates built by the original (kept in
    `templates`, at most KEEP per kind of axis and tick)."""
    @functools.wraps(original)
    def get_tick(self: Any, major: bool) -> Any:
        now = snapshot(self, major)
        if now is None:
            return original(self, major)
        kept = templates.setdefault((type(self), type(self.axes), major), [])
        for built_from, template in kept:
            if same(built_from, now):
                return place(copy_tick(template), self.axes)
        template = original(self, major)
        kept.append((now, template))
        del kept[:-KEEP]
        return place(copy_tick(template), self.axes)
    return get_tick


def install() -> bool:
    """Installs the copying (once); False when this matplotlib's constructors are not the ones it
    was written against (then nothing is changed)."""
    axis = maxis.Axis

    def patch() -> None:
        axis._get_tick = copied_get_tick(axis._get_tick, {})
    return mplsource.install_once(axis, "_dampsym_tick_clone",
                                  [(f, SOURCES_SHA256[name]) for name, f in sources().items()],
                                  patch)
