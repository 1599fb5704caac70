"""Metrics of OUR trajectories for verify/crosscheck.py, each written from its definition in
docs/conventions.md and docs/case-keys.md (never from the C++ sources); moved here from
crosscheck.py unchanged.  A metric undefined by the docs' rule is an `Undef` with its reason."""
import math
import re
from typing import Any, Dict, List, Optional, Tuple

import numpy as np

from . import xcache
from . import xmethods as xm
from . import xproblems as xp
from . import xrun

EPS = float(np.finfo(float).eps)
TINY = 1e-300


class BadInput(Exception):
    """Bad input (exit 2), with a message naming the file and the key."""


def lsq_slope(t: Any, y: Any) -> float:
    t = np.asarray(t, float)
    y = np.asarray(y, float)
    if len(t) < 2:
        return 0.0
    tm = t - t.mean()
    return float(np.dot(tm, y - y.mean()) / np.dot(tm, tm))


class Undef:
    """A metric that is undefined by the docs' rule (docs/conventions.md, "Law residuals and
    their scales"); the report has null there and its reason under `undefined.<name>`."""

    def __init__(self, why: str) -> None:
        self.why = why

    def __repr__(self) -> str:
        return "undefined (%s)" % self.why


DBL_MIN = np.finfo(float).tiny


def scale_ok(S: Any) -> Any:
    """A scale is usable where it is a positive normal number (docs: "Law residuals")."""
    S = np.asarray(S, float)
    return np.isfinite(S) & (S >= DBL_MIN)


def metric_invariants(prob: Any, traj: Any, times: Any, h: Optional[float] = None) -> Dict[str, Any]:
    """Conformal laws of the invariants on their scales S(z) (docs/conventions.md, "Law
    residuals and their scales"): step and global residuals on S, the ratio deviation r_n where
    it is resolved, and the undefined points.  With constant gamma the step factor is
    e^{-2 gamma h} from the step size h itself: differencing Gamma(t_n) = gamma t_n loses
    eps gamma t_n (8e-15 relative at gamma t = 19, pde-kg-momentum), 10x the residual's round-off."""
    out: Dict[str, Any] = {}
    if not hasattr(prob, "invariants"):
        return out
    scales = prob.invariant_scales()
    if type(prob).Gamma is xp.Problem.Gamma:    # gamma t: the same products, elementwise
        G = prob.Gamma(np.asarray(times, float)) - prob.Gamma(times[0])
    else:
        G = np.array([prob.Gamma(t) for t in times]) - prob.Gamma(times[0])
    rates = getattr(prob, "invariant_rates", {})
    for name, fn in prob.invariants().items():
        # rate factor f: the law is e^{-2 f Gamma} (1 but for the Burgers Casimir, docs/pde.md)
        f = rates.get(name, 1.0)
        two_g = 2.0 * f * G
        I = fn(traj)
        S = scales[name](traj)
        okS = scale_ok(S)
        if h is not None and type(prob).Gamma is xp.Problem.Gamma:
            fac = math.exp(-2.0 * f * prob.g * h)
        else:
            fac = np.exp(-2.0 * f * np.diff(G))
        num_ = np.abs(I[1:] - fac * I[:-1])
        step = num_ / np.where(okS[:-1], S[:-1], 1.0)
        step_ok = okS[:-1] & np.isfinite(step)
        glob_ok = okS[1:] & np.isfinite(I[1:])
        undef = int(np.sum(~step_ok) + np.sum(~glob_ok) + (0 if okS[0] else 1))
        d: Dict[str, Any] = dict(scale_initial=float(S[0]), undefined_points=undef)
        if step_ok.any():
            k = int(np.argmax(np.where(step_ok, step, -1.0)))
            d.update(max_step_res=float(step[k]), max_step_abs=float(np.max(num_[step_ok])),
                     scale_at_max_step_res=float(S[k]), _step=np.where(step_ok, step, -1.0), _S=S[:-1],
                     last_step_res=float(step[np.nonzero(step_ok)[0][-1]]))
        I0 = float(I[0])
        Sg = np.where(glob_ok, S[1:], 1.0)
        if I0 != 0.0:    # e^{-2 Gamma} I_0 / S_n in logarithms (no underflow in long runs)
            law_on_S = math.copysign(1.0, I0) * np.exp(math.log(abs(I0)) - two_g[1:] - np.log(Sg))
        else:
            law_on_S = np.zeros_like(Sg)
        g = I[1:] / Sg - law_on_S
        if glob_ok.any():
            d["max_global_res"] = float(np.max(np.abs(g[glob_ok])))
            d["global_res_slope"] = lsq_slope(times[1:][glob_ok], g[glob_ok])
        if undef:
            why = "scale not a positive normal number at %d points" % undef
            # without a step whose residual is defined, no numerator or scale at its maximum
            for kk in ("max_step_res", "last_step_res", "max_global_res", "global_res_slope") + (
                    () if step_ok.any() else ("max_step_abs", "scale_at_max_step_res")):
                d[kk] = Undef(why)
        # r_n = e^{2 Gamma} I_n / I_0 - 1, resolved where u_n = eps S_n / |e^{-2 Gamma} I_0| is
        # <= 1e-8 or <= 1e-2 |r_n| (at n = 0 with r = 0)
        with np.errstate(divide="ignore", invalid="ignore"):
            r = np.zeros(len(I))
            nz = I != 0.0
            r[nz] = np.sign(I[nz]) * math.copysign(1.0, I0 if I0 else 1.0) * np.exp(
                np.log(np.abs(I[nz])) - (math.log(abs(I0)) if I0 else math.inf) + two_g[nz])
            r = r - 1.0
            r[0] = 0.0
            log_u = math.log(EPS) + np.log(S) - (math.log(abs(I0)) if I0 else math.inf) + two_g
            resolved = okS & np.isfinite(r) & ((log_u <= math.log(1e-8)) | (log_u <= np.log(1e-2 * np.abs(r))))
        d["_log_u"] = log_u
        if I0 != 0.0 and resolved.all():
            d["max_global_ratio_dev"] = float(np.max(np.abs(r[1:])))
            d["ratio_dev_slope"] = lsq_slope(times[1:], r[1:])
            # our round-off band of r: n steps of u_n each, u_n as large as it is where r_n was
            # resolved by its second test (u_n <= 1e-2 |r_n|: then r is known to a per cent,
            # and the band says so rather than 1e-8)
            d["_ratio_u"] = float(np.max(np.exp(log_u)))
        else:
            k = int(np.argmin(resolved)) if I0 != 0.0 else 0
            why = "r_n unresolved at step %d" % k
            d["max_global_ratio_dev"] = d["ratio_dev_slope"] = Undef(why)
        out[name] = d
    return out


