"""invariants: each first integral's law (B, F) checked at every step of our run."""
from __future__ import annotations

from typing import Any, Dict

import numpy as np

from .. import xmetrics as xmt
from ..xrunctx import RunCtx, put
from . import Diagnostic, register


def recompute(cx: RunCtx) -> None:
    times = cx.t0 + cx.dt * np.arange(len(cx.traj))
    for name, vals in xmt.metric_invariants(cx.prob, cx.traj, times, cx.dt).items():
        put(cx, "invariants.%s." % name, vals)


def member(cx: RunCtx, traj: np.ndarray, ensemble: bool) -> Dict[str, Any]:
    """The public invariant metrics of a member of our ensemble (a chaotic or unstable run: their
    bands; ours are computed per step above)."""
    if not ensemble:
        return {}
    times = cx.t0 + cx.dt * np.arange(len(traj))
    return {"invariants.%s.%s" % (name, k): v
            for name, vals in xmt.metric_invariants(cx.prob, traj, times, cx.dt).items()
            for k, v in vals.items() if not k.startswith("_")}


register(Diagnostic("invariants", trajectory=True, run=recompute, grid=member))
