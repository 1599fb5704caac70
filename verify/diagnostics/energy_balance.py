"""energy-balance: B (3.4)'s residual of the energy balance law over the run's steps."""
from __future__ import annotations

import numpy as np

from .. import xmetrics as xmt
from ..xmetrics import EPS, Undef
from ..xrunctx import RunCtx
from . import Diagnostic, register


def recompute(cx: RunCtx) -> None:
    """R_n = |D_t H_n + 2 gamma p.grad T| with the 8th-order central difference over the run's
    steps (B (3.4): the difference quotient of the numerical energies, step by step, whatever
    the output grid), at every step with four steps on either side."""
    if cx.nsteps + 1 < 9:
        return
    Zg = cx.traj[: cx.nsteps + 1]
    Hg = cx.prob.energy(Zg)
    w8 = np.array([1 / 280, -4 / 105, 1 / 5, -4 / 5, 0.0, 4 / 5, -1 / 5, 4 / 105, -1 / 280])
    dlt = cx.dt
    D = np.convolve(Hg, w8[::-1], mode="valid") / dlt
    pg = Zg[4:-4, cx.prob.nq:]
    diss = 2 * cx.prob.g * np.sum(pg * cx.prob.dT(pg), axis=-1)
    Rb = np.abs(D + diss)
    cx.diss_max = float(diss.max())
    cx.mm.update({"energy-balance.max": float(Rb.max()), "energy-balance.mean": float(Rb.mean()),
                  "energy-balance.max_rel": float(Rb.max() / diss.max()) if diss.max() >= xmt.DBL_MIN
                  else Undef("max |dH/dt| is 0"),
                  "energy-balance.max_rate": float(np.max(np.abs(diss))),
                  "energy-balance.last": float(Rb[-1]), "energy-balance.points": len(Rb)})
    cx.eb_floor = 8 * EPS * float(np.max(np.abs(Hg))) * float(np.sum(np.abs(w8))) / dlt


register(Diagnostic("energy-balance", trajectory=True, run=recompute))