def metric_energy(prob: Any, traj: Any, times: Any, ref: Any = None) -> Dict[str, Any]:
    H = prob.energy(traj)
    dH = H - H[0]
    n = len(H)
    half = n // 2  # the first half: points 0..half; the second: the rest (docs/conventions.md)
    a1 = np.max(np.abs(dH[:half + 1]))
    a2 = np.max(np.abs(dH[half + 1:])) if n > half + 1 else 0.0
    out: Dict[str, Any] = dict(max_abs_change=float(np.max(np.abs(dH))), change_slope=lsq_slope(times, dH),
               growth_ratio=float(a2 / a1) if a1 > 0 else Undef("|H_n - H_0| = 0 on the first half"))
    if prob.energy_scale is not None:
        S0 = float(prob.energy_scale(traj[0]))
        out["scale_initial"] = S0
        if scale_ok(S0):
            out["max_change_res"] = float(np.max(np.abs(dH)) / S0)
            out["change_res_slope"] = lsq_slope(times, dH / S0)
        else:
            out["max_change_res"] = out["change_res_slope"] = Undef("energy scale at t0 is %r" % S0)
    return out


_HB = np.array([[1, 0, 0, -10, 15, -6], [0, 1, 0, -6, 8, -3], [0, 0, .5, -1.5, 1.5, -.5],
                [0, 0, 0, .5, -1, .5], [0, 0, 0, -4, 7, -3], [0, 0, 0, 10, -15, 6]], float)


def _horner(c: Any, x: Any) -> Any:
    """sum_j c[..., j] x^j row by row (c: rows x coefficients, low to high; x: rows, or rows x
    points when c has a point axis inserted)."""
    acc = c[..., -1]
    for j in range(c.shape[-1] - 2, -1, -1):
        acc = acc * x + c[..., j]
    return acc


