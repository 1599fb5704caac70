"""energy-balance: B (3.4)'s residual of the energy balance law on the output grid."""
from __future__ import annotations

import numpy as np

from .. import xmetrics as xmt
from ..xmetrics import EPS, Undef
from ..xrunctx import RunCtx
from . import Diagnostic, register


def recompute(cx: RunCtx) -> None:
    """R_n = |D_t H_n + 2 gamma p.grad T| with the 8th-order central difference on the output
    grid (interior points)."""
    if len(cx.grid_idx()) < 10:
        return
    Zg = cx.traj[cx.grid_idx()]
    Hg = cx.prob.energy(Zg)
    w8 = np.array([1 / 280, -4 / 105, 1 / 5, -4 / 5, 0.0, 4 / 5, -1 / 5, 4 / 105, -1 / 280])
    dlt = cx.stride * cx.dt
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
