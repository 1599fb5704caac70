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


register(Diagnostic("temperature", trajectory=True, grid=grid))