def _largest_maxima(coef: Any, dcoef: Any, ddcoef: Any, s: Any) -> None:
    """Steps where the quintic interpolant has several local maxima (coarse steps): s[r] set to
    the largest one's position (see dissipation_drift)."""
    # several local maxima of the interpolant in one step (coarse steps): the largest. The
    # critical points are the real roots of the quartic H' in (0, 1) (numpy's companion-matrix
    # eigenvalues), each a local maximum where H'' < 0, polished by bisection on H'.
    # Only a step where H'' changes sign twice between the roots of H''' (a quadratic) can hold
    # more than one root of H' (an odd number of them, as H'(0) > 0 >= H'(1)): those few rows go
    # to np.roots.
    qa, qb, qc = 60.0 * coef[:, 5], 24.0 * coef[:, 4], 6.0 * coef[:, 3]
    with np.errstate(divide="ignore", invalid="ignore"):
        disc = qb * qb - 4.0 * qa * qc
        sq = np.sqrt(np.where(disc > 0, disc, 0.0))
        den = 2.0 * np.where(qa != 0, qa, 1.0)
        r1 = np.where((qa != 0) & (disc > 0), (-qb - sq) / den, 0.0)
        r2 = np.where((qa != 0) & (disc > 0), (-qb + sq) / den, 0.0)
        r1 = np.where((qa == 0) & (qb != 0), -qc / np.where(qb != 0, qb, 1.0), r1)
    cuts = np.stack([np.zeros_like(r1), np.where((r1 > 0) & (r1 < 1), r1, 0.0),
                     np.where((r2 > 0) & (r2 < 1), r2, 0.0), np.ones_like(r1)], axis=-1)
    cuts.sort(axis=-1)
    dd_pos = _horner(ddcoef[:, None, :], cuts) > 0
    candidates = np.nonzero((dd_pos[:, 1:] != dd_pos[:, :-1]).sum(1) >= 2)[0]
    for r in candidates:
        roots = np.roots(dcoef[r][::-1])
        cand = sorted(x.real for x in roots if abs(x.imag) <= 1e-9 and 0.0 < x.real < 1.0
                      and (ddcoef[r] * x.real ** np.arange(4)).sum() < 0)
        if len(cand) < 2:
            continue
        best: Any = None
        for x in cand:
            lo, hi = max(0.0, x - 1e-6), min(1.0, x + 1e-6)
            dh = lambda y: (dcoef[r] * y ** np.arange(5)).sum()
            if not (dh(lo) > 0 >= dh(hi)):
                lo, hi = x, x
            for _ in range(100):
                mid = 0.5 * (lo + hi)
                if mid in (lo, hi):
                    break
                lo, hi = (mid, hi) if dh(mid) > 0 else (lo, mid)
            val = (coef[r] * lo ** np.arange(6)).sum()
            if best is None or val > best[0]:
                best = (val, lo)
        s[r] = best[1]


