"""dampfig.textcache: with its caches the figures are the same pixels as matplotlib's own text
drawing (a figure with tick labels, a rotated label, mathtext and a legend, drawn without the
caches, then twice with them: the second time from the caches), and the caches are used."""

import functools
from typing import Any

import matplotlib.mathtext
import numpy as np

from figure_pixels import loglog_panel, pixels

from dampfig import render, textcache  # noqa: F401 - render installs the caches


def draw(plt: Any) -> Any:
    fig, ax = loglog_panel(plt)
    ax.set_ylabel("relative error at t_end")  # drawn at 90 degrees
    ax.legend()
    return pixels(plt, fig)


def test_cached_text_draws_the_same_pixels(monkeypatch: Any) -> None:
    import matplotlib.pyplot as plt
    from matplotlib.backends.backend_agg import RendererAgg
    assert textcache.install(), "matplotlib's draw_text changed: check textcache against it"
    draw_cached, measure_cached = RendererAgg.draw_text, RendererAgg.get_text_width_height_descent
    monkeypatch.setattr(RendererAgg, "draw_text", draw_cached.__wrapped__)
    monkeypatch.setattr(RendererAgg, "get_text_width_height_descent",
                        measure_cached.__wrapped__)
    parser = matplotlib.mathtext.MathTextParser
    monkeypatch.setattr(parser, "_parse_cached",  # matplotlib's own: per parser, 50 formulas
                        functools.lru_cache(50)(parser._parse_cached.__wrapped__))
    plain = draw(plt)
    monkeypatch.undo()
    calls = []
    prepare = RendererAgg._prepare_font

    def counted(self: Any, prop: Any) -> Any:
        calls.append(prop)
        return prepare(self, prop)
    monkeypatch.setattr(RendererAgg, "_prepare_font", counted)
    first = draw(plt)
    n_first = len(calls)
    second = draw(plt)
    assert np.array_equal(plain, first) and np.array_equal(plain, second)
    assert n_first > 0 and len(calls) == n_first  # the second figure's text all from the caches


def test_a_string_measured_and_drawn_is_laid_out_once(monkeypatch: Any) -> None:
    """Measuring a string and then drawing it (what Text.draw does) lays it out once."""
    import matplotlib.pyplot as plt
    from matplotlib.backends.backend_agg import RendererAgg
    from matplotlib.font_manager import FontProperties
    layouts = []
    lay_out = textcache.lay_out

    def counted(renderer: Any, s: str, prop: Any) -> Any:
        layouts.append(s)
        return lay_out(renderer, s, prop)
    monkeypatch.setattr(textcache, "lay_out", counted)
    fig = plt.figure(figsize=(2, 1), dpi=100)
    renderer = fig.canvas.get_renderer()
    assert isinstance(renderer, RendererAgg)
    prop = FontProperties(size=8.25)
    text = "laid out once: 2×10⁻³ (a string no other test draws)"
    w, h, d = renderer.get_text_width_height_descent(text, prop, False)
    renderer.draw_text(renderer.new_gc(), 10.0, 20.0, text, prop, 0.0)
    plt.close(fig)
    assert w > 0 and h > 0 and layouts == [text]
