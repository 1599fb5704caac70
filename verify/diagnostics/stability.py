"""stability: the one-step matrix M of a method on the linear oscillator, its determinant, half
trace and eigenvalues (B §2, F §3)."""
from __future__ import annotations

import numpy as np

from .. import xmethods as xm
from .. import xmetrics as xmt
from .. import xproblems as xp
from ..xrunctx import RunCtx
from . import Diagnostic, register


def recompute(cx: RunCtx) -> None:
    """A function of (method, problem, dt) alone: defined whether or not the run finished."""
    # a multivalue method's one-step matrix acts on its whole multivalue state, which the
    # cross-check does not build: its stability metrics are then "not reproduced" by name
    if not isinstance(cx.prob, xp.Oscillator) or cx.method in xm.MULTIVALUE:
        return
    cx.mm.update({"stability." + k: v for k, v in xmt.metric_stability(cx.method, cx.prob, cx.dt).items()})
    ev = np.linalg.eigvals(np.array(cx.mm["stability.matrix"]))
    cx.mm["stability.eigenvalues"] = [[float(e.real), float(e.imag)] for e in ev]


register(Diagnostic("stability", keeps_failed=True, run=recompute))
