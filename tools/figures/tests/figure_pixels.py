"""Figures the pixel tests of dampfig's caches and memos draw (test_layoutcache, test_textcache,
test_tickclone, test_tickmemo, test_legendmemo): each draws a figure with and without the
mechanism and compares what these return."""

from typing import Any

import numpy as np


def pixels(plt: Any, fig: Any) -> Any:
    """The figure drawn on its Agg canvas, its RGBA pixels copied; the figure closed."""
    fig.canvas.draw()
    out = np.asarray(fig.canvas.buffer_rgba()).copy()
    plt.close(fig)
    return out


def loglog_panel(plt: Any) -> Any:
    """One log-log panel of two labelled lines, one label in mathtext, and a title with a
    formula and superscripts: the text the figures draw most."""
    fig, ax = plt.subplots(figsize=(4, 3), dpi=100)
    ax.plot([1e-3, 1e-2, 1e-1], [1e-8, 1e-6, 1e-4], "o-", label="csv1 (fixed h)")
    ax.plot([1e-3, 1e-1], [1e-7, 1e-5], "s--", label=r"$\|z - z_{ref}\|$ at $t_{end}$")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_title(r"energy $H(q, p)$  [×10⁻²⁰]")
    return fig, ax


def tick_grid(plt: Any) -> Any:
    """A 2×2 grid sharing x by column: log-log, linear, ticks on the right, large values."""
    fig, axs = plt.subplots(2, 2, figsize=(6, 4), dpi=100, sharex="col")
    axs[0, 0].plot([1e-3, 1e-2, 1e-1], [1e-8, 1e-6, 1e-4], "o-")
    axs[0, 0].set_xscale("log")
    axs[0, 0].set_yscale("log")
    axs[1, 0].plot([1e-3, 1e-1], [3.0, -2.0])
    axs[0, 1].plot([0, 10], [0.5, 0.7])
    axs[0, 1].yaxis.tick_right()
    axs[1, 1].plot([0, 10], [-1e4, 2e4])
    return fig, axs
