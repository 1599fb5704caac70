"""dampfig.tickmemo: with the memo an axis's ticks are updated once per draw and the figures are
the same pixels as matplotlib's own drawing (a figure with shared axes, log and linear scales, tick
labels on both sides of a panel and axis labels placed below them, drawn without the memo and
with it)."""

from typing import Any, List, Tuple

import matplotlib.axis
import numpy as np

from dampfig import render, tickmemo  # noqa: F401 - render installs the memo


def draw(plt: Any) -> Tuple[Any, List[Any]]:
    fig, axs = plt.subplots(2, 2, figsize=(6, 4), dpi=100, sharex="col")
    axs[0, 0].plot([1e-3, 1e-2, 1e-1], [1e-8, 1e-6, 1e-4], "o-")
    axs[0, 0].set_xscale("log")
    axs[0, 0].set_yscale("log")
    axs[1, 0].plot([1e-3, 1e-1], [3.0, -2.0])
    axs[0, 1].plot([0, 10], [0.5, 0.7])
    axs[0, 1].yaxis.tick_right()
    axs[1, 1].plot([0, 10], [-1e4, 2e4])
    for ax in axs.flat:
        ax.set_xlabel("step size h")
        ax.set_ylabel("error")
    axs[1, 1].xaxis.set_label_position("top")
    fig.canvas.draw()
    pixels = np.asarray(fig.canvas.buffer_rgba()).copy()
    plt.close(fig)
    return pixels, [a for ax in axs.flat for a in (ax.xaxis, ax.yaxis)]


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
