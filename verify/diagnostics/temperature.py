"""temperature: the kinetic temperature of a particle system on the output grid."""
from __future__ import annotations

from typing import Any, Dict

import numpy as np

from .. import xmetrics as xmt
from ..xrunctx import RunCtx
from . import Diagnostic, register


def grid(cx: RunCtx, traj: np.ndarray, ensemble: bool) -> Dict[str, Any]:
    if not hasattr(cx.prob, "temperature"):
        return {}
    return {"temperature." + k: v for k, v in xmt.metric_temperature(cx.prob, traj[cx.grid_idx()]).items()}


# our ensemble's relative final-state spread above which a chaotic run has decorrelated by its end
DECORRELATED = 1e-3


def member(cx: RunCtx, alt: Dict[str, Any]) -> None:
    """A chaotic run that decorrelates (D > DECORRELATED): the extremes of T over the run are
    extremes of another sample of the attractor once the runs part, and a few members a round-off
    apart need not reach the other program's (argon-verlet-steps with a Stormer-Verlet method
    file: ours and four members 2.8819 at t = 0.028, dampsym's 2.7819 later): their band is
    16 x the range of our T, which makes them "not comparable"; T(t0) and the mean keep theirs."""
    lo, hi = cx.mm.get("temperature.min"), cx.mm.get("temperature.max")
    if cx.D <= DECORRELATED or not isinstance(lo, float) or not isinstance(hi, float):
        return
    for k in ("min", "max", "max_abs_dev_initial"):
        key = "temperature." + k
        if isinstance(cx.mm.get(key), float):
            cx.band[key] = max(cx.band.get(key, 0.0), 16.0 * (hi - lo))


register(Diagnostic("temperature", trajectory=True, grid=grid, member=member))
