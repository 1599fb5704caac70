"""cost: per-step evaluation and Newton counts; an explicit method's exactly (steps x stages),
an implicit one's as the range of a family of correct Newton solvers (verify/xnewton.py, computed
by the run-level core, verify/xours.py, which also serves checks on the run's counts)."""
from __future__ import annotations

from .. import xmethods as xm
from ..xrunctx import RunCtx
from . import Diagnostic, register


def recompute(cx: RunCtx) -> None:
    if cx.method in xm.EXPLICIT_EVALS:
        cx.mm.update({"cost.rhs_evals_per_step": float(xm.EXPLICIT_EVALS[cx.method]),
                      "cost.max_newton_iters": 0, "cost.jac_evals_per_step": 0.0,
                      "cost.newton_iters_per_step": 0.0})


register(Diagnostic("cost", newton_counts=True, run=recompute))
