"""attractor: the statistics of a driven PDE's probe over the second half of the run (B Fig
5.10)."""
from __future__ import annotations

from typing import Any, Dict

import numpy as np

from .. import xmetrics as xmt
from ..xrunctx import RunCtx
from . import Diagnostic, register


def grid(cx: RunCtx, traj: np.ndarray, ensemble: bool) -> Dict[str, Any]:
    if not hasattr(cx.prob, "probe"):
        return {}
    return {"attractor." + k: v for k, v in
            xmt.metric_attractor(cx.prob, traj, cx.t0, cx.dt, cx.nsteps, cx.stride).items()}


def member(cx: RunCtx, alt: Dict[str, Any]) -> None:
    """A standard error from 10 batch means varies by 1/sqrt(18) = 24 % between samples: its
    band is at least the value itself."""
    for k in ("attractor.mean_se", "attractor.mean_rse"):
        if isinstance(cx.mm.get(k), float) and isinstance(alt.get(k), float):
            cx.band[k] = max(cx.band[k], abs(cx.mm[k]))


register(Diagnostic("attractor", trajectory=True, grid=grid, member=member))