def dissipation_drift(prob: Any, traj: Any, t0: float, h: float) -> Dict[str, Any]:
    """F (4.4): d = ln(max q) + Gamma(t) at the maxima of q, each located by the quintic Hermite
    interpolant through (q, q', q'') at both ends of the step where q' changes sign from + to -
    (docs/conventions.md §5; the largest of its local maxima when it has several in the step);
    its least-squares slope, range, first and last (t, d)."""
    q = traj[:, 0]
    p = traj[:, prob.nq:prob.nq + 1]
    n = np.arange(len(q))
    t = t0 + n * h
    qd = prob.dT(p)[:, 0]
    qdd = (prob.force(t[:, None], traj[:, :prob.nq]) - 2 * prob.gamma(t)[..., None] * p
           if np.ndim(prob.gamma(t)) else prob.force(t[:, None], traj[:, :prob.nq]) - 2 * prob.gamma(t) * p)
    qdd = np.asarray(qdd)[:, 0] / prob.m if np.ndim(prob.m) == 0 else np.asarray(qdd)[:, 0] / prob.m[0]
    k = np.nonzero((qd[:-1] > 0) & (qd[1:] <= 0))[0]
    coef = np.stack([q[k], h * qd[k], h * h * qdd[k], h * h * qdd[k + 1], h * qd[k + 1], q[k + 1]], axis=-1) @ _HB
    dcoef = coef[:, 1:] * np.arange(1, 6)
    ddcoef = dcoef[:, 1:] * np.arange(1, 5)
    # dH(0) > 0 >= dH(1): Newton kept inside the bracket [lo, hi] of the root, bisection where a
    # Newton step would leave it or dH is not concave (an unguarded Newton step can run to the
    # far end of the step when the interpolant is not concave there)
    s = qd[k] / (qd[k] - qd[k + 1])
    idx, S = np.arange(len(s)), s.copy()  # the rows still iterating and their iterates
    L, U, D1, D2 = np.zeros_like(s), np.ones_like(s), dcoef, ddcoef
    for _ in range(100):
        if len(idx) == 0:
            break
        g, dd = _horner(D1, S), _horner(D2, S)
        L, U = np.where(g > 0, S, L), np.where(g > 0, U, S)
        with np.errstate(divide="ignore", invalid="ignore"):
            nxt = np.where(dd < 0, S - g / np.where(dd < 0, dd, 1.0), 0.5 * (L + U))
        nxt = np.where((nxt > L) & (nxt < U), nxt, 0.5 * (L + U))
        conv = (np.abs(nxt - S) <= 4 * EPS) | (U - L <= 4 * EPS)
        s[idx] = nxt
        keep = ~conv
        idx, S, L, U, D1, D2 = idx[keep], nxt[keep], L[keep], U[keep], D1[keep], D2[keep]
    _largest_maxima(coef, dcoef, ddcoef, s)
    qm = (coef * s[:, None] ** np.arange(6)).sum(-1)
    tm = t[k] + s * h
    ok = qm > 0
    nonpos = int(np.sum(~ok))
    tm, qm = tm[ok], qm[ok]
    if len(tm) == 0:
        return dict(maxima=0, maxima_nonpositive=nonpos, _d=np.zeros(0))
    G = np.array([prob.Gamma(x) for x in tm]) - prob.Gamma(t0) if prob.t_dependent_gamma else prob.g * (tm - t0)
    d = np.log(qm) + G
    if nonpos:    # ln(max q) undefined at a maximum <= 0: slope and range undefined (docs)
        why = "%d maxima of q are <= 0" % nonpos
        return dict(maxima=len(d), maxima_nonpositive=nonpos, slope=Undef(why), range=Undef(why), _d=d)
    if len(d) < 3:
        return dict(maxima=len(d), maxima_nonpositive=0, _d=d)
    return dict(maxima=len(d), maxima_nonpositive=0, slope=lsq_slope(tm, d), range=float(d.max() - d.min()),
                first=[float(tm[0]), float(d[0])], last=[float(tm[-1]), float(d[-1])], _d=d)


def poincare_metrics(prob: Any, traj: Any, dt: float, Zref: Any) -> Dict[str, Any]:
    """Sections at t = t0 + k T (T the forcing period) after a 10 % transient, q wrapped to
    [-pi, pi): pointwise distances to OUR reference's sections and set distances (mean nearest
    distance, Hausdorff) (docs/conventions.md §5)."""
    stride = int(round(prob.forcing_period / dt))
    S = traj[::stride]
    R = Zref
    n = min(len(S), len(R))
    S, R = S[:n], R[:n]
    skip = int(0.1 * (n - 1))
    S2, R2 = S[skip:], R[skip:]

    def dist(A: Any, B: Any) -> Any:          # q is an angle: periodic difference in [-pi, pi)
        dq = np.mod(A[..., 0] - B[..., 0] + math.pi, 2 * math.pi) - math.pi
        return np.hypot(dq, A[..., 1] - B[..., 1])
    pw = dist(S2, R2)
    D = dist(S2[:, None, :], R2[None, :, :])
    return dict(_pairs=D, sections=n, transient_skipped=skip, pointwise_final=float(pw[-1]),
                pointwise_max=float(pw.max()), set_mean=float(D.min(axis=1).mean()),
                set_hausdorff=float(max(D.min(axis=1).max(), D.min(axis=0).max())))


