"""A legend's box packed once per draw (the cost of --figures, docs/reports.md "Cost"): the same
pixels, without packing the same entries again and again.

matplotlib 3.6's Legend.draw asks its box (a VPacker of the title and an HPacker of columns, each
a VPacker of entries, each an HPacker of a handle and a text) for its extent, then draws it; every
packer's get_extent_offsets asks each child for its extent, which for a packer is its own
get_extent_offsets, and drawing a packer computes its extent and offsets again before drawing
each child, which does the same: the entries of a legend were packed about sixteen times per
draw (3073 VPacker packings for 186 legend draws, over half of the legends' drawing time).
Nothing in a legend's draw changes what the packing reads (the children, their texts and sizes,
the renderer's dpi; the only writes are offsets, which packing does not read, the DrawingArea's
dpi transform and TextArea's baseline transform, set again to the same values, and the width a
packer gives its children in "expand" mode, the same every time). install() wraps Legend.draw
so that while a legend draws, VPacker's and HPacker's get_extent_offsets return what they
returned the first time in that draw for the same box and renderer; outside a legend's draw they
run as before. tests/test_legendmemo.py draws figures both ways and compares the pixels.

Applied only to the matplotlib versions whose legend and packers it was written against (their
code is checked); any other version draws without it."""

import functools
from typing import Any, Callable, Dict, Optional, Tuple

from matplotlib import legend as mlegend
from matplotlib import offsetbox as mob

from . import mplsource

# The SHA-256 of the sources this reasons about (matplotlib 3.6.3).
SOURCES_SHA256 = {
    "Legend.draw": "9e633ec301471a32056765527c54127cb4d97bd480c9d4c36f645253645903be",
    "VPacker.get_extent_offsets": "d28f78f51cc47dc6dfc2007575cf6e21e8e4835a3f711068ec33433b78a6e3c4",
    "HPacker.get_extent_offsets": "62255bca0dbe1eef3ea03adaef429c6b237203820d7f0f59d8e0e58e9e5aa92c",
    "OffsetBox.draw": "1abc8036fcf8b0c02cdde1ed2ad79c32bc9b445f90de01c7e9612b87c9c95976",
    "OffsetBox.get_extent": "eeb9e355e863f6969455e2fae4a984ca478dd211bab4163bf5390d9c044572d9",
    "OffsetBox.get_window_extent": "dcdcf5ed7a8eac8b3b8bb72bcfc798b9099d5f295b4676c3850d561af932bf08",
    "TextArea.get_extent": "53e6bb9d204bc680c4c374045abb4c895914ad8b458cac03638d9d1c5f322520",
    "TextArea.draw": "ae6feed7686946f3885b64c65d0c6c875ab05e972dafe54cb7fdaf37acc0fc02",
    "DrawingArea.get_extent": "dc9be16dd2e8fe2d97f4e13c1c53924e92867519837d4d02878468e6d75e2ca7",
    "DrawingArea.draw": "69ad9a4046c28b8975f34284bbcc266762faa604475bebe710d8104c9f69b4f4",
}


def sources() -> Dict[str, Any]:
    return {name: getattr({"Legend": mlegend.Legend, "VPacker": mob.VPacker,
                           "HPacker": mob.HPacker, "OffsetBox": mob.OffsetBox,
                           "TextArea": mob.TextArea, "DrawingArea": mob.DrawingArea}[cls], meth)
            for name in SOURCES_SHA256 for cls, meth in [name.split(".")]}


class Memo:
    """The packings of the legend being drawn (None outside a legend's draw), keyed by the ids
    of the box and the renderer (both kept alive with the result for the draw)."""

    def __init__(self) -> None:
        self.active: Optional[Dict[Tuple[int, int], Tuple[Any, Any, Any]]] = None


def memo_draw(original: Callable[..., Any], memo: Memo) -> Callable[..., Any]:
    """Legend.draw with a memo of its packings for the time it draws."""
    @functools.wraps(original)
    def draw(self: Any, renderer: Any, *args: Any, **kwargs: Any) -> Any:
        outer = memo.active
        memo.active = {}
        try:
            return original(self, renderer, *args, **kwargs)
        finally:
            memo.active = outer
    return draw


def memo_packing(original: Callable[..., Any], memo: Memo) -> Callable[..., Any]:
    """A packer's get_extent_offsets: within a legend's draw, the first result again for the
    same box and renderer (its callers read it: unpack the extent, zip the offsets)."""
    @functools.wraps(original)
    def get_extent_offsets(self: Any, renderer: Any) -> Any:
        active = memo.active
        if active is None:
            return original(self, renderer)
        key = (id(self), id(renderer))
        hit = active.get(key)
        if hit is None:
            hit = active[key] = (self, renderer, original(self, renderer))
        return hit[2]
    return get_extent_offsets


def install() -> bool:
    """Installs the memo (once); False when this matplotlib's legend or packers are not the ones
    it was written against (then nothing is changed)."""
    legend = mlegend.Legend

    def patch() -> None:
        memo = Memo()
        legend.draw = memo_draw(legend.draw, memo)
        for packer in (mob.VPacker, mob.HPacker):
            setattr(packer, "get_extent_offsets", memo_packing(packer.get_extent_offsets, memo))
    return mplsource.install_once(legend, "_dampsym_legend_memo",
                                  [(f, SOURCES_SHA256[name]) for name, f in sources().items()],
                                  patch)
