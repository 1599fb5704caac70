"""field-drift: B (5.6), ln max u + Gamma(t) on the output grid without t0."""
from __future__ import annotations

import numpy as np

from .. import xmethods as xm
from .. import xmetrics as xmt
from ..xrunctx import RunCtx
from . import Diagnostic, register


def recompute(cx: RunCtx) -> None:
    prob, traj = cx.prob, cx.traj
    if not hasattr(prob, "field_size"):
        return
    idx = cx.grid_idx()[1:]
    tt = cx.t0 + cx.dt * idx
    mx = np.max(traj[idx, :prob.field_size()], axis=1)
    if len(idx) >= 2 and np.all(mx > 0):
        dd = np.log(mx) + np.array([xm.dGamma(prob, cx.t0, x - cx.t0) for x in tt])
        cx.mm.update({"field-drift.slope": xmt.lsq_slope(tt, dd), "field-drift.range": float(dd.max() - dd.min()),
                      "field-drift.first": [float(tt[0]), float(dd[0])],
                      "field-drift.last": [float(tt[-1]), float(dd[-1])], "field-drift.points": float(len(idx))})


register(Diagnostic("field-drift", trajectory=True, run=recompute))
