"""dampfig.tickclone: with ticks copied from a template the figures are the same pixels as with
every tick built by matplotlib (a figure with shared axes, log and linear scales, tick labels on
both sides and rotated labels, drawn both ways), a copy equals a built tick attribute by attribute
while owning its callbacks, sticky edges and font, and a change of the tick keywords or rcParams
builds a new template."""

from typing import Any, List

import matplotlib as mpl
import matplotlib.axis
import numpy as np
from matplotlib.transforms import Transform

from figure_pixels import pixels, tick_grid

from dampfig import render, tickclone  # noqa: F401 - render installs the copying


def draw(plt: Any) -> Any:
    fig, axs = tick_grid(plt)
    axs[1, 1].tick_params(axis="x", labelrotation=30, labelsize=7, direction="in")
    for ax in axs.flat:
        ax.set_xlabel("step size h")
    return pixels(plt, fig)


def test_copied_ticks_draw_the_same_pixels(monkeypatch: Any) -> None:
    import matplotlib.pyplot as plt
    axis = matplotlib.axis.Axis
    assert tickclone.install(), "matplotlib's ticks changed: check tickclone against them"
    monkeypatch.setattr(axis, "_get_tick", axis._get_tick.__wrapped__)
    plain = draw(plt)
    monkeypatch.undo()
    built: List[int] = []
    original = axis._get_tick.__wrapped__

    def counted(self: Any, major: bool) -> Any:
        built.append(1)
        return original(self, major)
    copying = tickclone.copied_get_tick(counted, {})
    ticks: List[int] = []

    def every(self: Any, major: bool) -> Any:
        ticks.append(1)
        return copying(self, major)
    monkeypatch.setattr(axis, "_get_tick", every)
    copied = draw(plt)
    assert np.array_equal(plain, copied)
    # a template per kind of axis and tick keywords (tick_right, tick_params), the others copied
    assert 0 < len(built) < len(ticks) / 4


def equal(a: Any, b: Any) -> bool:
    """Equal values: transforms by their matrices, arrays by their elements, paths and markers
    by their vertices and transforms."""
    if isinstance(a, Transform):
        return isinstance(b, Transform) and np.array_equal(a.frozen().get_matrix(),
                                                           b.frozen().get_matrix())
    if isinstance(a, np.ndarray):
        return np.array_equal(a, b)
    if hasattr(a, "vertices"):
        return np.array_equal(a.vertices, b.vertices)
    if isinstance(a, mpl.markers.MarkerStyle):
        return (a.get_marker() == b.get_marker() and equal(a.get_path(), b.get_path())
                and equal(a.get_transform(), b.get_transform()))
    if isinstance(a, (list, tuple)):
        return len(a) == len(b) and all(equal(x, y) for x, y in zip(a, b))
    return bool(a == b)


def test_a_copy_is_a_tick_built_on_its_axes_with_its_own_state() -> None:
    """A tick copied from a template built on another figure's axes equals one built on its own
    axes: the same values, the same transform objects of its axes (they follow the axes' limits
    and size), labels placed by its own figure; and its font is its own."""
    import matplotlib.pyplot as plt
    other, _ = plt.subplots(figsize=(5, 4), dpi=100)
    other.axes[0].xaxis._get_tick(True)  # the template: built on another figure's axes
    other.axes[0].yaxis._get_tick(True)
    fig, ax = plt.subplots(figsize=(3, 2), dpi=100)
    for axis in (ax.xaxis, ax.yaxis):
        built = axis._get_tick.__wrapped__(axis, True)
        copy = axis._get_tick(True)
        for a, b in [(built, copy)] + [(getattr(built, n), getattr(copy, n))
                                       for n in tickclone.ARTISTS]:
            assert a.__dict__.keys() == b.__dict__.keys()
            for k, v in a.__dict__.items():
                if k in ("_callbacks",) + tickclone.ARTISTS:
                    continue
                assert equal(v, b.__dict__[k]), (type(a).__name__, k)
            assert b._callbacks is not a._callbacks and b.figure is fig
        for line in ("tick1line", "tick2line", "gridline"):
            assert getattr(copy, line)._transform is getattr(built, line)._transform
        for label in ("label1", "label2"):
            assert getattr(copy, label)._transform._a is getattr(built, label)._transform._a
            assert getattr(copy, label)._transform._b._scale_trans is fig.dpi_scale_trans
        again = axis._get_tick(True)
        copy.label1.set_fontsize(20)  # in place on the copy's own FontProperties
        assert again.label1.get_fontsize() != 20
        assert again._sticky_edges is not copy._sticky_edges
    plt.close(fig)
    plt.close(other)


def test_changed_keywords_or_rcparams_build_a_new_template() -> None:
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(3, 2), dpi=100)
    first = ax.xaxis._get_tick(True)
    ax.xaxis.set_tick_params(labelsize=15)
    assert ax.xaxis._get_tick(True).label1.get_fontsize() == 15 != first.label1.get_fontsize()
    with mpl.rc_context({"xtick.major.size": 9.0}):
        assert ax.xaxis._get_tick(True).tick1line.get_markersize() == 9.0
    assert ax.xaxis._get_tick(True).tick1line.get_markersize() == first.tick1line.get_markersize()
    plt.close(fig)
