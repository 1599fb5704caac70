"""field-drift: B (5.6), ln max u + Gamma(t) on the output grid without t0."""
from __future__ import annotations

from typing import Any, Dict

import numpy as np

from .. import xmethods as xm
from .. import xmetrics as xmt
from ..xrunctx import RunCtx
from . import Diagnostic, register


def drift(cx: RunCtx, traj: np.ndarray) -> Dict[str, Any]:
    """B (5.6)'s d(t) = ln max u + Gamma(t) - Gamma(t0) on the output grid after t0: its slope,
    range, first and last points."""
    prob = cx.prob
    idx = cx.grid_idx()[1:]
    tt = cx.t0 + cx.dt * idx
    mx = np.max(traj[idx, :prob.field_size()], axis=1)
    if len(idx) < 2 or not np.all(mx > 0):
        return {}
    dd = np.log(mx) + np.array([xm.dGamma(prob, cx.t0, x - cx.t0) for x in tt])
    return {"field-drift.slope": xmt.lsq_slope(tt, dd), "field-drift.range": float(dd.max() - dd.min()),
            "field-drift.first": [float(tt[0]), float(dd[0])],
            "field-drift.last": [float(tt[-1]), float(dd[-1])], "field-drift.points": float(len(idx))}


def recompute(cx: RunCtx) -> None:
    if hasattr(cx.prob, "field_size"):
        cx.mm.update(drift(cx, cx.traj))


def member(cx: RunCtx, traj: np.ndarray, ensemble: bool) -> Dict[str, Any]:
    """d(t) of a member of our ensemble (a chaotic or unstable run: the bands of its metrics)."""
    return drift(cx, traj) if ensemble and hasattr(cx.prob, "field_size") else {}


register(Diagnostic("field-drift", trajectory=True, run=recompute, grid=member))
