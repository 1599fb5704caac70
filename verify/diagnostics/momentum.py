"""momentum: the N-body momentum laws (B Table 3.1) at every step of our run."""
from __future__ import annotations

from typing import Any, Dict

import numpy as np

from .. import xmetrics as xmt
from ..xrunctx import RunCtx, put
from . import Diagnostic, register


def recompute(cx: RunCtx) -> None:
    if not hasattr(cx.prob, "linear_momentum"):
        return
    for kk, vals in xmt.metric_momentum(cx.prob, cx.traj, cx.dt, cx.method).items():
        put(cx, "momentum.%s." % kk, vals)


def member(cx: RunCtx, traj: np.ndarray, ensemble: bool) -> Dict[str, Any]:
    """The public momentum metrics of an ensemble member (ours are computed per step above)."""
    if not (ensemble and hasattr(cx.prob, "linear_momentum")):
        return {}
    return {"momentum.%s.%s" % (kk, k): v for kk, vals in xmt.metric_momentum(cx.prob, traj, cx.dt, cx.method).items()
            for k, v in vals.items() if not k.startswith("_")}


register(Diagnostic("momentum", trajectory=True, run=recompute, grid=member))
