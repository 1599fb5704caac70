"""error: the error against OUR reference (exact solution or certified DOP853) on the case's
output grid, and the case's named measures (docs/conventions.md)."""
from __future__ import annotations

import numpy as np

from .. import xmetrics as xmt
from ..xmetrics import TINY, Undef
from ..xrunctx import RunCtx
from . import Diagnostic, register


def max_rel_band(e: np.ndarray, rn: np.ndarray, bound: float) -> float:
    """How far max_n e_n / |z_ref(t_n)| can move when every e_n moves by at most `bound`: each
    ratio by w_n = bound / |z_ref(t_n)|; the other's maximum is at a point n whose ratio is within
    the argmax's w of ours (a_n + w_n >= M - w_argmax), so the band is the larger of w_argmax and
    a_n + w_n - M over those points -- not bound / min |z_ref|, which a point far below the
    maximum (the solution passing near the origin) would set."""
    with np.errstate(divide="ignore", invalid="ignore"):
        a, w = e / rn, bound / np.maximum(rn, TINY)
    if not len(a) or not np.isfinite(a).all():
        return bound / max(float(np.min(rn)) if len(rn) else 0.0, TINY)
    k = int(np.argmax(a))
    cand = a + w >= a[k] - w[k]
    return float(max(w[k], np.max((a + w - a[k])[cand])))


def recompute(cx: RunCtx) -> None:
    """error.* on the output grid; our reference's own estimate only (never the report's)."""
    idx = cx.grid_idx() if cx.traj is not None else np.array([cx.nsteps])
    times = cx.t0 + idx * cx.dt
    Zr, est, note = xmt.reference_states(cx.prob, cx.case, times)
    Z = cx.traj[idx] if cx.traj is not None else cx.mine["z"][None, :]
    e = np.linalg.norm(Z - Zr, axis=-1)
    rn = np.linalg.norm(Zr, axis=-1)
    # relative error defined where |z_ref| >= max(DBL_MIN, 100 x the estimate) (conventions)
    rel_ok = (rn >= xmt.DBL_MIN) & (rn >= 100 * est)
    ri = slice(1, None) if len(e) > 1 else slice(0, None)
    cx.mm.update({
        "error.final_abs": float(e[-1]),
        "error.final_rel": float(e[-1] / rn[-1]) if rel_ok[-1] else Undef("|z_ref(t_end)| below floor"),
        "error.max_abs": float(e.max()),
        "error.max_rel": float(np.max(e[ri] / rn[ri])) if rel_ok[ri].all() else Undef("|z_ref| below floor on the grid"),
        "error.mean_abs": float(e[1:].mean()) if len(e) > 1 else float(e[0]),
        "error.reference_error_estimate": est})
    cx.priv.update({"error.est": est, "error.ref_norm": float(rn[-1]), "error.ref_final": Zr[-1],
                    "error.final_rel.band": (cx.state_bound + est) / max(float(rn[-1]), TINY),
                    "error.max_rel.band": max_rel_band(e[ri], rn[ri], cx.state_bound + est)})
    cx.notes.append("our reference: %s, estimate %.2g" % (note, est))
    for key in ("final_abs", "max_abs", "mean_abs"):
        cx.unc["error." + key] = cx.state_bound + est
    for key in ("final_rel", "max_rel"):
        cx.unc["error." + key] = cx.priv["error." + key + ".band"]
    if cx.case.get("measures") is not None or cx.spec.get("measures"):
        mspec = dict(cx.case, measures=cx.spec.get("measures") or cx.case.get("measures"))
        for name, (val, fl) in xmt.measures(cx.prob, mspec, Z, Zr, times, cx.state_bound + est).items():
            cx.mm["measure." + name] = val
            cx.measure_floor["measure." + name] = fl


register(Diagnostic("error", trajectory=True, final_state=True, run=recompute))
