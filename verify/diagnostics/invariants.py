"""invariants: each first integral's law (B, F) checked at every step of our run."""
from __future__ import annotations

import numpy as np

from .. import xmetrics as xmt
from ..xrunctx import RunCtx, put
from . import Diagnostic, register


def recompute(cx: RunCtx) -> None:
    times = cx.t0 + cx.dt * np.arange(len(cx.traj))
    for name, vals in xmt.metric_invariants(cx.prob, cx.traj, times, cx.dt).items():
        put(cx, "invariants.%s." % name, vals)


register(Diagnostic("invariants", trajectory=True, run=recompute))
