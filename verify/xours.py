"""OUR side of one run for verify/crosscheck.py: the integration (step count and output grid from
the case file, verify/xcase.py), the round-off floor of the final state from our own ensemble,
and every metric of the run from our trajectory (verify/xmetrics.py), with the bands (our own
round-off or sampling uncertainty of each metric) that the comparisons and the verdicts use."""
from __future__ import annotations

import math
from typing import Any, Dict, List, Optional

import numpy as np

import xmethods as xm
import xmetrics as xmt
import xnewton
import xproblems as xp
import xrun
from xmetrics import EPS, TINY, Undef

TOL_STATE = {"explicit": 1e-12, "implicit": 1e-10}
FLOOR_K = 16.0
CHAOS_D = 1e-8      # our ensemble's relative spread above which a run's metrics are statistical
TRAJ_DIAGS = ("error", "invariants", "energy", "momentum", "temperature", "conformal-symplectic",
              "dissipation-drift", "poincare", "precession", "field-drift", "pde-error", "attractor",
              "energy-balance")


class RunCtx:
    """Everything known about one run (method, dt) of a case: the inputs from the case file,
    our integration and metrics, and the report's run record (only to be compared)."""

    def __init__(self, case: Dict[str, Any], spec: Dict[str, Any], prob: Any, run: Dict[str, Any],
                 method: str, dt: float, nsteps: int, stride: int, diags: List[str]) -> None:
        self.case, self.spec, self.prob, self.run = case, spec, prob, run
        self.method, self.dt, self.nsteps, self.stride, self.diags = method, dt, nsteps, stride, diags
        self.t0 = float(spec.get("t0", 0.0))
        self.t_end = float(spec["t_end"])
        self.metrics: Dict[str, Any] = run.get("metrics") or {}
        self.mm: Dict[str, Any] = {}        # our metrics, flat
        self.priv: Dict[str, Any] = {}      # our private quantities (never compared)
        self.unc: Dict[str, float] = {}     # our band of a metric (verdict ties)
        self.band: Dict[str, float] = {}    # chaotic run: our ensemble band per metric
        self.cost_range: Dict[str, Any] = {}
        self.comps: List[Dict[str, Any]] = []
        self.notes: List[str] = []
        self.not_compared: Dict[str, str] = {}
        self.mine: Dict[str, Any] = {}
        self.chaotic: Optional[Dict[str, Any]] = None
        self.D = 0.0                        # our ensemble's relative final-state spread
        self.tol = TOL_STATE["implicit" if method in xm.IMPLICIT else "explicit"]
        self.scale = 1.0
        self.state_bound = 0.0
        self.measure_floor: Dict[str, float] = {}
        self.eb_floor = 0.0
        self.diss_max = 0.0

    @property
    def traj(self) -> Any:
        return self.mine.get("traj")

    def wants(self, diag: str) -> bool:
        return diag in self.diags

    def grid_idx(self) -> np.ndarray:
        """Step indices of the output grid t0, t0 + stride dt, ..., t_end."""
        return np.arange(0, self.nsteps + 1, self.stride)


