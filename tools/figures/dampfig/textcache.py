"""Caches of matplotlib's text work across the figures of one drawing process (the cost of
--figures, docs/reports.md "Cost"): the same pixels, computed once.

Text was the largest part of the drawing time: FreeType lays a string out glyph by glyph (about
30 µs a glyph here, hinted or not) every time Agg measures it and again every time it draws it,
and matplotlib keeps its measurements per renderer, i.e. per figure; the legends measure "lp" for
every entry at every draw; and mathtext parses (45 ms each) are cached per renderer, i.e. again
for every figure, 50 at most. install() wraps Agg's get_text_width_height_descent and draw_text
with one cache keyed by everything their results depend on (the string, a copy of the font
properties, the renderer's dpi, the hinting flag and antialiasing), and shares one mathtext
parse cache between the renderers. Measuring and drawing a string lay it out the same way
(FT2Font.set_text at angle 0 with the hinting flag), so the first of the two lays it out once
and keeps both results: its size and the glyph bitmap FreeType drew, which is handed to the same
draw_text_image at the same position. The figures are the same byte for byte
(tests/test_textcache.py draws a figure both ways).

Applied only to the matplotlib versions whose Agg renderer it was written against (the code of
draw_text and get_text_width_height_descent is checked); any other version draws without these
caches."""

import functools
from math import cos, radians, sin
from typing import Any, Callable, Dict, Tuple

import matplotlib as mpl
import matplotlib.mathtext
import numpy as np
from matplotlib.backends import backend_agg

from . import mplsource

# The SHA-256 of the sources of RendererAgg.draw_text and get_text_width_height_descent these
# wrappers reproduce (matplotlib 3.6.3).
DRAW_TEXT_SHA256 = "b4b7c9f79a34dac6fd4e8ce0b185336de2f9b16e2ce1b6850dffc9e2bc3e117f"
MEASURE_SHA256 = "b2af521086fd949092821412eea45cbbe9ef15355e1e735aa5979ccb83c668d5"
MAX_ENTRIES = 50_000  # per cache; a default-suite run needs about 2000

Key = Tuple[Any, ...]


def _key(renderer: Any, s: str, prop: Any) -> Key:
    return (s, prop.copy(), renderer.dpi, backend_agg.get_hinting_flag(),
            bool(mpl.rcParams["text.antialiased"]))


# a plain string laid out once: (width, height, descent) as get_text_width_height_descent returns
# them, and the glyph bitmap with the offsets draw_text reads (descent, x and y offset, in pixels)
Entry = Tuple[Tuple[float, float, float], Any, float, float, float]


def lay_out(renderer: Any, s: str, prop: Any) -> Entry:
    """The steps of RendererAgg.get_text_width_height_descent (plain text) and of draw_text up to
    draw_text_image, after one FT2Font.set_text."""
    font = renderer._prepare_font(prop)
    font.set_text(s, 0.0, flags=backend_agg.get_hinting_flag())
    w, h = font.get_width_height()  # width and height of unrotated string
    d = font.get_descent() / 64.0
    font.draw_glyphs_to_bitmap(antialiased=mpl.rcParams["text.antialiased"])
    xo, yo = font.get_bitmap_offset()
    return (w / 64.0, h / 64.0, d), np.array(font, copy=True), d, xo / 64.0, yo / 64.0


class TextCache:
    """Plain strings laid out by lay_out, at most MAX_ENTRIES of them."""

    def __init__(self) -> None:
        self.entries: Dict[Key, Entry] = {}

    def get(self, renderer: Any, s: str, prop: Any) -> Entry:
        key = _key(renderer, s, prop)
        hit = self.entries.get(key)
        if hit is None:
            hit = lay_out(renderer, s, prop)
            if len(self.entries) < MAX_ENTRIES:
                self.entries[key] = hit
        return hit


def cached_measure(original: Callable[..., Any], cache: TextCache) -> Callable[..., Any]:
    """get_text_width_height_descent, from the cache for plain (non-math, non-TeX) strings."""
    @functools.wraps(original)
    def measure(self: Any, s: str, prop: Any, ismath: Any) -> Any:
        if ismath is not False:
            return original(self, s, prop, ismath)
        return cache.get(self, s, prop)[0]
    return measure


def cached_draw(original: Callable[..., Any], cache: TextCache) -> Callable[..., Any]:
    """draw_text with the glyph bitmap and its offsets from the cache (RendererAgg.draw_text's
    steps)."""
    @functools.wraps(original)
    def draw_text(self: Any, gc: Any, x: float, y: float, s: str, prop: Any, angle: float,
                  ismath: Any = False, mtext: Any = None) -> None:
        if ismath:
            return original(self, gc, x, y, s, prop, angle, ismath, mtext)
        _, image, d, xo, yo = cache.get(self, s, prop)
        xd = d * sin(radians(angle))
        yd = d * cos(radians(angle))
        self._renderer.draw_text_image(image, round(x + xo + xd), round(y + yo + yd) + 1, angle,
                                       gc)
    return draw_text


def shared_parse(original: Callable[..., Any]) -> Callable[..., Any]:
    """MathTextParser._parse_cached with one cache for every parser of an output type: each Agg
    renderer (each figure) has its own parser, and matplotlib's cache is keyed by the parser and
    holds 50 formulas. The parse depends on the parser only through its output type."""
    cache: Dict[Key, Any] = {}

    @functools.wraps(original)
    def parse_cached(self: Any, s: str, dpi: float, prop: Any) -> Any:
        key = (self._output_type, s, dpi, prop)  # prop: parse()'s own copy
        hit = cache.get(key)
        if hit is None:
            hit = original(self, s, dpi, prop)
            if len(cache) < MAX_ENTRIES:
                cache[key] = hit
        return hit
    return parse_cached


def install() -> bool:
    """Installs the caches (once); False when this matplotlib's draw_text or
    get_text_width_height_descent is not the one they reproduce (then nothing is changed)."""
    agg = backend_agg.RendererAgg

    def patch() -> None:
        cache = TextCache()
        agg.get_text_width_height_descent = cached_measure(agg.get_text_width_height_descent,
                                                           cache)
        agg.draw_text = cached_draw(agg.draw_text, cache)
        parser = matplotlib.mathtext.MathTextParser
        parser._parse_cached = shared_parse(parser._parse_cached.__wrapped__)
    return mplsource.install_once(agg, "_dampsym_text_cache",
                                  [(agg.draw_text, DRAW_TEXT_SHA256),
                                   (agg.get_text_width_height_descent, MEASURE_SHA256)], patch)
