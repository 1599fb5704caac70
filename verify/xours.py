"""OUR side of one run for verify/crosscheck.py: the integration (step count and output grid from
the case file, verify/xcase.py), the round-off floor of the final state from our own ensemble,
and every metric of the run from our trajectory (verify/xmetrics.py), with the bands (our own
round-off or sampling uncertainty of each metric) that the comparisons and the verdicts use."""
from __future__ import annotations

import math
from typing import Any, Dict

import numpy as np

from . import diagnostics
from . import xmethods as xm
from . import xnewton
from . import xrun
from .xmetrics import EPS, TINY
from .xrunctx import CHAOS_D, FLOOR_K, TOL_STATE, RunCtx, put

__all__ = ["CHAOS_D", "FLOOR_K", "TOL_STATE", "RunCtx", "integrate", "state_tolerance", "all_metrics"]

def integrate(cx: RunCtx) -> None:
    """Our run over the case file's step count; run-level counts of an explicit method."""
    need = any(d.trajectory for d in diagnostics.enabled(cx.diags))
    status = cx.run.get("status", "ok")
    cx.mine = xrun.integrate(cx.method, cx.prob, cx.dt, cx.nsteps, cx.t0, record=need,
                             blowup=None if status == "ok" else 1e100)
    st = cx.mine["steps"]
    cx.mm.update({"run.steps": st, "run.steps_planned": cx.nsteps, "run.ok": int(cx.mine["status"] == "ok"),
                  "run.diverged": int(cx.mine["status"] == "diverged"),
                  "run.failed_at_step": st if cx.mine["status"] != "ok" else 0,
                  "run.final_time": cx.t0 + st * cx.dt})
    if cx.method in xm.EXPLICIT_EVALS:
        cx.mm.update({"run.rhs_evals": st * xm.EXPLICIT_EVALS[cx.method], "run.jac_evals": 0,
                      "run.newton_iters": 0, "run.max_newton_iters_per_step": 0})
    for d in diagnostics.enabled(cx.diags):
        if d.keeps_failed and d.run is not None:
            d.run(cx)


def _perturbed(cx: RunCtx, z0: np.ndarray, t0: float, n: int, record: bool) -> Dict[str, Any]:
    """Our run from z0 instead of the problem's initial state."""
    keep = cx.prob.z0
    cx.prob.z0 = z0
    try:
        return xrun.integrate(cx.method, cx.prob, cx.dt, n, t0, record=record)
    finally:
        cx.prob.z0 = keep


def kicked(z: np.ndarray, k: float) -> np.ndarray:
    """z with every component moved by k of itself (a RELATIVE kick: argon's momenta are 1e-23,
    its positions 1e-9; the outer solar system's sun at 0 stays there); z = 0 by k (the driven
    pendulum from rest)."""
    z = np.asarray(z, float)
    return z * (1 + k) if np.any(z != 0.0) else np.full_like(z, k)


def ensemble_spread(cx: RunCtx, need_traj: bool, force: bool = False) -> None:
    """How far two computations that differ at round-off drift apart: our run from z0 kicked by
    4 eps relative, and (but for glm4 and kg-box, which step r values or two levels) from z_{n/2}
    kicked by 4 eps, since an early contracting transient can absorb a kick at t0.  D = the larger
    relative final-state spread.  A chaotic run (D > 1e-8) gets a third member for the metric bands, kicked at t0 by
    4 n eps (the other program rounds differently at EVERY step, and roundings may share a sign:
    a single 4-eps kick decorrelates later than dampsym's run does, argon-verlet-steps)."""
    z, n = cx.mine["z"], cx.nsteps
    z0 = np.asarray(cx.prob.z0, float)
    pert = _perturbed(cx, kicked(z0, 4 * EPS), cx.t0, n, need_traj)
    D = float(np.linalg.norm(pert["z"] - z)) / cx.scale
    members = [pert]
    if cx.method not in xm.MULTIVALUE and cx.method not in xm.TWO_LEVEL and n >= 2:
        half = n // 2
        zm = xrun.integrate(cx.method, cx.prob, cx.dt, half, cx.t0)["z"]
        zb = _perturbed(cx, kicked(zm, 4 * EPS), cx.t0 + half * cx.dt, n - half, need_traj)
        D = max(D, float(np.linalg.norm(zb["z"] - z)) / cx.scale)
        if need_traj and cx.traj is not None and zb.get("traj") is not None:
            members.append(dict(z=zb["z"], traj=np.concatenate([cx.traj[:half], zb["traj"]])))
    cx.D = D
    if (D > CHAOS_D or force) and need_traj:
        members.append(_perturbed(cx, kicked(z0, 4 * n * EPS), cx.t0, n, True))
        cx.chaotic = dict(pert, members=members)


def chaotic_reference(cx: RunCtx) -> bool:
    """A run whose case's reference is itself chaotic (a diagnostic says so): every
    reference-dependent metric is statistical."""
    return any(d.chaotic_reference(cx) for d in diagnostics.enabled(cx.diags) if d.chaotic_reference is not None)