def metric_attractor(prob: Any, traj: Any, t0: float, dt: float, nsteps: int, stride: int) -> Dict[str, Any]:
    """docs/conventions.md section 5 'attractor': statistics of the probe over the output grid
    points with t >= t0 + (t_end - t0)/2 (t0 itself never), written from that definition."""
    t_end = t0 + nsteps * dt
    frm = t0 + 0.5 * (t_end - t0)
    idx = np.arange(stride, len(traj), stride)
    tt = t0 + dt * idx
    keep = tt >= frm
    tt, s = tt[keep], np.array([prob.probe(traj[i]) for i in idx[keep]])
    out: Dict[str, Any] = {"from": frm, "points": float(len(s))}
    names = ("mean", "std", "min", "max", "q10", "q50", "q90", "mean_se", "mean_rse", "crossings",
             "period", "period_spread")
    if len(s) < 20:
        for k in names:
            out[k] = Undef("fewer than 20 output points in the second half")
        return out
    m = float(np.mean(s))
    out.update(mean=m, std=float(np.std(s)), min=float(np.min(s)), max=float(np.max(s)),
               q10=float(np.quantile(s, 0.1)), q50=float(np.quantile(s, 0.5)),
               q90=float(np.quantile(s, 0.9)))
    bm = np.array([b.mean() for b in np.array_split(s, 10)])
    se = float(np.std(bm, ddof=1) / math.sqrt(10))
    out["mean_se"] = se
    out["mean_rse"] = se / abs(m) if m != 0 else Undef("mean 0")
    if not (out["std"] > 1e-12 * max(abs(m), 1e-300)):
        out["crossings"] = 0.0
        out["period"] = out["period_spread"] = Undef("constant probe")
        return out
    up = np.nonzero((s[:-1] < m) & (s[1:] >= m))[0]
    tc = tt[up] + (m - s[up]) / (s[up + 1] - s[up]) * (tt[up + 1] - tt[up])
    out["crossings"] = float(len(tc))
    if len(tc) < 3:
        out["period"] = out["period_spread"] = Undef("fewer than three crossings")
        return out
    iv = np.diff(tc)
    per = (tc[-1] - tc[0]) / (len(tc) - 1)
    out["period"] = float(per)
    out["period_spread"] = float((iv.max() - iv.min()) / per)
    return out


def metric_temperature(prob: Any, traj: Any) -> Dict[str, Any]:
    T = prob.temperature(traj)
    return dict(initial=float(T[0]), max=float(T.max()), min=float(T.min()), mean=float(T.mean()),
                max_abs_dev_initial=float(np.max(np.abs(T - T[0]))))


def metric_precession(prob: Any, traj: Any, ref: Any = None) -> Dict[str, Any]:
    """HLW Fig 2.1: the unwrapped turn of the perihelion direction atan2(A2, A1) of the
    Laplace-Runge-Lenz vector (every step here; the C++ side samples the output grid: the same
    total while no grid step turns it by pi)."""
    def total(z: Any) -> Tuple[float, Any]:
        A = prob.runge_lenz(z)
        phi = np.arctan2(A[:, 1], A[:, 0])
        return float(np.sum(np.remainder(np.diff(phi) + math.pi, 2 * math.pi) - math.pi)), A
    tot, A = total(traj)
    ecc = np.hypot(A[:, 0], A[:, 1])
    out: Dict[str, Any] = dict(initial_angle=float(math.atan2(A[0, 1], A[0, 0])), min_eccentricity=float(ecc.min()),
               total=tot)
    if ref is not None:
        out["reference_total"], _ = total(ref)
        out["total_minus_reference"] = tot - out["reference_total"]
    return out


def table_factor(method: str, g: float, h: float) -> Optional[float]:
    """B Table 3.1: per-step linear-momentum factor each conformal method achieves (cse-if and
    cse-etd, B (2.18), (2.19): p1 = e^{-2 g h} p + h c F(q) with sum F = 0, the law itself); a
    method file's factor is the one its claims declare (docs/method-files.md)."""
    claims = xm.FILE_CLAIMS.get(method)
    if claims is not None:
        cayley, exact = "linear-momentum-cayley" in claims, "linear-momentum" in claims
    else:
        exact = method in ("csv1", "csv1-perk", "cse-if", "cse-etd")
        cayley = method in ("csv2", "csv2-perk", "cimp")   # csv2-perk is csv2 as a PERK pair (B (2.21))
    if cayley:
        return math.exp(-g * h) * (2 - g * h) / (2 + g * h)
    if exact:
        return math.exp(-2 * g * h)
    return None


