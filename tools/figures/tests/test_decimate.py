"""Thinning of time-series lines for drawing (figdata.decimate_columns, used by the linear panels
of draw_series.panel_lines): in every pixel column of the axes the thinned line covers the same
vertical extent as the full series; a single spike survives; the endpoints stay."""

import math
import random
from typing import Dict, List, Tuple

from dampfig import figdata as fd
from dampfig.render import COLUMNS


def column_extents(t: List[float], y: List[float], lo: float, hi: float,
                   columns: int) -> Dict[int, Tuple[float, float]]:
    out: Dict[int, Tuple[float, float]] = {}
    for a, b in zip(t, y):
        c = int((a - lo) * columns / (hi - lo))
        mn, mx = out.get(c, (b, b))
        out[c] = (min(mn, b), max(mx, b))
    return out


def series(n: int, seed: int) -> Tuple[List[float], List[float]]:
    rng = random.Random(seed)
    t = [10.0 * k / (n - 1) for k in range(n)]
    y = [math.exp(-0.3 * a) * (1.0 + 0.5 * math.sin(7.0 * a)) * (1.0 + 0.1 * rng.random())
         for a in t]
    return t, y


def test_decimation_keeps_every_column_extent_and_endpoints() -> None:
    t, y = series(20000, 1)
    td, yd = fd.decimate_columns(t, y, 0.0, 10.0, COLUMNS)
    assert len(td) <= 2 * COLUMNS + 2 < len(t)
    assert column_extents(td, yd, 0.0, 10.0, COLUMNS) == column_extents(t, y, 0.0, 10.0, COLUMNS)
    assert (td[0], td[-1]) == (t[0], t[-1])
    assert td == sorted(td)


def test_a_single_spike_survives() -> None:
    t, y = series(20000, 2)
    y[12345] = 50.0  # one sample far above its neighbours
    td, yd = fd.decimate_columns(t, y, 0.0, 10.0, COLUMNS)
    assert 50.0 in yd and td[yd.index(50.0)] == t[12345]
