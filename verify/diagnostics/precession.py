"""precession: HLW Fig 2.1's turn of the Runge-Lenz vector, every step, against OUR reference's;
the largest turn between two output grid points."""
from __future__ import annotations

import math

import numpy as np

from .. import xmetrics as xmt
from ..xrunctx import RunCtx, put
from . import Diagnostic, register


def recompute(cx: RunCtx) -> None:
    if not (hasattr(cx.prob, "runge_lenz") and len(cx.traj) >= 2):
        return
    Zr, _, _ = xmt.reference_states(cx.prob, cx.case, cx.t0 + cx.dt * np.arange(len(cx.traj)))
    pm = xmt.metric_precession(cx.prob, cx.traj, Zr)
    pm["rate"] = pm["total"] / (cx.dt * (len(cx.traj) - 1))
    A = cx.prob.runge_lenz(cx.traj[cx.grid_idx()])
    dphi = np.diff(np.arctan2(A[:, 1], A[:, 0]))
    pm["max_grid_step"] = float(np.max(np.abs(np.remainder(dphi + math.pi, 2 * math.pi) - math.pi)))
    put(cx, "precession.", pm)


register(Diagnostic("precession", trajectory=True, run=recompute))