def metric_momentum(prob: Any, traj: Any, h: float, method: str) -> Dict[str, Any]:
    """Sum p and sum q x p per step (B Ex. 1.3): law residual |X_{n+1} - e^{-2 gamma h} X_n|_2 on
    the scales S_p = sum |p_i|, S_L = sum |q_i||p_i| of z_n, and for the linear momentum the
    factor B Table 3.1 gives the method; the measured factor X_{n+1}.X_n/|X_n|^2 only where
    |X_n| >= 1e-8 S(z_n) (docs/conventions.md, "Law residuals and their scales")."""
    out: Dict[str, Any] = {}
    law = math.exp(-2.0 * prob.g * h)
    for kind, fn, sfn in (("linear", prob.linear_momentum, prob.linear_momentum_scale),
                          ("angular", prob.angular_momentum, prob.angular_momentum_scale)):
        if kind == "linear" and not getattr(prob, "linear_momentum_law", True):
            out[kind] = {"reason": "no linear momentum law"}     # Kepler: a fixed centre
            continue
        P = fn(traj)
        S = sfn(traj)[:-1]
        okS = scale_ok(S)
        Sd = np.where(okS, S, 1.0)
        nrm = np.linalg.norm(P, axis=-1)
        num_ = np.linalg.norm(P[1:] - law * P[:-1], axis=-1)
        step = num_ / Sd
        tf = table_factor(method, prob.g, h) if kind == "linear" else None
        d: Dict[str, Any] = dict(initial_norm=float(nrm[0]), scale_initial=float(S[0]),
                 undefined_points=int(np.sum(~okS)), _scale_max=float(np.max(S)))
        if okS.any():
            k = int(np.argmax(np.where(okS, step, -1.0)))
            d.update(max_law_res=float(step[k]), last_law_res=float(step[np.nonzero(okS)[0][-1]]),
                     max_law_abs=float(np.max(num_[okS])), scale_at_max_law_res=float(S[k]),
                     _step=np.where(okS, step, -1.0), _S=S)
            if tf is not None:
                d["max_table_res"] = float(np.max((np.linalg.norm(P[1:] - tf * P[:-1], axis=-1) / Sd)[okS]))
        if not okS.all():
            for kk in ("max_law_res", "last_law_res", "max_table_res"):
                if kk in d or (kk == "max_table_res" and tf is not None):
                    d[kk] = Undef("scale not a positive normal number")
        fok = okS & (nrm[:-1] >= 1e-8 * S)
        d["factor_undefined_points"] = int(np.sum(~fok))
        exp_f = tf if tf is not None else law
        fac = np.sum(P[1:] * P[:-1], axis=-1) / np.where(fok, nrm[:-1] ** 2, 1.0)
        if fok.all():
            d["max_factor_dev"] = float(np.max(np.abs(fac - exp_f)) / abs(exp_f))
            # round-off of a measured factor: eps S_n / |X_n|
            d["_factor_u"] = float(np.max(EPS * S / nrm[:-1]))
        else:
            d["max_factor_dev"] = Undef("|X_n| < 1e-8 S(z_n) at %d steps" % int(np.sum(~fok)))
        d["first_factor"] = float(fac[0]) if fok[0] else Undef("|X_0| < 1e-8 S(z_0)")
        if kind == "linear":
            d["law_factor"] = law
            if tf is not None:
                d["table_factor"] = tf
        out[kind] = d
    return out


@xcache.memo
def metric_conformal_symplectic(method: str, prob: Any, h: float, t0: float, traj: Any) -> Dict[str, Any]:
    """E_n: Psi^T J^-1 Psi against e^{-2 dGamma} J^-1 (canonical), or Psi D Psi^T against
    e^{-2 dGamma} D for a problem with a Poisson structure matrix D (B's Burgers (5.9))."""
    d = prob.d
    n = d // 2
    D = prob.structure() if hasattr(prob, "structure") else None
    Jinv = np.block([[np.zeros((n, n)), np.eye(n)], [-np.eye(n), np.zeros((n, n))]])
    E: List[Tuple[Any, float]] = []
    for k in range(len(traj) - 1):
        t = t0 + k * h
        Psi = xrun.step_jacobian(method, prob, h, t, traj[k])
        fac = math.exp(-2.0 * xm.dGamma(prob, t, h))
        if D is None:
            E.append((np.linalg.norm(Psi.T @ Jinv @ Psi - fac * Jinv), fac))
        else:
            E.append((np.linalg.norm(Psi @ D @ Psi.T - fac * D), fac))
    Ea = np.array([e for e, _ in E])
    scale = math.sqrt(d) if D is None else float(np.linalg.norm(D))
    Er = np.array([e / (f * scale) for e, f in E])
    return dict(max_abs=float(Ea.max()), max_rel=float(Er.max()), last_abs=float(Ea[-1]),
                last_rel=float(Er[-1]), steps_measured=len(E), max_rel_step=int(np.argmax(Er)) + 1,
                _Er=Er)


