"""local-error: one step from z0 against the problem's exact solution."""
from __future__ import annotations

import numpy as np

from .. import xrun
from ..xmetrics import EPS, Undef
from ..xrunctx import RunCtx
from . import Diagnostic, register


def recompute(cx: RunCtx) -> None:
    """The one-step error; its floor 8 eps |z| + our exact solution's estimate."""
    if not cx.prob.exact_available:
        return
    z1 = xrun.integrate(cx.method, cx.prob, cx.dt, 1, cx.t0)["z"]
    ze = cx.prob.exact(cx.t0, [cx.t0 + cx.dt])[0]
    la, nze = float(np.linalg.norm(z1 - ze)), float(np.linalg.norm(ze))
    cx.priv["local-error.floor"] = 8 * EPS * nze + getattr(cx.prob, "exact_estimate", 0.0)
    cx.priv["local-error.norm"] = nze
    cx.mm["local-error.abs"] = la
    cx.mm["local-error.rel"] = la / nze if nze > 0 else Undef("exact solution at t0 + h has norm 0")


register(Diagnostic("local-error", run=recompute))
