"""energy: H = T + V on the output grid (F Fig 4.3), and with `error` H(reference) - H(method)."""
from __future__ import annotations

from typing import Any, Dict

import numpy as np

from .. import xmetrics as xmt
from ..xmetrics import Undef
from ..xrunctx import RunCtx
from . import Diagnostic, register


def grid(cx: RunCtx, traj: np.ndarray, ensemble: bool) -> Dict[str, Any]:
    idx = cx.grid_idx()
    tt = cx.t0 + cx.dt * np.arange(len(traj))
    return {"energy." + k: v for k, v in xmt.metric_energy(cx.prob, traj[idx], tt[idx]).items()}


def grad_norm_max(prob: Any, Z: np.ndarray) -> float:
    """max over the points of |grad H(z)|_2, by forward differences along each coordinate
    (step sqrt(eps) of the coordinate's scale): a bound's scale, not a derivative to compare."""
    Z = np.asarray(Z, float)
    H0 = prob.energy(Z)
    g2 = np.zeros(len(Z))
    for k in range(Z.shape[-1]):
        d = 1.5e-8 * max(float(np.max(np.abs(Z[:, k]))), 1.0)
        Zk = Z.copy()
        Zk[:, k] += d
        g2 += ((prob.energy(Zk) - H0) / d) ** 2
    return float(np.sqrt(np.max(g2))) if len(g2) else 0.0


def energy_error(cx: RunCtx) -> None:
    """F Fig 4.3: H(reference) - H(method) on the output grid (when the case asks for errors)."""
    if not cx.wants("error"):
        return
    idx = cx.grid_idx()
    tt = cx.t0 + idx * cx.dt
    Zr, _, _ = xmt.reference_states(cx.prob, cx.case, tt)
    de = cx.prob.energy(Zr) - cx.prob.energy(cx.traj[idx])
    # these four carry the reference's error through H: |grad H(z_ref)| x (state bound + our
    # estimate) (xfamilies.f_energy), |grad H| by differences along each coordinate
    cx.priv["energy.grad_max"] = grad_norm_max(cx.prob, Zr)
    cx.mm["energy.max_abs_error"] = float(np.max(np.abs(de)))
    cx.mm["energy.final_abs_error"] = float(abs(de[-1]))
    cx.mm["energy.drift_slope"] = xmt.lsq_slope(tt, de)
    if cx.prob.energy_scale is not None:
        Sr = cx.prob.energy_scale(Zr)
        cx.mm["energy.error_res_slope"] = (xmt.lsq_slope(tt, de / Sr) if xmt.scale_ok(Sr).all()
                                           else Undef("energy scale of the reference not normal"))


register(Diagnostic("energy", trajectory=True, run=energy_error, grid=grid))
