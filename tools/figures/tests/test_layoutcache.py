"""dampfig.layoutcache: with the cache the figures are the same pixels as matplotlib's own text
layout (a figure with tick labels, a rotated and a multi-line label, mathtext, a title and a
legend, drawn without the cache, then twice with it: the second time from the cache), and a text
whose font, alignment or rotation changes in place is laid out again."""

from typing import Any, List

import numpy as np

from figure_pixels import loglog_panel, pixels

from dampfig import layoutcache, render  # noqa: F401 - render installs the cache


def draw(plt: Any) -> Any:
    fig, ax = loglog_panel(plt)
    ax.set_ylabel("relative error\nat t_end")  # two lines at 90 degrees
    ax.text(0.5, 0.5, "centred\nlonger second line", ha="center", va="center",
            multialignment="right", transform=ax.transAxes, rotation=30)
    ax.legend()
    return pixels(plt, fig)


def test_cached_layout_draws_the_same_pixels(monkeypatch: Any) -> None:
    import matplotlib.pyplot as plt
    from matplotlib.text import Text
    assert layoutcache.install(), "matplotlib's Text._get_layout changed: check layoutcache"
    cached = Text._get_layout
    monkeypatch.setattr(Text, "_get_layout", cached.__wrapped__)
    plain = draw(plt)
    monkeypatch.undo()
    calls: List[str] = []
    original = cached.__wrapped__

    def counted(self: Any, renderer: Any) -> Any:
        calls.append(self.get_text())
        return original(self, renderer)
    monkeypatch.setattr(Text, "_get_layout", layoutcache.cached_layout(counted))
    first = draw(plt)
    n_first = len(calls)
    second = draw(plt)
    assert np.array_equal(plain, first) and np.array_equal(plain, second)
    assert n_first > 0 and len(calls) == n_first  # the second figure's layouts all cached


def test_a_text_changed_in_place_is_laid_out_again() -> None:
    """The key snapshots what the layout reads: a font size, alignment or rotation changed on the
    same Text object (and its FontProperties mutated in place) gives the new layout."""
    import matplotlib.pyplot as plt
    fig = plt.figure(figsize=(3, 2), dpi=100)
    text = fig.text(0.5, 0.5, "2×10⁻³ (layoutcache)")
    renderer = fig.canvas.get_renderer()

    def extent() -> Any:
        return text.get_window_extent(renderer).get_points().copy()
    before = extent()
    assert np.array_equal(before, extent())
    text.get_fontproperties().set_size(14)  # in place
    bigger = extent()
    text.set_horizontalalignment("right")
    right = extent()
    text.set_rotation(90)
    turned = extent()
    plt.close(fig)
    assert bigger[1, 0] - bigger[0, 0] > before[1, 0] - before[0, 0]
    assert right[1, 0] < bigger[1, 0]
    assert turned[1, 1] - turned[0, 1] > turned[1, 0] - turned[0, 0]