def integrate(cx: RunCtx) -> None:
    """Our run over the case file's step count; run-level counts of an explicit method."""
    need = any(cx.wants(d) for d in TRAJ_DIAGS)
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
    if cx.wants("stability") and isinstance(cx.prob, xp.Oscillator):
        cx.mm.update({"stability." + k: v for k, v in xmt.metric_stability(cx.method, cx.prob, cx.dt).items()})
        ev = np.linalg.eigvals(np.array(cx.mm["stability.matrix"]))
        cx.mm["stability.eigenvalues"] = [[float(e.real), float(e.imag)] for e in ev]


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
    4 eps relative, and (but for glm4, which steps r values) from z_{n/2} kicked by 4 eps, since
    an early contracting transient can absorb a kick at t0.  D = the larger relative final-state
    spread.  A chaotic run (D > 1e-8) gets a third member for the metric bands, kicked at t0 by
    4 n eps (the other program rounds differently at EVERY step, and roundings may share a sign:
    a single 4-eps kick decorrelates later than dampsym's run does, argon-verlet-steps)."""
    z, n = cx.mine["z"], cx.nsteps
    z0 = np.asarray(cx.prob.z0, float)
    pert = _perturbed(cx, kicked(z0, 4 * EPS), cx.t0, n, need_traj)
    D = float(np.linalg.norm(pert["z"] - z)) / cx.scale
    members = [pert]
    if cx.method != "glm4" and n >= 2:
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
    """A Poincare case whose reference is itself chaotic (its certified estimate is not small):
    every reference-dependent metric is statistical."""
    if not (cx.wants("poincare") and cx.prob.forcing_period and cx.traj is not None):
        return False
    stp = int(round(cx.prob.forcing_period / cx.dt))
    ts = cx.t0 + cx.dt * np.arange(0, cx.nsteps + 1, stp)
    return bool(xmt.reference_states(cx.prob, cx.case, ts)[1] > 1e-6)


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


def cost_metrics(cx: RunCtx) -> None:
    """Newton counts of an implicit method: the range of a stated family of correct solvers
    (verify/xnewton.py); explicit methods' per-step costs exactly."""
    if cx.wants("cost") and cx.method in xm.EXPLICIT_EVALS:
        cx.mm.update({"cost.rhs_evals_per_step": float(xm.EXPLICIT_EVALS[cx.method]),
                      "cost.max_newton_iters": 0, "cost.jac_evals_per_step": 0.0,
                      "cost.newton_iters_per_step": 0.0})
    run_counts = {"run.newton_iters", "run.rhs_evals", "run.jac_evals"}
    asked = cx.wants("cost") or any(
        c.get("metric") in run_counts and (c.get("methods") == "all" or cx.method in (c.get("methods") or []))
        for c in (cx.spec.get("expect") or {}).values())
    if cx.method not in xm.IMPLICIT or not xnewton.supported(cx.method) or not asked:
        return
    if cx.method == "glm4":
        gy = cx.mine.get("glm_y")
        if gy is None:
            gy = xrun.integrate(cx.method, cx.prob, cx.dt, cx.nsteps, cx.t0, record=True).get("glm_y")
        cx.cost_range = xnewton.glm_cost_metrics(cx.prob, cx.dt, cx.t0, gy)
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


def undefined(why: str) -> Undef:
    return Undef(why)


def error_metrics(cx: RunCtx) -> None:
    """error.* on the case's output grid against OUR reference (exact or DOP853), and the
    case's named measures; our reference's own estimate only (never the report's)."""
    if not (cx.wants("error") or cx.wants("order")):
        return
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
    cx.priv.update({"error.est": est, "error.ref_norm": float(rn[-1]), "error.ref_final": Zr[-1]})
    cx.notes.append("our reference: %s, estimate %.2g" % (note, est))
    for key in ("final_abs", "max_abs", "mean_abs"):
        cx.unc["error." + key] = cx.state_bound + est
    for key in ("final_rel", "max_rel"):
        cx.unc["error." + key] = (cx.state_bound + est) / max(float(rn[-1]), TINY)
    if cx.case.get("measures") is not None or cx.spec.get("measures"):
        mspec = dict(cx.case, measures=cx.spec.get("measures") or cx.case.get("measures"))
        for name, (val, fl) in xmt.measures(cx.prob, mspec, Z, Zr, times, cx.state_bound + est).items():
            cx.mm["measure." + name] = val
            cx.measure_floor["measure." + name] = fl


def local_error(cx: RunCtx) -> None:
    """One step from z0 against the exact solution: floor 8 eps |z| + our exact estimate."""
    if not (cx.wants("local-error") and cx.prob.exact_available):
        return
    z1 = xrun.integrate(cx.method, cx.prob, cx.dt, 1, cx.t0)["z"]
    ze = cx.prob.exact(cx.t0, [cx.t0 + cx.dt])[0]
    la, nze = float(np.linalg.norm(z1 - ze)), float(np.linalg.norm(ze))
    cx.priv["local-error.floor"] = 8 * EPS * nze + getattr(cx.prob, "exact_estimate", 0.0)
    cx.priv["local-error.norm"] = nze
    cx.mm["local-error.abs"] = la
    cx.mm["local-error.rel"] = la / nze if nze > 0 else Undef("exact solution at t0 + h has norm 0")


def energy_balance(cx: RunCtx) -> None:
    """B (3.4): R_n = |D_t H_n + 2 gamma p.grad T| with the 8th-order central difference on the
    output grid (interior points)."""
    if cx.traj is None or not cx.wants("energy-balance") or len(cx.grid_idx()) < 10:
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


def _put(cx: RunCtx, prefix: str, vals: Dict[str, Any]) -> None:
    for k, v in vals.items():
        (cx.priv if k.split(".")[-1].startswith("_") else cx.mm)[prefix + k] = v


def law_metrics(cx: RunCtx) -> None:
    """Invariants, momentum, E_n (per step, every step of our run)."""
    prob, traj = cx.prob, cx.traj
    times = cx.t0 + cx.dt * np.arange(len(traj))
    if cx.wants("invariants"):
        for name, vals in xmt.metric_invariants(prob, traj, times, cx.dt).items():
            _put(cx, "invariants.%s." % name, vals)
    if cx.wants("momentum") and hasattr(prob, "linear_momentum"):
        for kk, vals in xmt.metric_momentum(prob, traj, cx.dt, cx.method).items():
            _put(cx, "momentum.%s." % kk, vals)
    has_cs = prob.canonical or (hasattr(prob, "structure") and prob.structure() is not None)
    if cx.wants("conformal-symplectic") and has_cs and cx.method != "glm4":
        vals = xmt.metric_conformal_symplectic(cx.method, prob, cx.dt, cx.t0, traj)
        _put(cx, "conformal-symplectic.", vals)
        cx.mm["conformal-symplectic.status"] = "ok" if np.all(np.isfinite(vals["_Er"])) else "diverged"


def grid_metrics(cx: RunCtx, traj: np.ndarray, ens: bool = False) -> Dict[str, Any]:
    """Metrics sampled on the output grid (energy, temperature, attractor, momentum for the
    ensemble member); `ens`: only those an ensemble band is taken of."""
    prob, out = cx.prob, {}
    idx = cx.grid_idx()
    tt = cx.t0 + cx.dt * np.arange(len(traj))
    if cx.wants("energy"):
        out.update({"energy." + k: v for k, v in xmt.metric_energy(prob, traj[idx], tt[idx]).items()})
    if cx.wants("temperature") and hasattr(prob, "temperature"):
        out.update({"temperature." + k: v for k, v in xmt.metric_temperature(prob, traj[idx]).items()})
    if cx.wants("attractor") and hasattr(prob, "probe"):
        out.update({"attractor." + k: v for k, v in
                    xmt.metric_attractor(prob, traj, cx.t0, cx.dt, cx.nsteps, cx.stride).items()})
    if ens and cx.wants("momentum") and hasattr(prob, "linear_momentum"):
        for kk, vals in xmt.metric_momentum(prob, traj, cx.dt, cx.method).items():
            out.update({"momentum.%s.%s" % (kk, k): v for k, v in vals.items() if not k.startswith("_")})
    if cx.wants("poincare") and prob.forcing_period:
        st = int(round(prob.forcing_period / cx.dt))
        Zs, _, _ = xmt.reference_states(prob, cx.case, cx.t0 + cx.dt * np.arange(0, cx.nsteps + 1, st))
        out.update({"poincare." + k: v for k, v in xmt.poincare_metrics(prob, traj, cx.dt, Zs).items()
                    if not (ens and k in ("sections", "transient_skipped"))})
    return out


def drift_metrics(cx: RunCtx) -> None:
    """d(t) of F (4.4) at the maxima of q (with the reference's d(t) from OUR reference)."""
    if not (cx.wants("dissipation-drift") and cx.prob.nq == 1):
        return
    traj, times = cx.traj, cx.t0 + cx.dt * np.arange(len(cx.traj))
    dd = xmt.dissipation_drift(cx.prob, traj, cx.t0, cx.dt)
    _put(cx, "dissipation-drift.", {k: v for k, v in dd.items() if k != "_d"})
    if not (cx.wants("error") or cx.wants("order")):
        return
    Zr, _, _ = xmt.reference_states(cx.prob, cx.case, times)
    rd = xmt.dissipation_drift(cx.prob, Zr, cx.t0, cx.dt)
    _put(cx, "dissipation-drift.reference.", {k: v for k, v in rd.items() if k != "_d"})
    k_ = min(len(dd["_d"]), len(rd["_d"]))
    cx.mm["dissipation-drift.max_abs_diff_reference"] = float(np.max(np.abs(dd["_d"][:k_] - rd["_d"][:k_]))) if k_ else 0.0
    cx.mm["dissipation-drift.maxima_count_diff"] = dd["maxima"] - rd["maxima"]
    if isinstance(dd.get("slope"), float) and isinstance(rd.get("slope"), float):
        cx.mm["dissipation-drift.slope_minus_reference"] = dd["slope"] - rd["slope"]


def energy_error(cx: RunCtx) -> None:
    """F Fig 4.3: H(reference) - H(method) on the output grid."""
    if not (cx.wants("energy") and (cx.wants("error") or cx.wants("order"))):
        return
    idx = cx.grid_idx()
    tt = cx.t0 + idx * cx.dt
    Zr, _, _ = xmt.reference_states(cx.prob, cx.case, tt)
    de = cx.prob.energy(Zr) - cx.prob.energy(cx.traj[idx])
    cx.mm["energy.max_abs_error"] = float(np.max(np.abs(de)))
    cx.mm["energy.final_abs_error"] = float(abs(de[-1]))
    cx.mm["energy.drift_slope"] = xmt.lsq_slope(tt, de)
    if cx.prob.energy_scale is not None:
        Sr = cx.prob.energy_scale(Zr)
        cx.mm["energy.error_res_slope"] = (xmt.lsq_slope(tt, de / Sr) if xmt.scale_ok(Sr).all()
                                           else Undef("energy scale of the reference not normal"))


def field_metrics(cx: RunCtx) -> None:
    """B (5.6) field drift and B Fig 5.4's error against the PDE's solution, on the output grid
    without t0."""
    prob, traj = cx.prob, cx.traj
    idx = cx.grid_idx()[1:]
    tt = cx.t0 + cx.dt * idx
    if cx.wants("field-drift") and hasattr(prob, "field_size"):
        mx = np.max(traj[idx, :prob.field_size()], axis=1)
        if len(idx) >= 2 and np.all(mx > 0):
            dd = np.log(mx) + np.array([xm.dGamma(prob, cx.t0, x - cx.t0) for x in tt])
            cx.mm.update({"field-drift.slope": xmt.lsq_slope(tt, dd), "field-drift.range": float(dd.max() - dd.min()),
                          "field-drift.first": [float(tt[0]), float(dd[0])],
                          "field-drift.last": [float(tt[-1]), float(dd[-1])], "field-drift.points": float(len(idx))})
    if cx.wants("pde-error") and hasattr(prob, "pde_solution"):
        errs: List[float] = []
        rels: List[float] = []
        for i in idx:
            u = prob.pde_solution(cx.t0, cx.t0 + cx.dt * i)
            if u is None:
                return
            e = float(np.max(np.abs(traj[i, :len(u)] - u)))
            errs.append(e)
            rels.append(e / float(np.max(np.abs(u))))
        if errs:
            cx.mm.update({"pde-error.max_abs": max(errs), "pde-error.final_abs": errs[-1],
                          "pde-error.max_rel": max(rels), "pde-error.points": float(len(errs))})


def precession(cx: RunCtx) -> None:
    """HLW Fig 2.1: the turn of the Runge-Lenz vector, every step, against OUR reference's; the
    largest turn between two output grid points."""
    if not (cx.wants("precession") and hasattr(cx.prob, "runge_lenz") and len(cx.traj) >= 2):
        return
    Zr, _, _ = xmt.reference_states(cx.prob, cx.case, cx.t0 + cx.dt * np.arange(len(cx.traj)))
    pm = xmt.metric_precession(cx.prob, cx.traj, Zr)
    pm["rate"] = pm["total"] / (cx.dt * (len(cx.traj) - 1))
    A = cx.prob.runge_lenz(cx.traj[cx.grid_idx()])
    dphi = np.diff(np.arctan2(A[:, 1], A[:, 0]))
    pm["max_grid_step"] = float(np.max(np.abs(np.remainder(dphi + math.pi, 2 * math.pi) - math.pi)))
    _put(cx, "precession.", pm)


def ensemble_band(cx: RunCtx) -> None:
    """Chaotic run: our two runs a round-off apart diverge; each trajectory metric gets the band
    16 |m - m'| (the C++ run is a third member); a batch-means standard error at least |m|."""
    if cx.chaotic is None or cx.chaotic.get("traj") is None:
        return
    for mem in cx.chaotic.get("members") or [cx.chaotic]:
        alt = grid_metrics(cx, mem["traj"], ens=True)
        if "poincare.set_hausdorff" in alt:
            cx.priv["poincare._alt_hausdorff"] = alt["poincare.set_hausdorff"]
        for k, v in alt.items():
            if isinstance(cx.mm.get(k), float) and isinstance(v, float):
                cx.band[k] = max(cx.band.get(k, 0.0), FLOOR_K * abs(cx.mm[k] - v))
                if k in ("attractor.mean_se", "attractor.mean_rse"):
                    # a standard error from 10 batch means varies by 1/sqrt(18) = 24 % between samples
                    cx.band[k] = max(cx.band[k], abs(cx.mm[k]))
    cx.notes.append("chaotic run (our ensemble spread D = %.3g): metric bands from it" % cx.D)


def all_metrics(cx: RunCtx) -> None:
    """Every metric of the case's diagnostics from our run (after the final state is judged)."""
    error_metrics(cx)
    local_error(cx)
    if cx.traj is not None:
        energy_balance(cx)
        _put(cx, "", grid_metrics(cx, cx.traj))
        law_metrics(cx)
        drift_metrics(cx)
        energy_error(cx)
        field_metrics(cx)
        precession(cx)
    cost_metrics(cx)
    ensemble_band(cx)
