"""poincare: the Poincare section of a periodically forced problem (B Fig 3.5) against OUR
reference's, section by section."""
from __future__ import annotations

from typing import Any, Dict

import numpy as np

from .. import xmetrics as xmt
from ..xrunctx import RunCtx
from . import Diagnostic, register


def grid(cx: RunCtx, traj: np.ndarray, ensemble: bool) -> Dict[str, Any]:
    prob = cx.prob
    if not prob.forcing_period:
        return {}
    st = int(round(prob.forcing_period / cx.dt))
    Zs, _, _ = xmt.reference_states(prob, cx.case, cx.t0 + cx.dt * np.arange(0, cx.nsteps + 1, st))
    return {"poincare." + k: v for k, v in xmt.poincare_metrics(prob, traj, cx.dt, Zs).items()
            if not (ensemble and k in ("sections", "transient_skipped"))}


def member(cx: RunCtx, alt: Dict[str, Any]) -> None:
    """The set distance of an ensemble member's section (the Hausdorff comparison's scale)."""
    if "poincare.set_hausdorff" in alt:
        cx.priv["poincare._alt_hausdorff"] = alt["poincare.set_hausdorff"]


def chaotic_reference(cx: RunCtx) -> bool:
    """A case whose reference is itself chaotic (its certified estimate is not small): every
    reference-dependent metric is statistical."""
    if not (cx.prob.forcing_period and cx.traj is not None):
        return False
    stp = int(round(cx.prob.forcing_period / cx.dt))
    ts = cx.t0 + cx.dt * np.arange(0, cx.nsteps + 1, stp)
    return bool(xmt.reference_states(cx.prob, cx.case, ts)[1] > 1e-6)


register(Diagnostic("poincare", trajectory=True, grid=grid, member=member, chaotic_reference=chaotic_reference))
