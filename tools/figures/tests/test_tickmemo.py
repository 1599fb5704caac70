"""dampfig.tickmemo: with the memo an axis's ticks are updated once per draw and the figures are
the same pixels as matplotlib's own drawing (a figure with shared axes, log and linear scales, tick
labels on both sides of a panel and axis labels placed below them, drawn without the memo and
with it)."""

from typing import Any, List, Tuple

import matplotlib.axis
import numpy as np

from figure_pixels import pixels, tick_grid

from dampfig import render, tickmemo  # noqa: F401 - render installs the memo


def draw(plt: Any) -> Tuple[Any, List[Any]]:
    fig, axs = tick_grid(plt)
    for ax in axs.flat:
        ax.set_xlabel("step size h")
        ax.set_ylabel("error")
    axs[1, 1].xaxis.set_label_position("top")
    axes = [a for ax in axs.flat for a in (ax.xaxis, ax.yaxis)]
    return pixels(plt, fig), axes


def test_memo_draws_the_same_pixels_with_half_the_tick_updates(monkeypatch: Any) -> None:
    import matplotlib.pyplot as plt
    axis = matplotlib.axis.Axis
    assert tickmemo.install(), "matplotlib's Axis changed: check tickmemo against it"
    calls: List[int] = []
    update = axis._update_ticks.__wrapped__

    def counted(self: Any) -> Any:
        calls.append(1)
        return update(self)
    for name in ("draw", "_get_ticklabel_bboxes"):  # matplotlib's own
        monkeypatch.setattr(axis, name, getattr(axis, name).__wrapped__)
    monkeypatch.setattr(axis, "_update_ticks", counted)
    plain, _ = draw(plt)
    n_plain = len(calls)
    monkeypatch.undo()
    monkeypatch.setattr(axis, "_update_ticks", tickmemo.memo_update_ticks(counted))
    calls.clear()
    memo, axes = draw(plt)
    assert np.array_equal(plain, memo)
    assert n_plain == 16 and len(calls) == 8  # 8 axes drawn: twice each without the memo, once
    assert not any(hasattr(a, tickmemo.MEMO) for a in axes)  # nothing kept after the draw
