"""pde-error: B Fig 5.4's max-norm error against the PDE's own solution on the grid, at the
output times without t0."""
from __future__ import annotations

from typing import List

import numpy as np

from ..xrunctx import RunCtx
from . import Diagnostic, register


def recompute(cx: RunCtx) -> None:
    """Nothing when the problem declares no solution up to some output time (after a shock)."""
    prob, traj = cx.prob, cx.traj
    if not hasattr(prob, "pde_solution"):
        return
    errs: List[float] = []
    rels: List[float] = []
    for i in cx.grid_idx()[1:]:
        u = prob.pde_solution(cx.t0, cx.t0 + cx.dt * i)
        if u is None:
            return
        e = float(np.max(np.abs(traj[i, :len(u)] - u)))
        errs.append(e)
        rels.append(e / float(np.max(np.abs(u))))
    if errs:
        cx.mm.update({"pde-error.max_abs": max(errs), "pde-error.final_abs": errs[-1],
                      "pde-error.max_rel": max(rels), "pde-error.points": float(len(errs))})


register(Diagnostic("pde-error", trajectory=True, run=recompute))
