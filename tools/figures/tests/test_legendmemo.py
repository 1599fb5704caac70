"""dampfig.legendmemo: with the memo a legend's entries are packed once per draw and the figures
are the same pixels as matplotlib's own drawing (an axes legend in two columns with a title and a
figure legend in "expand" mode, drawn without the memo and with it), and nothing is kept from one
draw to the next (a legend whose text changed is packed anew)."""

from typing import Any, List

import numpy as np
from matplotlib import offsetbox

from figure_pixels import pixels

from dampfig import legendmemo, render  # noqa: F401 - render installs the memo


def draw(plt: Any) -> Any:
    fig, ax = plt.subplots(figsize=(5, 4), dpi=100)
    for k in range(5):
        ax.plot([0, 1], [k, k + 1], marker="os^Dv"[k], label=f"method {k}" + " (ref)" * (k == 2))
    ax.legend(ncol=2, title="methods", loc="upper left")
    fig.legend(handles=ax.get_lines()[:3], loc="lower center", ncol=3, mode="expand",
               bbox_to_anchor=(0.1, 0.0, 0.8, 0.1))
    return pixels(plt, fig)


def test_memo_draws_the_same_pixels_with_fewer_packings(monkeypatch: Any) -> None:
    import matplotlib.pyplot as plt
    from matplotlib.legend import Legend
    assert legendmemo.install(), "matplotlib's legend changed: check legendmemo against it"
    packers = (offsetbox.VPacker, offsetbox.HPacker)
    calls: List[int] = []

    def counting(packer: Any) -> Any:
        plain = packer.get_extent_offsets.__wrapped__

        def counted(self: Any, renderer: Any) -> Any:
            calls.append(1)
            return plain(self, renderer)
        return counted
    monkeypatch.setattr(Legend, "draw", Legend.draw.__wrapped__)
    for p in packers:
        monkeypatch.setattr(p, "get_extent_offsets", counting(p))
    plain = draw(plt)
    n_plain = len(calls)
    monkeypatch.undo()
    memo = legendmemo.Memo()
    monkeypatch.setattr(Legend, "draw", legendmemo.memo_draw(Legend.draw.__wrapped__, memo))
    for p in packers:
        monkeypatch.setattr(p, "get_extent_offsets", legendmemo.memo_packing(counting(p), memo))
    calls.clear()
    memoised = draw(plt)
    assert np.array_equal(plain, memoised)
    assert 0 < 3 * len(calls) < n_plain  # 70 packings without the memo, 17 with it
    assert memo.active is None  # nothing kept after the draws


def test_a_legend_changed_between_draws_is_packed_anew() -> None:
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(4, 3), dpi=100)
    ax.plot([0, 1], [0, 1], label="a")
    legend = ax.legend(loc="upper left")
    fig.canvas.draw()
    narrow = legend.legendPatch.get_width()  # the frame drawn around the packed entries
    legend.get_texts()[0].set_text("a much longer label than before")
    fig.canvas.draw()
    wide = legend.legendPatch.get_width()
    plt.close(fig)
    assert wide > narrow + 50