def metric_stability(method: str, prob: Any, h: float) -> Dict[str, Any]:
    M = xrun.step_jacobian(method, prob, h, 0.0, np.zeros(2))
    ev = np.linalg.eigvals(M)
    g = prob.g
    ht = 0.5 * np.trace(M)
    w = prob.w
    det, dexp = float(np.linalg.det(M)), math.exp(-2 * g * h)
    b2 = (w - g) * (w + g)
    # exact flow: half trace of e^{hA} = e^{-gh} cos(beta h) (cosh for beta^2 < 0)
    hx = math.exp(-g * h) * (math.cos(math.sqrt(b2) * h) if b2 >= 0 else math.cosh(math.sqrt(-b2) * h))
    out: Dict[str, Any] = dict(det=det, det_expected=dexp, det_abs_err=abs(det - dexp),
               det_rel_err=abs(det - dexp) / dexp if dexp >= DBL_MIN
               else Undef("e^{-2 gamma h} underflows"), half_trace=float(ht),
               half_trace_exact=hx, half_trace_exact_err=abs(ht - hx),
               spectral_radius=float(np.abs(ev).max()), matrix=M.tolist(),
               # power-bounded: rho < 1, or rho = 1 within 8 eps with distinct (non-defective)
               # eigenvalues on the unit circle (symplectic methods at gamma = 0)
               power_bounded=int(float(np.abs(ev).max()) < 1.0 - 8 * EPS or (
                   float(np.abs(ev).max()) <= 1.0 + 8 * EPS and abs(ev[0] - ev[-1]) > 1e-7)),
               F_condition=int(abs(ht) < math.exp(-g * h)))
    # F's closed forms (3.10), (3.15), (3.20) (docs/conventions.md §5)
    e = math.exp(-g * h)
    F = {"cimp": e * (1 - h * h * b2 / 4) / (1 + h * h * b2 / 4),
         "csv1": e * (1 - h * h * w * w / 2) * math.cosh(g * h),
         "csv2": e * ((4 + g * g * h * h) - 2 * h * h * w * w * math.cosh(g * h / 2)) / (4 - g * g * h * h)
         if g * h != 2 else math.nan}.get(method)
    if F is not None:
        # relative form undefined where |f| <= 1e-8 e^{-gamma h} (docs/conventions.md, "Other
        # relative metrics"): the half trace passes through 0 near a threshold
        out.update(half_trace_formula=F, half_trace_formula_abs_err=abs(ht - F),
                   half_trace_formula_rel_err=abs(ht - F) / abs(F) if abs(F) > 1e-8 * e
                   else Undef("|f| <= 1e-8 e^{-gamma h}"))
    return out


def _component(prob: Any, spec: Any, Z: Any) -> Any:
    """The components a measure reads (docs/case-keys.md): state, q, p, q[i], p[i], z[i]."""
    spec = spec or "state"
    if spec == "state":
        return Z
    if spec == "q":
        return Z[..., :prob.nq]
    if spec == "p":
        return Z[..., prob.nq:]
    m = re.fullmatch(r"([qpz])\[(\d+)\]", spec)
    if not m:
        raise BadInput("measure component '%s' not understood" % spec)
    i = int(m.group(2)) + (prob.nq if m.group(1) == "p" else 0)
    return Z[..., i:i + 1]


def _grad_norm(fn: Any, Z: Any) -> float:
    """max_n |grad fn(z_n)|_2 by central differences (step 1e-6 |z|; only sizes a floor)."""
    g2 = np.zeros(len(Z))
    for i in range(Z.shape[-1]):
        dz = 1e-6 * np.maximum(1.0, np.abs(Z[:, i]))
        Zp, Zm = Z.copy(), Z.copy()
        Zp[:, i] += dz
        Zm[:, i] -= dz
        g2 += ((fn(Zp) - fn(Zm)) / (2 * dz)) ** 2
    return float(np.sqrt(g2.max()))