def state_tolerance(cx: RunCtx, theirs: np.ndarray) -> str:
    """Our relative tolerance of the final state: TOL_STATE, the linear path's 4 n eps, or when
    the states differ by more, our round-off floor 16 D (module docstring of crosscheck.py)."""
    z = cx.mine["z"]
    cx.scale = max(float(np.linalg.norm(theirs)) if theirs.shape == z.shape else 0.0,
                   float(np.linalg.norm(z)), TINY)
    note = ""
    if cx.mine.get("linear_path"):
        cx.tol = max(cx.tol, 4 * cx.nsteps * EPS)
        note = "linear path, 4 n eps"
    diff = float(np.linalg.norm(z - theirs)) if theirs.shape == z.shape else math.inf
    chaos_ref = chaotic_reference(cx)
    if (diff > cx.tol * cx.scale or chaos_ref) and math.isfinite(diff):
        ensemble_spread(cx, cx.traj is not None, force=chaos_ref)
        if FLOOR_K * cx.D > cx.tol:
            cx.tol = FLOOR_K * cx.D
            note = "round-off floor 16 D, D = %.3g from our own ensemble" % cx.D
    cx.state_bound = cx.tol * cx.scale
    return note


def newton_counts(cx: RunCtx) -> None:
    """Newton counts of an implicit method: the range of a stated family of correct solvers
    (verify/xnewton.py), where a diagnostic needs them or a check reads a run count."""
    run_counts = {"run.newton_iters", "run.rhs_evals", "run.jac_evals"}
    asked = any(d.newton_counts for d in diagnostics.enabled(cx.diags)) or any(
        c.get("metric") in run_counts and (c.get("methods") == "all" or cx.method in (c.get("methods") or []))
        for c in (cx.spec.get("expect") or {}).values())
    if cx.method not in xm.IMPLICIT or not xnewton.supported(cx.method) or not asked:
        return
    if cx.method in xm.MULTIVALUE:
        gy = cx.mine.get("glm_y")
        if gy is None:
            gy = xrun.integrate(cx.method, cx.prob, cx.dt, cx.nsteps, cx.t0, record=True).get("glm_y")
        cx.cost_range = xnewton.glm_cost_metrics(cx.prob, cx.dt, cx.t0, gy, xm.glm_coefficients(cx.method))
    elif cx.mine.get("linear_path"):
        size = xnewton._coef(cx.method, cx.prob, cx.dt)[1](cx.t0)[2].size
        cx.cost_range = xnewton.linear_cost_metrics(cx.method, size, cx.nsteps)
    else:
        tr = cx.traj if cx.traj is not None else xrun.integrate(
            cx.method, cx.prob, cx.dt, cx.nsteps, cx.t0, record=True)["traj"]
        cx.cost_range = xnewton.cost_metrics(cx.method, cx.prob, cx.dt, cx.t0, tr)
    for k, (o, lo, hi) in cx.cost_range.items():
        cx.mm[k] = o
        cx.unc[k] = max(hi - o, o - lo)
    if "run.newton_iters" in cx.cost_range and "cost.max_newton_iters" in cx.cost_range:
        cx.cost_range.setdefault("run.max_newton_iters_per_step", cx.cost_range["cost.max_newton_iters"])
        cx.mm.setdefault("run.max_newton_iters_per_step", cx.cost_range["cost.max_newton_iters"][0])


def grid_metrics(cx: RunCtx, traj: np.ndarray, ensemble: bool = False) -> Dict[str, Any]:
    """Every enabled diagnostic's metrics on the output grid of `traj` (ours, or a member of our
    ensemble: only those an ensemble band is taken of)."""
    out: Dict[str, Any] = {}
    for d in diagnostics.enabled(cx.diags):
        if d.grid is not None:
            out.update(d.grid(cx, traj, ensemble))
    return out


def _floats(v: Any) -> bool:
    return isinstance(v, list) and all(isinstance(x, float) for x in v)


def ensemble_band(cx: RunCtx) -> None:
    """Chaotic run: our two runs a round-off apart diverge; each trajectory metric gets the band
    16 |m - m'| (the C++ run is a third member), adjusted by its diagnostic (`member`)."""
    if cx.chaotic is None or cx.chaotic.get("traj") is None:
        return
    for mem in cx.chaotic.get("members") or [cx.chaotic]:
        alt = grid_metrics(cx, mem["traj"], ensemble=True)
        for k, v in alt.items():
            mine = cx.mm.get(k)
            if isinstance(mine, float) and isinstance(v, float):
                cx.band[k] = max(cx.band.get(k, 0.0), FLOOR_K * abs(mine - v))
            elif isinstance(mine, list) and _floats(mine) and _floats(v) and len(mine) == len(v):
                # per entry: the widest
                cx.band[k] = max([cx.band.get(k, 0.0)] + [FLOOR_K * abs(a - b) for a, b in zip(mine, v)])
        for d in diagnostics.enabled(cx.diags):
            if d.member is not None:
                d.member(cx, alt)
    cx.notes.append("chaotic run (our ensemble spread D = %.3g): metric bands from it" % cx.D)


def all_metrics(cx: RunCtx) -> None:
    """Every metric of the case's diagnostics from our run (after the final state is judged):
    each enabled diagnostic's run and grid hooks (those that need our trajectory only when it
    was recorded), the Newton counts, the ensemble bands of a chaotic run."""
    for d in diagnostics.enabled(cx.diags):
        if d.keeps_failed:
            continue
        if d.grid is not None and cx.traj is not None:
            put(cx, "", d.grid(cx, cx.traj, False))
        if d.run is not None and (cx.traj is not None or not d.trajectory or d.final_state):
            d.run(cx)
    newton_counts(cx)
    ensemble_band(cx)
