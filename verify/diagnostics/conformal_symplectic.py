"""conformal-symplectic: E_n, the defect of the conformal symplectic relation of one step's
Jacobian (B (2.6)), at every step of our run."""
from __future__ import annotations

import numpy as np

from .. import xmethods as xm
from .. import xmetrics as xmt
from ..xrunctx import RunCtx, put
from . import Diagnostic, register


def recompute(cx: RunCtx) -> None:
    """Defined for a one-step map of the state (a multivalue method steps more than the state)
    on a problem with a (conformal) symplectic structure."""
    prob = cx.prob
    has_cs = prob.canonical or (hasattr(prob, "structure") and prob.structure() is not None)
    if not has_cs or cx.method in xm.MULTIVALUE:
        return
    vals = xmt.metric_conformal_symplectic(cx.method, prob, cx.dt, cx.t0, cx.traj)
    put(cx, "conformal-symplectic.", vals)
    cx.mm["conformal-symplectic.status"] = "ok" if np.all(np.isfinite(vals["_Er"])) else "diverged"


register(Diagnostic("conformal-symplectic", trajectory=True, run=recompute))
