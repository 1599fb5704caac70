"""A text's layout computed once per process (the cost of --figures, docs/reports.md "Cost"): the
same pixels, without matplotlib working out the same tick label, legend entry or title again.

matplotlib 3.6's Text._get_layout (called by Text.draw, Text.get_window_extent and the legends'
TextArea.get_extent) splits the text into lines, measures each line and the line height "lp"
through the renderer, and aligns and rotates them: a box and the lines' offsets relative to the
text's anchor, in pixels. It is the same for every tick label "10⁻³" of every figure, but was a
sixth of the drawing time, mostly its Python overhead (the measurements themselves come from
textcache's and mathtext's caches). Its result depends only on the text, the font properties, the
usetex and parse_math flags, the line spacing, the rotation, the alignments, the rotation mode,
the figure's and the renderer's dpi and what the renderer measures (for Agg: the same key as
textcache's and matplotlib's own metrics cache). install() wraps Text._get_layout with one cache
keyed by all of these, for Agg renderers only (svg and pdf measure differently; they run as
before), and hands each caller its own copy of the box (the lines are tuples of str and floats).
tests/test_layoutcache.py draws figures both ways and compares the pixels.

Applied only to the matplotlib versions whose Text it was written against (the code of
_get_layout is checked); any other version draws without it."""

import functools
from typing import Any, Callable, Dict, Tuple

import matplotlib as mpl
from matplotlib import text as mtext
from matplotlib.backends import backend_agg

from . import mplsource

# The SHA-256 of the source of Text._get_layout this reasons about (matplotlib 3.6.3).
LAYOUT_SHA256 = "5510996d846ca0f2ff04f767e9fbf7344506ef9dc8763c916c6070b9be053819"
MAX_ENTRIES = 50_000  # a default-suite run needs about 900

Key = Tuple[Any, ...]


def font_key(prop: Any) -> Key:
    """Every attribute of a FontProperties the font lookup and mathtext read (a snapshot: the
    object is mutable)."""
    return (tuple(prop.get_family()), prop.get_slant(), prop.get_variant(), prop.get_weight(),
            prop.get_stretch(), prop.get_size(), prop.get_file(), prop.get_math_fontfamily())


def layout_key(text: Any, renderer: Any) -> Key:
    """What Text._get_layout's result depends on (its own reads of the Text, and the renderer's
    measurements: the renderer's dpi, Agg's hinting flag and antialiasing, as textcache)."""
    return (text.get_text(), font_key(text._fontproperties), text.get_usetex(),
            text.get_parse_math(), text._linespacing, text.get_rotation(),
            text._get_multialignment(), text._horizontalalignment, text._verticalalignment,
            text.get_rotation_mode(), text.figure.dpi, renderer.dpi,
            backend_agg.get_hinting_flag(), bool(mpl.rcParams["text.antialiased"]))


def cached_layout(original: Callable[..., Any]) -> Callable[..., Any]:
    """Text._get_layout from one cache for Agg renderers; every call gets its own box."""
    cache: Dict[Key, Any] = {}

    @functools.wraps(original)
    def get_layout(self: Any, renderer: Any) -> Any:
        if type(renderer) is not backend_agg.RendererAgg:
            return original(self, renderer)
        key = layout_key(self, renderer)
        hit = cache.get(key)
        if hit is None:
            hit = original(self, renderer)
            if len(cache) < MAX_ENTRIES:
                cache[key] = hit
        bbox, info, descent = hit
        return bbox.frozen(), list(info), descent
    return get_layout


def install() -> bool:
    """Installs the cache (once); False when this matplotlib's Text._get_layout is not the one it
    was written against (then nothing is changed)."""
    text = mtext.Text

    def patch() -> None:
        text._get_layout = cached_layout(text._get_layout)
    return mplsource.install_once(text, "_dampsym_layout_cache",
                                  [(text._get_layout, LAYOUT_SHA256)], patch)
