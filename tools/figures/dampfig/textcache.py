"""Caches of matplotlib's text work across the figures of one drawing process (the cost of
--figures, docs/reports.md "Cost"): the same pixels, computed once.

Text was the largest part of the drawing time: FreeType lays a string out glyph by glyph (about
30 µs a glyph here, hinted or not) every time Agg measures it and again every time it draws it,
and matplotlib keeps its measurements per renderer, i.e. per figure; the legends measure "lp" for
every entry at every draw; and mathtext parses (45 ms each) are cached per renderer, i.e. again
for every figure, 50 at most. install() wraps Agg's get_text_width_height_descent and draw_text
with caches keyed by everything their result depends on (the string, a copy of the font
properties, the renderer's dpi, the hinting flag and antialiasing), and shares one mathtext
parse cache between the renderers. A cached glyph bitmap is the array
FreeType drew, handed to the same draw_text_image at the same position: the figures are the same
byte for byte (tests/test_textcache.py draws a figure both ways).

Applied only to the matplotlib versions whose Agg renderer it was written against (the
code of draw_text is checked); any other version draws without these caches."""

import functools
import hashlib
import inspect
from math import cos, radians, sin
from typing import Any, Callable, Dict, Tuple

import matplotlib as mpl
import matplotlib.mathtext
import numpy as np
from matplotlib.backends import backend_agg

# The SHA-256 of the source of RendererAgg.draw_text these wrappers reproduce (matplotlib 3.6.3).
DRAW_TEXT_SHA256 = "b4b7c9f79a34dac6fd4e8ce0b185336de2f9b16e2ce1b6850dffc9e2bc3e117f"
MAX_ENTRIES = 50_000  # per cache; a default-suite run needs about 2000

Key = Tuple[Any, ...]


def draw_text_source_hash() -> str:
    return hashlib.sha256(inspect.getsource(backend_agg.RendererAgg.draw_text).encode()).hexdigest()


def _key(renderer: Any, s: str, prop: Any) -> Key:
    return (s, prop.copy(), renderer.dpi, backend_agg.get_hinting_flag(),
            bool(mpl.rcParams["text.antialiased"]))


def cached_measure(original: Callable[..., Any]) -> Callable[..., Any]:
    """get_text_width_height_descent, cached for plain (non-math, non-TeX) strings."""
    cache: Dict[Key, Any] = {}

    @functools.wraps(original)
    def measure(self: Any, s: str, prop: Any, ismath: Any) -> Any:
        if ismath is not False:
            return original(self, s, prop, ismath)
        key = _key(self, s, prop)
        hit = cache.get(key)
        if hit is None:
            hit = original(self, s, prop, ismath)
            if len(cache) < MAX_ENTRIES:
                cache[key] = hit
        return hit
    return measure


def cached_draw(original: Callable[..., Any]) -> Callable[..., Any]:
    """draw_text with the glyph bitmap and its offsets cached (RendererAgg.draw_text's steps)."""
    cache: Dict[Key, Tuple[Any, float, float, float]] = {}

    @functools.wraps(original)
    def draw_text(self: Any, gc: Any, x: float, y: float, s: str, prop: Any, angle: float,
                  ismath: Any = False, mtext: Any = None) -> None:
        if ismath:
            return original(self, gc, x, y, s, prop, angle, ismath, mtext)
        key = _key(self, s, prop)
        hit = cache.get(key)
        if hit is None:
            font = self._prepare_font(prop)
            font.set_text(s, 0, flags=backend_agg.get_hinting_flag())
            font.draw_glyphs_to_bitmap(antialiased=mpl.rcParams["text.antialiased"])
            xo, yo = font.get_bitmap_offset()
            hit = (np.array(font, copy=True), font.get_descent() / 64.0, xo / 64.0, yo / 64.0)
            if len(cache) < MAX_ENTRIES:
                cache[key] = hit
        image, d, xo, yo = hit
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
    """Installs the caches (once); False when this matplotlib's draw_text is not the one they
    reproduce (then nothing is changed)."""
    agg = backend_agg.RendererAgg
    if getattr(agg, "_dampsym_text_cache", False):
        return True
    if draw_text_source_hash() != DRAW_TEXT_SHA256:
        return False
    agg.get_text_width_height_descent = cached_measure(agg.get_text_width_height_descent)
    agg.draw_text = cached_draw(agg.draw_text)
    parser = matplotlib.mathtext.MathTextParser
    parser._parse_cached = shared_parse(parser._parse_cached.__wrapped__)
    agg._dampsym_text_cache = True
    return True
