"""dissipation-drift: d(t) of F (4.4) at the maxima of q, with the reference's d(t) from OUR
reference when the case asks for errors."""
from __future__ import annotations

import numpy as np

from .. import xmetrics as xmt
from ..xrunctx import RunCtx, put
from . import Diagnostic, register


def recompute(cx: RunCtx) -> None:
    if cx.prob.nq != 1:
        return
    traj, times = cx.traj, cx.t0 + cx.dt * np.arange(len(cx.traj))
    dd = xmt.dissipation_drift(cx.prob, traj, cx.t0, cx.dt)
    put(cx, "dissipation-drift.", {k: v for k, v in dd.items() if k != "_d"})
    if not cx.wants("error"):
        return
    Zr, _, _ = xmt.reference_states(cx.prob, cx.case, times)
    rd = xmt.dissipation_drift(cx.prob, Zr, cx.t0, cx.dt)
    put(cx, "dissipation-drift.reference.", {k: v for k, v in rd.items() if k != "_d"})
    k_ = min(len(dd["_d"]), len(rd["_d"]))
    cx.mm["dissipation-drift.max_abs_diff_reference"] = float(np.max(np.abs(dd["_d"][:k_] - rd["_d"][:k_]))) if k_ else 0.0
    cx.mm["dissipation-drift.maxima_count_diff"] = dd["maxima"] - rd["maxima"]
    if isinstance(dd.get("slope"), float) and isinstance(rd.get("slope"), float):
        cx.mm["dissipation-drift.slope_minus_reference"] = dd["slope"] - rd["slope"]


register(Diagnostic("dissipation-drift", trajectory=True, run=recompute))