def measures(prob: Any, case: Dict[str, Any], Z: Any, Zr: Any, times: Any, dz: float) -> Dict[str, Any]:
    """measure.<name> of docs/case-keys.md: the pointwise error U_n - u(t_n) of a component
    (Euclidean norm; `rel` divides pointwise by the reference component's norm), or the energy
    error H(U_n) - H(u(t_n)) (`rel`: by |H(u(t_n))|), reduced over the output grid t_1..t_end
    (final, max, mean, rms), or `growth`: least-squares slope of log(running maximum from t_1)
    against log(t - t0) over the grid points t >= from (default t0 + (t_end - t0)/10).
    Returns {name: (value, floor)}: floor = the value's uncertainty from the state bound dz
    (propagated pointwise) and the reference estimate, for the comparison and the verdicts."""
    t0 = float(case.get("t0", 0.0))
    t_end = float(case.get("t_end", times[-1]))
    out: Dict[str, Any] = {}
    for name, spec in sorted(case["measures"].items()):
        qty = spec.get("quantity", "error")
        rel = spec.get("norm", "abs") == "rel"
        if qty == "energy-error":
            Hm, Hr = prob.energy(Z), prob.energy(Zr)
            e = np.abs(Hm - Hr)
            fl = dz * max(_grad_norm(prob.energy, Zr), _grad_norm(prob.energy, Z)) \
                + 8 * EPS * float(np.max(np.abs(Hr)) + np.max(np.abs(Hm)))
            if rel:
                den = np.abs(Hr)
        else:
            C, Cr = _component(prob, spec.get("component"), Z), _component(prob, spec.get("component"), Zr)
            e = np.linalg.norm(C - Cr, axis=-1)
            fl = dz
            if rel:
                den = np.linalg.norm(Cr, axis=-1)
        flp = np.full(len(e), fl)
        if rel:
            ok = den >= DBL_MIN
            e = np.where(ok, e / np.where(ok, den, 1.0), np.nan)
            flp = np.where(ok, fl / np.where(ok, den, 1.0), np.inf)
        i1 = slice(1, None) if len(e) > 1 else slice(0, None)
        over = spec.get("over")
        ev, fv = e[i1], flp[i1]
        if over == "final":
            val, f = float(e[-1]), float(flp[-1])
        elif over == "max":
            val, f = float(np.max(ev)), float(np.max(fv))
        elif over == "mean":
            val, f = float(np.mean(ev)), float(np.mean(fv))
        elif over == "rms":
            val, f = float(np.sqrt(np.mean(ev ** 2))), float(np.max(fv))
        elif over == "growth":
            frm = float(spec.get("from", t0 + (t_end - t0) / 10.0))
            tt = times[i1] - t0
            run = np.maximum.accumulate(ev)
            w = times[i1] >= frm * (1 - 1e-12) - 1e-300
            x, y = np.log(tt[w]), np.log(run[w])
            val = lsq_slope(x, y)
            # log of the running max moves by at most floor/value: slope by twice that over the
            # log-time span (the fit's leverage)
            f = 2.0 * float(np.max(fv[w] / run[w])) / max(float(x[-1] - x[0]), TINY)
        else:
            raise BadInput("measure '%s': over '%s' not understood" % (name, over))
        if not math.isfinite(val):
            out[name] = (Undef("reference norm 0 on the grid"), 0.0)
        else:
            out[name] = (val, f)
    return out


def make_problem(case: Dict[str, Any]) -> Tuple[Any, Optional[str]]:
    try:
        pid = case["problem"]["id"]
        params = dict(case["problem"].get("params", {}))
    except (KeyError, TypeError) as exc:
        raise BadInput("case %s: malformed problem (%s)" % (case.get("id"), exc))
    if pid not in xp.PROBLEMS:
        return None, "unknown problem '%s'" % pid
    try:
        return xp.make_problem(pid, params), None
    except TypeError as exc:
        return None, "problem '%s' parameters not modelled (%s)" % (pid, exc)


def reference_states(prob: Any, case: Dict[str, Any], times: Any) -> Tuple[Any, float, str]:
    """(states at times, error estimate, note)."""
    t0 = float(case.get("t0", 0.0))
    if prob.exact_available and hasattr(prob, "exact"):
        Z = prob.exact(t0, times)
        return Z, getattr(prob, "exact_estimate", 0.0), "exact"
    Z, est = prob.reference_grid(t0, times)
    return Z, est, "DOP853 rtol 2.3e-14 atol 1e-16, certified against rtol 1e-13"


def get_path(d: Any, path: str) -> Any:
    for k in path.split("."):
        if not isinstance(d, dict) or k not in d:
            return None
        d = d[k]
    return d


def flatten(prefix: str, d: Dict[str, Any], out: Dict[str, Any]) -> Dict[str, Any]:
    for k, v in d.items():
        key = prefix + "." + k if prefix else k
        if isinstance(v, dict):
            flatten(key, v, out)
        else:
            out[key] = v
    return out
