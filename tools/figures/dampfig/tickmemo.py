"""An axis's ticks computed once per draw (the cost of --figures, docs/reports.md "Cost"): the same
pixels, with half the tick work.

matplotlib 3.6's Axis.draw updates its ticks (locator, formatter, each tick's position and label:
Axis._update_ticks) and measures their labels (_get_ticklabel_bboxes), draws them, and then places
the axis label below them (_update_label_position), which updates the ticks and measures their
labels a second time (_get_tick_boxes_siblings). Nothing between the two changes the view limits,
the locator or the formatter, so the second time computes the same ticks and boxes; it was a
tenth of the drawing time. install() wraps Axis.draw so that, while an axis draws, its
_update_ticks and _get_ticklabel_bboxes (for the same ticks and renderer) return what they
returned the first time in that draw; outside a draw (and for another axis) they run as before.
tests/test_tickmemo.py draws figures both ways and compares the pixels.

Applied only to the matplotlib versions whose Axis it was written against (the code of the four
methods is checked); any other version draws without it."""

import functools
from typing import Any, Callable, Dict, List, Optional, Tuple

from matplotlib import axis as maxis

from . import mplsource

# The SHA-256 of the sources of the Axis methods this reasons about (matplotlib 3.6.3).
SOURCES_SHA256 = {
    "draw": "848c9f93499b00db74a47e8f6377387a767ba25ebaeb9efa5eebabf02a421d59",
    "_update_ticks": "f6f6d03ee946ca270bce044084bc8a478b877c356fb99c2174d2c5c3ea4373f9",
    "_get_ticklabel_bboxes": "aa110c5efdc0bb35ae11e8f49b9d97348b45805eef8ad0e83faf80a910cb2a35",
    "_get_tick_boxes_siblings": "30691c355535c298649af0e5721738b410573895c90172b98fb1af89854f384e",
}
MEMO = "_dampsym_tick_memo"
DRAWN = "_dampsym_drawn_tick_boxes"


def memo_draw(original: Callable[..., Any]) -> Callable[..., Any]:
    """Axis.draw with a memo of its ticks and their label boxes for the time it draws."""
    @functools.wraps(original)
    def draw(self: Any, renderer: Any, *args: Any, **kwargs: Any) -> Any:
        setattr(self, MEMO, {})
        try:
            return original(self, renderer, *args, **kwargs)
        finally:
            memo = getattr(self, MEMO)
            setattr(self, DRAWN, [b for k, v in memo.items() if k != "ticks"
                                  for b in (*v[1][0], *v[1][1])])
            delattr(self, MEMO)
    return draw


def drawn_tick_boxes(axis: Any) -> Optional[List[Any]]:
    """The boxes (pixels) of the tick labels an axis drew in its last draw (kept by the memo, so
    that the layout can check them without measuring again); None without the memo or a draw."""
    boxes: Optional[List[Any]] = getattr(axis, DRAWN, None)
    return boxes


def memo_update_ticks(original: Callable[..., Any]) -> Callable[..., Any]:
    """Axis._update_ticks: the first result of this draw again (the same list of ticks)."""
    @functools.wraps(original)
    def update_ticks(self: Any) -> Any:
        memo: Optional[Dict[Any, Any]] = getattr(self, MEMO, None)
        if memo is None:
            return original(self)
        if "ticks" not in memo:
            memo["ticks"] = original(self)
        return memo["ticks"]
    return update_ticks


def memo_bboxes(original: Callable[..., Any]) -> Callable[..., Any]:
    """Axis._get_ticklabel_bboxes: for this draw's ticks and renderer, the first result again
    (its callers read the lists; the sibling search copies them into lists of its own)."""
    @functools.wraps(original)
    def bboxes(self: Any, ticks: List[Any], renderer: Any = None) -> Tuple[List[Any], List[Any]]:
        memo: Optional[Dict[Any, Any]] = getattr(self, MEMO, None)
        if memo is None or ticks is not memo.get("ticks") or renderer is None:
            return original(self, ticks, renderer)
        key = ("bboxes", id(renderer))
        if key not in memo:
            memo[key] = (renderer, original(self, ticks, renderer))
        return memo[key][1]
    return bboxes


def install() -> bool:
    """Installs the memo (once); False when this matplotlib's Axis methods are not the ones it
    was written against (then nothing is changed)."""
    ax = maxis.Axis

    def patch() -> None:
        ax.draw = memo_draw(ax.draw)
        ax._update_ticks = memo_update_ticks(ax._update_ticks)
        ax._get_ticklabel_bboxes = memo_bboxes(ax._get_ticklabel_bboxes)
    return mplsource.install_once(ax, "_dampsym_tick_memo_installed",
                                  [(getattr(ax, name), h) for name, h in SOURCES_SHA256.items()],
                                  patch)
