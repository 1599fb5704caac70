#!/usr/bin/python3
"""Independent Python cross-check of a dampsym report.

    /usr/bin/python3 verify/crosscheck.py REPORT.json [--out DIR] [--jobs N] [--strict]

--strict (the ctests' setting): exit 1 also when a run, order fit or check is "not reproduced",
so a case added to a suite without its independent counterpart here fails the cross-check.

The report is read ONLY to learn what to recompute (problem, parameters, method, dt, steps,
t0, t_end, grid size, the checks' metric/op/expected) and which C++ numbers to compare
against.  Every "ours" value is computed from scratch by verify/xproblems.py,
verify/xmethods.py and verify/xrun.py (written from the papers and docs/, never from the C++
sources or coefficient tables).  Runs and metrics are found by name; a metric we do not
recompute is reported as "not reproduced", never a crash.

Tolerances (each justified in one line):
  final_time      rel 1e-12: t0 + n h in double, both sides.
  final_state     rel 1e-12 explicit / 1e-10 implicit (Newton stops at round-off, so both
                  sides' stages differ only by round-off amplified by the Newton contraction),
                  or, when larger, the ROUND-OFF FLOOR 16 D: D = |z_n' - z_n|/|z_n| between our
                  run and our run from z0 (1 + 4 eps) measures how far two computations that
                  differ at round-off drift apart (rounding noise plus its amplification, huge
                  for chaotic runs: argon, the driven pendulum); 16 is the safety factor.
  error.*         rel 1e-6 when the error is >= 1000x both reference estimates (then it is a
                  property of the method, not of the reference); otherwise |diff| <= the
                  state-difference bound plus both reference estimates.
  klein-gordon    exact reference: the semi-discrete solution mode by mode (xproblems.KleinGordon),
                  estimate 8 eps [(log2 M + 4)|z| + amplitude-weighted |beta| t |z|]: two FFTs of
                  log2 M roundings each plus each mode's phase error eps |beta t| (measured against
                  a 40-digit matrix exponential: 20-100x below this bound).
  schrodinger     exact reference: the semi-discrete solution mode by mode (xproblems.Schrodinger),
                  estimate 8 eps (log2 M + 4 + max|lambda - kd^2| t) |z|: two FFTs plus each mode's
                  phase error.  burgers, nls: the DOP853 reference (certified as for every problem).
  nls-if/-etd/-imp B's schemes (4.15), (5.27), (5.28) as verify/xmethods.nls_b_step writes them
                  (fixed point, FFT), compiled with our own radix-2 FFT (verify/xjit.py) for M a
                  power of two: final states as implicit methods; attractor statistics as other
                  metrics (chaotic runs: the ensemble band).
  residuals       (invariant laws *_step_res, E_n, momentum *_law_res/*_table_res, all on the
                  scales of docs/conventions.md "Law residuals and their scales", recomputed here
                  from the docs' definitions): factor 2, or both below 1e-13 (100 eps over a few
                  operations: the round-off floor of a residual on its scale).
  max_global_res  factor 2 or both <= 8 n eps: one rounding eps S(z_k) per step, decaying with
                  the law, stays ~n eps on S(z_n).
  ratio dev       max_global_ratio_dev factor 2 or both <= 8 n u (u = eps S(z_n)/|e^{-2 Gamma}
                  I_0| <= 1e-8 where r_n is resolved); slopes rel 1e-6 + that floor / run time.
  *_abs numerators the residual floor 1e-13 times the largest scale in the run.
  measured factor max_factor_dev factor 2 or both <= 8 max eps S(z_n)/|X_n| (its round-off);
                  first_factor rel 1e-6 + the same.
  initial_norm    rel 1e-6 + 4 N eps S(z_0): |sum of N vectors| summed in another order.
  local-error     rel 1e-6 + 8 eps |z(t0 + h)| (+ our exact solution's estimate): one step and
                  the exact value are each rounded to a few eps |z|.
  scale_initial   rel 64 eps: a function of z0 alone, a few sums of products.
  precession      total, rate: rel 1e-6 or |diff| <= 8 pi n eps (/ span for the rate): a sum of n
                  angle increments each rounded a few times (the reference's turn is round-off).
  scale_at_max_*  compared only when the maximum residual is > 1e-10 (else the argmax of
                  round-off), against S(z_k) at every step k whose residual is within rel 1e-6
                  of our maximum (near-ties between steps), rel 1e-6.
  energy *_res    on S_H: rel 1e-6 + 8 sqrt(n) eps S_H(z0) / S_H(z0) (random-walk round-off of
                  H = T + V, which is eps (T + |V|), not eps |H|); slopes that over the run time.
  chaotic runs    residuals: factor 2 or both below the floor + 16 |m - m'| over our own 4-eps
                  ensemble (the C++ run is a third member); other metrics rel 1e-6 + that band;
                  attractor.mean_se/mean_rse at least |ours| too (a batch-means standard error
                  from 10 batches varies by 24 % between samples).
  undefined       a null metric (reason under `undefined.<name>`) must be undefined here by
                  the docs' rule, and a defined one defined; a check on an undefined metric
                  must have failed.
  other metrics   rel 1e-6 plus the propagated state-difference bound (they are smooth
                  functions of the trajectory).
  order.slope     abs 0.01 plus (floor-limited fits): the slope of two independent error sets
                  that agree to 1e-6 agrees to 1e-5; 0.01 leaves room for window choice.
  stability       det, half_trace rel 1e-12 (a few roundings of a 2x2 product); entries 1e-12
                  max|M|; spectral radius rel 1e-7 (eigenvalues of a near-defective M move like
                  sqrt(eps)).
  stability *_abs_err  |det M - e^{-2 gamma h}|, |1/2 tr M - f|: factor 2 or both <= 8 eps
                  max(1, |f|) (two O(1) numbers each rounded a few times).
  measure.*       rel 1e-6 plus the floor propagated pointwise from the state bound and the
                  reference estimates (energy errors: times max |grad H| on the grid, + 8 eps |H|;
                  growth slopes: twice the largest floor/value over the log-time span).
  Newton counts   cost.* and run.{newton_iters,rhs_evals,jac_evals} of implicit methods: inside the
                  range of a stated family of correct solvers (full to simplified Newton, tests
                  from 1e-8 ~ sqrt(eps) down to our round-off test; verify/xnewton.py), because a
                  count depends on the solver variant and on round-off in the last update.
  stability sweep counts within the number of round-off tie points (|1/2 tr M| within 16 eps of
                  e^{-gamma h}, rho within 16 eps of 1); first-failure steps within the range the
                  ties allow; F's formula boundary exactly; max_half_trace_err rel 1e-9 + 1e-13.
  trace-taylor    h4_coeff and its errors within the truncation of a step-size-h estimate plus
                  round-off (our value is extrapolated to ~1e-6; verify/xsweep.py); expected rel 1e-12.
  chaotic Poincare pointwise_final/pointwise_max/set_hausdorff: statistical (the trajectories
                  decorrelate): inside the range the attractor's pair-distance distribution gives
                  one draw / the maximum of n draws; Hausdorff within a factor 2 of our ensemble.
  check verdicts  recomputed from OUR value with the check's op/expected; must equal `passed`.
Exit 0 all agree, 1 any disagreement (or, with --strict, anything not reproduced), 2 bad input.
"""
import argparse
import json
import math
import os
import re
import sys
import time
from multiprocessing import Pool

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import xmethods as xm  # noqa: E402
import xproblems as xp  # noqa: E402
import xrun  # noqa: E402
import xjit  # noqa: E402
import xnewton  # noqa: E402
import xsweep  # noqa: E402
from refmath import fit_order  # noqa: E402  (our own asymptotic-window fit)

EPS = np.finfo(float).eps
TOL_STATE = {"explicit": 1e-12, "implicit": 1e-10}
TOL_TIME = 1e-12
TOL_ERR = 1e-6
TOL_RESID_FACTOR, TOL_RESID_FLOOR = 2.0, 1e-13
TOL_METRIC = 1e-6
TOL_ORDER = 0.01
TOL_STAB, TOL_RHO = 1e-12, 1e-7
FLOOR_K = 16.0
TINY = 1e-300


class BadInput(Exception):
    pass


def num(x):
    return math.nan if x is None else float(x)


def comp(name, ours, theirs, agree, tol, **kw):
    d = dict(quantity=name, ours=ours, theirs=theirs, tolerance=tol, agree=bool(agree))
    d.update(kw)
    return d


def cmp_rel(name, ours, theirs, tol, abs_floor=0.0, label=None):
    o, t = num(ours), num(theirs)
    if math.isnan(o) and math.isnan(t):
        return comp(name, o, t, True, "both undefined")
    diff = abs(o - t)
    ok = diff <= tol * abs(t) + abs_floor or diff <= TINY
    return comp(name, o, t, ok, label or ("rel %.3g" % tol + (" + %.3g" % abs_floor if abs_floor else "")),
                rel_diff=diff / abs(t) if t else diff)


def cmp_resid(name, ours, theirs, slack=0.0):
    o, t = num(ours), num(theirs)
    ok = (max(o, t) <= TOL_RESID_FLOOR + slack
          or (o > 0 and t > 0 and max(o, t) <= TOL_RESID_FACTOR * min(o, t))
          or abs(o - t) <= slack)
    return comp(name, o, t, ok, "factor %g or both <= %g%s" % (
        TOL_RESID_FACTOR, TOL_RESID_FLOOR, " (+%.2g floor)" % slack if slack else ""))


# ---------------------------------------------------------------------------------------
# metrics from OUR trajectory
# ---------------------------------------------------------------------------------------
def lsq_slope(t, y):
    t = np.asarray(t, float)
    y = np.asarray(y, float)
    if len(t) < 2:
        return 0.0
    tm = t - t.mean()
    return float(np.dot(tm, y - y.mean()) / np.dot(tm, tm))


class Undef:
    """A metric that is undefined by the docs' rule (docs/conventions.md, "Law residuals and
    their scales"); the report has null there and its reason under `undefined.<name>`."""

    def __init__(self, why):
        self.why = why

    def __repr__(self):
        return "undefined (%s)" % self.why


DBL_MIN = np.finfo(float).tiny


def scale_ok(S):
    """A scale is usable where it is a positive normal number (docs: "Law residuals")."""
    S = np.asarray(S, float)
    return np.isfinite(S) & (S >= DBL_MIN)


def metric_invariants(prob, traj, times, h=None):
    """Conformal laws of the invariants on their scales S(z) (docs/conventions.md, "Law
    residuals and their scales"): step and global residuals on S, the ratio deviation r_n where
    it is resolved, and the undefined points.  With constant gamma the step factor is
    e^{-2 gamma h} from the step size h itself: differencing Gamma(t_n) = gamma t_n loses
    eps gamma t_n (8e-15 relative at gamma t = 19, pde-kg-momentum), 10x the residual's round-off."""
    out = {}
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
        d = dict(scale_initial=float(S[0]), undefined_points=undef)
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
            for k in ("max_step_res", "last_step_res", "max_global_res", "global_res_slope"):
                d[k] = Undef(why)
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
            # our round-off band of r: n steps of u_n each
            d["_ratio_u"] = float(np.max(np.minimum(np.exp(log_u), 1e-8)))
        else:
            k = int(np.argmin(resolved)) if I0 != 0.0 else 0
            why = "r_n unresolved at step %d" % k
            d["max_global_ratio_dev"] = d["ratio_dev_slope"] = Undef(why)
        out[name] = d
    return out


def metric_energy(prob, traj, times, ref=None):
    H = prob.energy(traj)
    dH = H - H[0]
    n = len(H)
    half = n // 2
    a1, a2 = np.max(np.abs(dH[:half + 1])), np.max(np.abs(dH[half:]))
    out = dict(max_abs_change=float(np.max(np.abs(dH))), change_slope=lsq_slope(times, dH),
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


def _horner(c, x):
    """sum_j c[..., j] x^j row by row (c: rows x coefficients, low to high; x: rows, or rows x
    points when c has a point axis inserted)."""
    acc = c[..., -1]
    for j in range(c.shape[-1] - 2, -1, -1):
        acc = acc * x + c[..., j]
    return acc


def dissipation_drift(prob, traj, t0, h):
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
        best = None
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


def poincare_metrics(prob, traj, dt, Zref):
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

    def dist(A, B):          # q is an angle: periodic difference in [-pi, pi)
        dq = np.mod(A[..., 0] - B[..., 0] + math.pi, 2 * math.pi) - math.pi
        return np.hypot(dq, A[..., 1] - B[..., 1])
    pw = dist(S2, R2)
    D = dist(S2[:, None, :], R2[None, :, :])
    return dict(_pairs=D, sections=n, transient_skipped=skip, pointwise_final=float(pw[-1]),
                pointwise_max=float(pw.max()), set_mean=float(D.min(axis=1).mean()),
                set_hausdorff=float(max(D.min(axis=1).max(), D.min(axis=0).max())))


def metric_attractor(prob, traj, t0, dt, nsteps, stride):
    """docs/conventions.md section 5 'attractor': statistics of the probe over the output grid
    points with t >= t0 + (t_end - t0)/2 (t0 itself never), written from that definition."""
    t_end = t0 + nsteps * dt
    frm = t0 + 0.5 * (t_end - t0)
    idx = np.arange(stride, len(traj), stride)
    tt = t0 + dt * idx
    keep = tt >= frm
    tt, s = tt[keep], np.array([prob.probe(traj[i]) for i in idx[keep]])
    out = {"from": frm, "points": float(len(s))}
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


def metric_temperature(prob, traj):
    T = prob.temperature(traj)
    return dict(initial=float(T[0]), max=float(T.max()), min=float(T.min()), mean=float(T.mean()),
                max_abs_dev_initial=float(np.max(np.abs(T - T[0]))))


def metric_precession(prob, traj, ref=None):
    """HLW Fig 2.1: the unwrapped turn of the perihelion direction atan2(A2, A1) of the
    Laplace-Runge-Lenz vector (every step here; the C++ side samples the output grid: the same
    total while no grid step turns it by pi)."""
    def total(z):
        A = prob.runge_lenz(z)
        phi = np.arctan2(A[:, 1], A[:, 0])
        return float(np.sum(np.remainder(np.diff(phi) + math.pi, 2 * math.pi) - math.pi)), A
    tot, A = total(traj)
    ecc = np.hypot(A[:, 0], A[:, 1])
    out = dict(initial_angle=float(math.atan2(A[0, 1], A[0, 0])), min_eccentricity=float(ecc.min()),
               total=tot)
    if ref is not None:
        out["reference_total"], _ = total(ref)
        out["total_minus_reference"] = tot - out["reference_total"]
    return out


def table_factor(method, g, h):
    """B Table 3.1: per-step linear-momentum factor each conformal method achieves."""
    if method in ("csv1", "csv1-perk"):
        return math.exp(-2 * g * h)
    if method in ("csv2", "csv2-perk", "cimp"):   # csv2-perk is csv2 as a PERK pair (B (2.21))
        return math.exp(-g * h) * (2 - g * h) / (2 + g * h)
    return None


def metric_momentum(prob, traj, h, method):
    """Sum p and sum q x p per step (B Ex. 1.3): law residual |X_{n+1} - e^{-2 gamma h} X_n|_2 on
    the scales S_p = sum |p_i|, S_L = sum |q_i||p_i| of z_n, and for the linear momentum the
    factor B Table 3.1 gives the method; the measured factor X_{n+1}.X_n/|X_n|^2 only where
    |X_n| >= 1e-8 S(z_n) (docs/conventions.md, "Law residuals and their scales")."""
    out = {}
    law = math.exp(-2.0 * prob.g * h)
    for kind, fn, sfn in (("linear", prob.linear_momentum, prob.linear_momentum_scale),
                          ("angular", prob.angular_momentum, prob.angular_momentum_scale)):
        P = fn(traj)
        S = sfn(traj)[:-1]
        okS = scale_ok(S)
        Sd = np.where(okS, S, 1.0)
        nrm = np.linalg.norm(P, axis=-1)
        num_ = np.linalg.norm(P[1:] - law * P[:-1], axis=-1)
        step = num_ / Sd
        tf = table_factor(method, prob.g, h) if kind == "linear" else None
        d = dict(initial_norm=float(nrm[0]), scale_initial=float(S[0]),
                 undefined_points=int(np.sum(~okS)), _scale_max=float(np.max(S)))
        if okS.any():
            k = int(np.argmax(np.where(okS, step, -1.0)))
            d.update(max_law_res=float(step[k]), last_law_res=float(step[np.nonzero(okS)[0][-1]]),
                     max_law_abs=float(np.max(num_[okS])), scale_at_max_law_res=float(S[k]),
                     _step=np.where(okS, step, -1.0), _S=S)
            if tf is not None:
                d["max_table_res"] = float(np.max((np.linalg.norm(P[1:] - tf * P[:-1], axis=-1) / Sd)[okS]))
        if not okS.all():
            for k in ("max_law_res", "last_law_res", "max_table_res"):
                if k in d or (k == "max_table_res" and tf is not None):
                    d[k] = Undef("scale not a positive normal number")
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


def metric_conformal_symplectic(method, prob, h, t0, traj):
    """E_n: Psi^T J^-1 Psi against e^{-2 dGamma} J^-1 (canonical), or Psi D Psi^T against
    e^{-2 dGamma} D for a problem with a Poisson structure matrix D (B's Burgers (5.9))."""
    d = prob.d
    n = d // 2
    D = prob.structure() if hasattr(prob, "structure") else None
    Jinv = np.block([[np.zeros((n, n)), np.eye(n)], [-np.eye(n), np.zeros((n, n))]])
    E = []
    for k in range(len(traj) - 1):
        t = t0 + k * h
        Psi = xrun.step_jacobian(method, prob, h, t, traj[k])
        fac = math.exp(-2.0 * xm.dGamma(prob, t, h))
        if D is None:
            E.append((np.linalg.norm(Psi.T @ Jinv @ Psi - fac * Jinv), fac))
        else:
            E.append((np.linalg.norm(Psi @ D @ Psi.T - fac * D), fac))
    Ea = np.array([e for e, _ in E])
    scale = math.sqrt(d) if D is None else np.linalg.norm(D)
    Er = np.array([e / (f * scale) for e, f in E])
    return dict(max_abs=float(Ea.max()), max_rel=float(Er.max()), last_abs=float(Ea[-1]),
                last_rel=float(Er[-1]), steps_measured=len(E), max_rel_step=int(np.argmax(Er)) + 1,
                _Er=Er)


def metric_stability(method, prob, h):
    M = xrun.step_jacobian(method, prob, h, 0.0, np.zeros(2))
    ev = np.linalg.eigvals(M)
    g = prob.g
    ht = 0.5 * np.trace(M)
    w = prob.w
    det, dexp = float(np.linalg.det(M)), math.exp(-2 * g * h)
    b2 = (w - g) * (w + g)
    # exact flow: half trace of e^{hA} = e^{-gh} cos(beta h) (cosh for beta^2 < 0)
    hx = math.exp(-g * h) * (math.cos(math.sqrt(b2) * h) if b2 >= 0 else math.cosh(math.sqrt(-b2) * h))
    out = dict(det=det, det_expected=dexp, det_abs_err=abs(det - dexp),
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


def _component(prob, spec, Z):
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


def _grad_norm(fn, Z):
    """max_n |grad fn(z_n)|_2 by central differences (step 1e-6 |z|; only sizes a floor)."""
    g2 = np.zeros(len(Z))
    for i in range(Z.shape[-1]):
        dz = 1e-6 * np.maximum(1.0, np.abs(Z[:, i]))
        Zp, Zm = Z.copy(), Z.copy()
        Zp[:, i] += dz
        Zm[:, i] -= dz
        g2 += ((fn(Zp) - fn(Zm)) / (2 * dz)) ** 2
    return float(np.sqrt(g2.max()))


def measures(prob, case, Z, Zr, times, dz):
    """measure.<name> of docs/case-keys.md: the pointwise error U_n - u(t_n) of a component
    (Euclidean norm; `rel` divides pointwise by the reference component's norm), or the energy
    error H(U_n) - H(u(t_n)) (`rel`: by |H(u(t_n))|), reduced over the output grid t_1..t_end
    (final, max, mean, rms), or `growth`: least-squares slope of log(running maximum from t_1)
    against log(t - t0) over the grid points t >= from (default t0 + (t_end - t0)/10).
    Returns {name: (value, floor)}: floor = the value's uncertainty from the state bound dz
    (propagated pointwise) and the reference estimate, for the comparison and the verdicts."""
    t0 = float(case.get("t0", 0.0))
    t_end = float(case.get("t_end", times[-1]))
    out = {}
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


def sweep_spec(case):
    """The (gamma, h) grid is an input of the case file (docs/case-keys.md `stability_sweep`),
    not part of the report: read it from the file the report names, else from verify/cases."""
    here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "cases")
    cands = [case.get("file") or "", os.path.join(here, os.path.basename(case.get("file") or "")),
             os.path.join(here, "%s.json" % case["id"])]
    for path in cands:
        if path and os.path.isfile(path):
            try:
                with open(path) as fh:
                    c = json.load(fh)
            except (OSError, ValueError):
                continue
            if c.get("id") == case["id"] and c.get("stability_sweep"):
                return c["stability_sweep"]
    return None


def _in_range(v, rng):
    """rng = [ours, lo, hi] of a first-failure step (None = no failure = beyond the grid)."""
    big = math.inf
    val = big if v is None else float(v)
    lo, hi = (big if x is None else x for x in (rng[1], rng[2]))
    return min(lo, hi) * (1 - 1e-12) <= val <= max(lo, hi) * (1 + 1e-12) or val == rng[0]


def compare_sweep(ours, theirs, comps, mine, unc):
    """Sweep metrics (verify/xsweep.py): counts agree within the number of round-off ties, first
    failure steps within the range ties allow, F's formula boundary exactly, the half-trace
    error rel 1e-9 + 1e-13 (M's entries carry a few eps of rounding), the grid exactly."""
    for k, v in theirs.items():
        if isinstance(v, str):
            continue
        if k in ("grid",):
            comps.append(comp("stability-sweep.grid", ours["grid"], v, ours["grid"] == v, "equal"))
        elif k == "omega":
            continue                       # an input (the case's stability_sweep.omega)
        elif k in ("rows", "first_row"):
            rows_t = v if k == "rows" else [v]
            rows_o = ours["rows"] if k == "rows" else [ours["first_row"]]
            ok, worst = len(rows_t) == len(rows_o), ""
            for ro, rt in zip(rows_o, rows_t):
                if abs(ro["gamma"] - num(rt.get("gamma"))) > 1e-12 * max(1.0, abs(ro["gamma"])):
                    ok, worst = False, "gamma %s" % rt.get("gamma")
                for kk in ("h_F_empirical", "h_power_unbounded", "h_F_formula"):
                    if kk in rt and kk in ro and not _in_range(rt[kk], ro[kk]):
                        ok, worst = False, "%s at gamma %g: ours %s, theirs %s" % (kk, ro["gamma"], ro[kk][0], rt[kk])
                if "max_half_trace_err" in rt and rt["max_half_trace_err"] is not None:
                    a, b = ro["max_half_trace_err"], num(rt["max_half_trace_err"])
                    if not abs(a - b) <= 1e-9 * abs(b) + 1e-13:
                        ok, worst = False, "max_half_trace_err at gamma %g: %r vs %r" % (ro["gamma"], a, b)
            comps.append(comp("stability-sweep.%s" % k, "%d rows" % len(rows_o), "%d rows" % len(rows_t), ok,
                              "first failures within the ties' range, h_F_formula equal, max_half_trace_err "
                              "rel 1e-9 + 1e-13", note=worst))
            if k == "first_row":
                for kk in ("h_F_empirical", "h_power_unbounded"):
                    rng = ours["first_row"][kk]
                    if rng[0] is not None:
                        mine["stability-sweep.first_row." + kk] = rng[0]
                        unc["stability-sweep.first_row." + kk] = max(
                            abs((x if x is not None else rng[0]) - rng[0]) for x in rng)
                mine["stability-sweep.first_row.gamma"] = ours["first_row"]["gamma"]
        elif k in ours:
            o, ties = ours[k]
            t_ = num(v)
            comps.append(comp("stability-sweep." + k, o, v, abs(o - t_) <= ties,
                              "equal within %d round-off tie points" % ties))
            mine["stability-sweep." + k] = o
            unc["stability-sweep." + k] = ties
        else:
            comps.append(comp("stability-sweep." + k, "not computed", v, False, "metric unknown to us"))


def compare_trace_taylor(method, prob, case, theirs, comps, mine, unc):
    """h^4 coefficient (verify/xsweep.trace_taylor, at h = the case's first step size): ours is
    extrapolated to ~1e-6; the report's estimate may carry the truncation of any estimator at
    step sizes <= h, which the band bounds.  Expected: docs/conventions.md §5's magnitudes."""
    w, g = prob.w, prob.g
    h = float((case.get("dt_ladder") or [case["runs"][0]["dt"]])[0])
    c, band = xsweep.trace_taylor(method, w, g, h)
    exp_ = {"cimp": (w * w - g * g) ** 2 / 12, "csv1": w * w * (w * w + 4 * g * g) / 24,
            "csv2": (2 * w ** 4 + 5 * g * g * w * w - 4 * g ** 4) / 48}.get(method)
    vals = {"h4_coeff": (c, band)}
    if exp_ is not None:
        exp_ = abs(exp_)
        vals["h4_coeff_expected"] = (exp_, 1e-12 * exp_)
        vals["h4_coeff_abs_err"] = (abs(c - exp_), band)
        vals["h4_coeff_rel_err"] = ((abs(c - exp_) / exp_, band / exp_) if exp_ > 0
                                    else (Undef("expected coefficient 0"), 0.0))
    for k, v in theirs.items():
        if isinstance(v, str) or k == "undefined":
            continue
        key = "trace-taylor." + k
        if k not in vals:
            comps.append(comp(key, "not computed", v, False, "metric unknown to us"))
            continue
        o, b = vals[k]
        mine[key], unc[key] = o, b
        if v is None or isinstance(o, Undef):
            comps.append(comp(key, repr(o), v, (v is None) == isinstance(o, Undef), "both undefined, or both defined"))
            continue
        comps.append(comp(key, o, v, abs(o - num(v)) <= b, "abs %.3g: truncation of a step-size-h estimate "
                          "plus round-off" % b if k != "h4_coeff_expected" else "rel 1e-12"))


# ---------------------------------------------------------------------------------------
def make_problem(case):
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


def reference_states(prob, case, times):
    """(states at times, error estimate, note)."""
    t0 = float(case.get("t0", 0.0))
    if prob.exact_available and hasattr(prob, "exact"):
        Z = prob.exact(t0, times)
        return Z, getattr(prob, "exact_estimate", 0.0), "exact"
    Z, est = prob.reference_grid(t0, times)
    return Z, est, "DOP853 rtol 2.3e-14 atol 1e-16, certified against rtol 1e-13"


def get_path(d, path):
    for k in path.split("."):
        if not isinstance(d, dict) or k not in d:
            return None
        d = d[k]
    return d


def flatten(prefix, d, out):
    for k, v in d.items():
        key = prefix + "." + k if prefix else k
        if isinstance(v, dict):
            flatten(key, v, out)
        else:
            out[key] = v
    return out


def check_case(case):
    t_case = time.perf_counter()
    c_case = time.process_time()
    for key in ("id", "problem", "runs"):
        if key not in case:
            raise BadInput("a case lacks '%s'" % key)
    cid = case["id"]
    prob, why = make_problem(case)
    runs_out, orders_out, checks_out = [], [], []
    if prob is None:
        for r in case["runs"]:
            runs_out.append(dict(case=cid, method=r.get("method"), dt=r.get("dt"),
                                 verdict="not reproduced", reason=why, comparisons=[], notes=[]))
        # the case's order fits and checks are not reproduced either: count them, never drop them
        for m_, mmd in sorted((case.get("method_metrics") or {}).items()):
            for diag in ("order", "local-order", "stability-sweep", "trace-taylor"):
                if (mmd or {}).get(diag) is not None:
                    orders_out.append(dict(case=cid, method=m_ if diag == "order" else "%s (%s)" % (m_, diag),
                                           verdict="not reproduced", reason=why, comparisons=[], notes=[]))
        for chk in case.get("checks") or []:
            checks_out.append(dict(case=cid, method=chk.get("method"), check=chk.get("name"),
                                   metric=chk.get("metric"), verdict="not reproduced", reason=why,
                                   comparisons=[], notes=[]))
        return dict(runs=runs_out, orders=orders_out, checks=checks_out, case=cid, seconds=0.0,
                    cpu_seconds=0.0, problem=case["problem"].get("id"))
    t0 = float(case.get("t0", 0.0))
    t_end = float(case.get("t_end", 0.0))
    ref = case.get("reference") or {}
    points = int(ref.get("points") or 0)
    ours_metrics = {}        # (method, dt) -> flat metric dict
    ours_unc = {}            # (method, dt) -> {metric: our round-off band}
    my_err = {}              # method -> {dt: final error}
    my_local = {}
    for run in case["runs"]:
        try:
            method, dt = run["method"], float(run["dt"])
        except (KeyError, TypeError) as exc:
            raise BadInput("case %s: malformed run (%s)" % (cid, exc))
        rec = dict(case=cid, method=method, dt=dt, comparisons=[], notes=[])
        runs_out.append(rec)
        if method not in xm.METHODS:
            rec.update(verdict="not reproduced", reason="unknown method '%s'" % method)
            continue
        status = run.get("status", "ok")
        nsteps = int(run.get("steps_planned", run.get("steps", 0)))
        metrics = run.get("metrics") or {}
        need_traj = bool(metrics) and any(k in metrics for k in (
            "error", "invariants", "energy", "momentum", "temperature", "conformal-symplectic",
            "dissipation-drift", "poincare", "precession", "field-drift", "pde-error",
            "attractor"))
        mine = xrun.integrate(method, prob, dt, nsteps, t0, record=need_traj,
                              blowup=None if status == "ok" else 1e100)
        comps = rec["comparisons"]
        ours_metrics[(method, dt)] = {
            "run.steps": mine["steps"], "run.ok": int(mine["status"] == "ok"),
            "run.diverged": int(mine["status"] == "diverged"),
            "run.failed_at_step": mine["steps"] if mine["status"] != "ok" else 0,
            "run.final_time": t0 + mine["steps"] * dt}
        if method in xm.EXPLICIT_EVALS:
            ours_metrics[(method, dt)]["run.rhs_evals"] = mine["steps"] * xm.EXPLICIT_EVALS[method]
            ours_metrics[(method, dt)]["run.jac_evals"] = 0
            ours_metrics[(method, dt)]["run.newton_iters"] = 0
        if "stability" in metrics and isinstance(prob, xp.Oscillator):
            ours_metrics[(method, dt)].update(
                {"stability." + k: v for k, v in metric_stability(method, prob, dt).items()})
        if status != "ok" or mine["status"] != "ok":
            ok = mine["status"] == status
            if ok and "steps" in run and status == "diverged":
                # a run that overflows: the step where a value first becomes inf depends on the
                # rounding of the last finite step (values near 1e308), so one step either way
                ok = abs(mine["steps"] - int(run["steps"])) <= 1
            comps.append(comp("status", mine["status"] + (" at %d" % mine["steps"] if mine["status"] != "ok" else ""),
                              status + (" at %s" % run.get("steps") if status != "ok" else ""), ok,
                              "equal (a divergence step within 1)"))
            rec["verdict"] = "agree" if ok else "disagree"
            continue
        chaotic = None
        eb_floor = 0.0
        kind = "implicit" if method in xm.IMPLICIT else "explicit"
        my_t = t0 + nsteps * dt
        comps.append(cmp_rel("final_time", my_t, run.get("final_time"), TOL_TIME))
        z = mine["z"]
        theirs = np.array([num(x) for x in run.get("final_state", [])])
        scale = max(float(np.linalg.norm(theirs)), TINY)
        diff = float(np.linalg.norm(z - theirs)) if theirs.shape == z.shape else math.inf
        tol = TOL_STATE[kind]
        floor_note = ""
        if mine.get("linear_path"):
            # oscillator by powers of our rounded one-step matrix: |M_ours - M_exact| <= a few
            # eps |M| propagates to at most 4 n eps relative in z_n
            tol = max(tol, 4 * nsteps * EPS)
            floor_note = "linear path, 4 n eps"
        chaotic_ref = False
        if "poincare" in metrics and prob.forcing_period and need_traj:
            # a reference whose certified estimate is not small (a chaotic reference: its two
            # solves differ pointwise) makes every reference-dependent metric statistical, even
            # when our run happens to reproduce the report's final state
            stp = int(round(prob.forcing_period / dt))
            chaotic_ref = reference_states(prob, case, t0 + dt * np.arange(0, nsteps + 1, stp))[1] > 1e-6
        if (diff > tol * scale or chaotic_ref) and math.isfinite(diff):
            # round-off floor from our own sensitivity (see the module docstring)
            z0 = prob.z0.copy()
            prob.z0 = z0 + 4 * EPS * max(1.0, float(np.max(np.abs(z0))))
            pert_run = xrun.integrate(method, prob, dt, nsteps, t0, record=need_traj)
            pert = pert_run["z"]
            prob.z0 = z0
            D = float(np.linalg.norm(pert - z)) / scale
            if method != "glm4" and nsteps >= 2:
                # a perturbation of z0 can be absorbed by an early contracting transient, so
                # the rounding is also injected at mid-run: restart from z_{n/2} (1 + 4 eps)
                half = nsteps // 2
                zm = xrun.integrate(method, prob, dt, half, t0)["z"]
                prob.z0 = zm * (1 + 4 * EPS) + 4 * EPS * TINY
                zbr = xrun.integrate(method, prob, dt, nsteps - half, t0 + half * dt, record=need_traj)
                zb = zbr["z"]
                prob.z0 = z0
                Dm = float(np.linalg.norm(zb - z)) / scale
                if Dm > D and need_traj and mine["traj"] is not None and zbr["traj"] is not None:
                    pert_run = dict(z=zb, traj=np.concatenate([mine["traj"][:half], zbr["traj"]]))
                D = max(D, Dm)
            fl = FLOOR_K * D
            if (D > 1e-8 or chaotic_ref) and need_traj:
                chaotic = pert_run          # metrics get an ensemble band below
            if fl > tol:
                tol = fl
                floor_note = "round-off floor 16 D, D = %.3g" % D
        comps.append(comp("final_state", z.tolist(), theirs.tolist(), diff <= tol * scale,
                          "rel %.3g%s" % (tol, " (" + floor_note + ")" if floor_note else ""),
                          rel_diff=diff / scale))
        state_bound = tol * scale          # absolute state difference we accept
        measure_floor = {}
        mm = ours_metrics[(method, dt)]
        # errors on the output grid
        if "error" in metrics or "order" in (case.get("diagnostics") or []):
            if need_traj and points >= 2:
                stride = max(1, int(round((t_end - t0) / (points - 1) / dt)))
                idx = np.arange(0, nsteps + 1, stride)
            else:
                idx = np.array([nsteps])
            times = t0 + idx * dt
            Zr, est, note = reference_states(prob, case, times)
            Z = mine["traj"][idx] if mine["traj"] is not None else z[None, :]
            e = np.linalg.norm(Z - Zr, axis=-1)
            rn = np.linalg.norm(Zr, axis=-1)
            # a relative error is defined where |z_ref| >= max(DBL_MIN, 100 x the reference's
            # estimate) (docs/conventions.md, "Other relative metrics")
            rel_ok = (rn >= DBL_MIN) & (rn >= 100 * est)
            rel_i = slice(1, None) if len(e) > 1 else slice(0, None)
            mm.update({"error.final_abs": float(e[-1]),
                       "error.final_rel": float(e[-1] / rn[-1]) if rel_ok[-1] else Undef("|z_ref(t_end)| below floor"),
                       "error.max_abs": float(e.max()),
                       # relative error over t_1..t_end (the initial state may be 0)
                       "error.max_rel": float(np.max(e[rel_i] / rn[rel_i])) if rel_ok[rel_i].all()
                       else Undef("|z_ref| below floor on the grid"),
                       "error.mean_abs": float(e[1:].mean()) if len(e) > 1 else float(e[0])})
            my_err.setdefault(method, {})[dt] = (float(e[-1]), est)
            mm["error.reference_error_estimate"] = est      # OUR reference's estimate (verdicts)
            rec["notes"].append("our reference: %s, estimate %.2g" % (note, est))
            their_est = num(get_path(metrics, "error.reference_error_estimate") or 0.0)
            err_slack = state_bound + est + (0.0 if math.isnan(their_est) else their_est)
            for key in ("final_abs", "final_rel", "max_abs", "max_rel", "mean_abs"):
                th = get_path(metrics, "error." + key)
                ours = mm["error." + key]
                if th is None or isinstance(ours, Undef):
                    if th is None and get_path(metrics, "error.undefined." + key) is None:
                        continue
                    comps.append(comp("error." + key, repr(ours) if isinstance(ours, Undef) else ours,
                                      "undefined" if th is None else th,
                                      isinstance(ours, Undef) == (th is None), "both undefined, or both defined"))
                    continue
                sl = err_slack / (rn[-1] if key.endswith("rel") else 1.0)
                big = num(th) >= 1000 * max(est, their_est if not math.isnan(their_est) else 0.0, TINY)
                comps.append(cmp_rel("error." + key, ours, th, TOL_ERR if big else 0.0, abs_floor=sl))
            if case.get("measures"):
                # issue 19's named measures (docs/case-keys.md "Measures as the paper states
                # them") from OUR trajectory and OUR reference on the output grid
                for name, (val, fl) in measures(prob, case, Z, Zr, times, state_bound + est).items():
                    mm["measure." + name] = val
                    measure_floor["measure." + name] = fl
        priv = {}                 # our own round-off bands of metrics (never compared)
        if "local-error" in metrics and prob.exact_available:
            z1 = xrun.integrate(method, prob, dt, 1, t0)["z"]
            ze = prob.exact(t0, [t0 + dt])[0]
            la = float(np.linalg.norm(z1 - ze))
            nze = float(np.linalg.norm(ze))
            # one step and the exact value are each rounded to a few eps |z|: floor 8 eps |z| plus
            # our exact solution's estimate (the rigid body's: the phase round-off of its elliptic closed form)
            priv["local-error.floor"] = 8 * EPS * nze + getattr(prob, "exact_estimate", 0.0)
            priv["local-error.norm"] = nze
            mm["local-error.abs"] = la
            mm["local-error.rel"] = la / nze if nze > 0 else Undef("exact solution at t0 + h has norm 0")
            my_local.setdefault(method, {})[dt] = la
        traj = mine["traj"]
        if traj is not None and "energy-balance" in metrics and points >= 10:
            # B (3.4): R_n = |D_t H_n + 2 gamma p_n^2| with the 8th-order central difference on the
            # output grid (interior points n = 4 .. N-4)
            stride = max(1, int(round((t_end - t0) / (points - 1) / dt)))
            Zg = traj[::stride]
            Hg = prob.energy(Zg)
            w8 = np.array([1 / 280, -4 / 105, 1 / 5, -4 / 5, 0.0, 4 / 5, -1 / 5, 4 / 105, -1 / 280])
            D = np.convolve(Hg, w8[::-1], mode="valid") / (stride * dt)
            pg = Zg[4:-4, prob.nq:]
            Rb = np.abs(D + 2 * prob.g * np.sum(pg * prob.dT(pg), axis=-1))
            diss = 2 * prob.g * np.sum(pg * prob.dT(pg), axis=-1)
            mm.update({"energy-balance.max": float(Rb.max()), "energy-balance.mean": float(Rb.mean()),
                       # relative to the largest dissipation rate 2 gamma p.grad T(p) on the grid
                       "energy-balance.max_rel": float(Rb.max() / diss.max()) if diss.max() >= DBL_MIN
                       else Undef("max |dH/dt| is 0"),
                       "energy-balance.max_rate": float(np.max(np.abs(diss))),
                       "energy-balance.last": float(Rb[-1]), "energy-balance.points": len(Rb)})
            # round-off floor of the difference quotient: 8 eps max|H| sum|w| / Delta
            eb_floor = 8 * EPS * float(np.max(np.abs(Hg))) * float(np.sum(np.abs(w8))) / (stride * dt)
        if traj is not None:
            times = t0 + dt * np.arange(len(traj))
            if "invariants" in metrics:
                for name, vals in metric_invariants(prob, traj, times, dt).items():
                    for k, v in vals.items():
                        (priv if k.startswith("_") else mm)["invariants.%s.%s" % (name, k)] = v
            if "energy" in metrics:
                # energy is sampled on the run's output grid (observed.grid_points)
                gp = int(get_path(run, "observed.grid_points") or 0)
                st = max(1, int(round(nsteps / (gp - 1)))) if gp >= 2 else 1
                for k, v in metric_energy(prob, traj[::st], times[::st]).items():
                    mm["energy." + k] = v
            if "poincare" in metrics and prob.forcing_period:
                stride = int(round(prob.forcing_period / dt))
                ts = t0 + dt * np.arange(0, nsteps + 1, stride)
                Zs, _, _ = reference_states(prob, case, ts)
                for k, v in poincare_metrics(prob, traj, dt, Zs).items():
                    (priv if k.startswith("_") else mm)["poincare." + k] = v
            if "dissipation-drift" in metrics and prob.nq == 1:
                dd = dissipation_drift(prob, traj, t0, dt)
                for k, v in dd.items():
                    if k != "_d":
                        mm["dissipation-drift." + k] = v
                if "reference" in (metrics.get("dissipation-drift") or {}):
                    # the reference's d(t) from OUR reference sampled at the same step times
                    Zr_all, _, _ = reference_states(prob, case, times)
                    rd = dissipation_drift(prob, Zr_all, t0, dt)
                    for k, v in rd.items():
                        if k != "_d":
                            mm["dissipation-drift.reference." + k] = v
                    k_ = min(len(dd["_d"]), len(rd["_d"]))
                    mm["dissipation-drift.max_abs_diff_reference"] = (
                        float(np.max(np.abs(dd["_d"][:k_] - rd["_d"][:k_]))) if k_ else 0.0)
                    mm["dissipation-drift.maxima_count_diff"] = dd["maxima"] - rd["maxima"]
                    if isinstance(dd.get("slope"), float) and isinstance(rd.get("slope"), float):
                        mm["dissipation-drift.slope_minus_reference"] = dd["slope"] - rd["slope"]
            if "energy" in metrics and "error" in metrics and points >= 2:
                # F Fig 4.3: H(reference) - H(method) on the output grid
                stride = max(1, int(round((t_end - t0) / (points - 1) / dt)))
                idx = np.arange(0, nsteps + 1, stride)
                Zr, _, _ = reference_states(prob, case, t0 + idx * dt)
                Hr, Hm = prob.energy(Zr), prob.energy(traj[idx])
                de = Hr - Hm
                mm["energy.max_abs_error"] = float(np.max(np.abs(de)))
                mm["energy.final_abs_error"] = float(abs(de[-1]))
                mm["energy.drift_slope"] = lsq_slope(t0 + idx * dt, de)
                if prob.energy_scale is not None:
                    Sr = prob.energy_scale(Zr)
                    mm["energy.error_res_slope"] = (lsq_slope(t0 + idx * dt, de / Sr) if scale_ok(Sr).all()
                                                    else Undef("energy scale of the reference not normal"))
            if "temperature" in metrics and hasattr(prob, "temperature"):
                for k, v in metric_temperature(prob, traj).items():
                    mm["temperature." + k] = v
            if "field-drift" in metrics and hasattr(prob, "field_size"):
                # B (5.6): d = ln max_x u + Gamma(t) - Gamma(t0) on the output grid without t0
                gp = int(get_path(run, "observed.grid_points") or 0)
                stride = max(1, int(round(nsteps / (gp - 1)))) if gp >= 2 else 1
                idx = np.arange(stride, len(traj), stride)
                tt = t0 + dt * idx
                mx = np.max(traj[idx, :prob.field_size()], axis=1)
                if len(idx) >= 2 and np.all(mx > 0):
                    dd = np.log(mx) + np.array([xm.dGamma(prob, t0, x - t0) for x in tt])
                    mm["field-drift.slope"] = lsq_slope(tt, dd)
                    mm["field-drift.range"] = float(dd.max() - dd.min())
                    mm["field-drift.first"] = [float(tt[0]), float(dd[0])]
                    mm["field-drift.last"] = [float(tt[-1]), float(dd[-1])]
                    mm["field-drift.points"] = float(len(idx))
            if "attractor" in metrics and hasattr(prob, "probe"):
                gp = int(get_path(run, "observed.grid_points") or 0)
                stride = max(1, int(round(nsteps / (gp - 1)))) if gp >= 2 else 1
                for k, v in metric_attractor(prob, traj, t0, dt, nsteps, stride).items():
                    mm["attractor." + k] = v
            if "pde-error" in metrics and hasattr(prob, "pde_solution"):
                # B Fig 5.4: max-norm error against the PDE's solution on the output grid, t0 left out
                gp = int(get_path(run, "observed.grid_points") or 0)
                stride = max(1, int(round(nsteps / (gp - 1)))) if gp >= 2 else 1
                idx = np.arange(stride, len(traj), stride)
                errs, rels = [], []
                for i in idx:
                    u = prob.pde_solution(t0, t0 + dt * i)
                    if u is None:
                        errs = None
                        break
                    e = float(np.max(np.abs(traj[i, :len(u)] - u)))
                    errs.append(e)
                    rels.append(e / float(np.max(np.abs(u))))
                if errs:
                    mm["pde-error.max_abs"] = max(errs)
                    mm["pde-error.final_abs"] = errs[-1]
                    mm["pde-error.max_rel"] = max(rels)
                    mm["pde-error.points"] = float(len(errs))
            if "precession" in metrics and hasattr(prob, "runge_lenz") and len(traj) >= 2:
                Zr, _, _ = reference_states(prob, case, t0 + dt * np.arange(len(traj)))
                pm = metric_precession(prob, traj, Zr)
                pm["rate"] = pm["total"] / (t0 + dt * (len(traj) - 1) - t0)
                # the largest turn between two points of the output grid (the C++ side's samples)
                gp = int(get_path(run, "observed.grid_points") or 0)
                A = prob.runge_lenz(traj[::max(1, int(round(nsteps / (gp - 1)))) if gp >= 2 else 1])
                dphi = np.diff(np.arctan2(A[:, 1], A[:, 0]))
                pm["max_grid_step"] = float(np.max(np.abs(np.remainder(dphi + math.pi, 2 * math.pi)
                                                          - math.pi)))
                for k, v in pm.items():
                    mm["precession." + k] = v
            if "momentum" in metrics and hasattr(prob, "linear_momentum"):
                for kk, vals in metric_momentum(prob, traj, dt, method).items():
                    for k, v in vals.items():
                        (priv if k.startswith("_") else mm)["momentum.%s.%s" % (kk, k)] = v
            # a general linear method steps r values: its one-step map of z alone has no Jacobian
            # (dampsym reports E_n as not applicable for it, as for a Poisson problem)
            has_cs = prob.canonical or (hasattr(prob, "structure") and prob.structure() is not None)
            if "conformal-symplectic" in metrics and has_cs and method != "glm4":
                for k, v in metric_conformal_symplectic(method, prob, dt, t0, traj).items():
                    (priv if k.startswith("_") else mm)["conformal-symplectic." + k] = v
        if "cost" in metrics and method in xm.EXPLICIT_EVALS:
            # implicit methods' counts depend on each side's Newton: not reproduced
            mm["cost.rhs_evals_per_step"] = float(xm.EXPLICIT_EVALS[method])
            mm["cost.max_newton_iters"] = 0
            mm["cost.jac_evals_per_step"] = 0.0
            mm["cost.newton_iters_per_step"] = 0.0
        cost_range = {}
        run_counts = {"run.newton_iters", "run.rhs_evals", "run.jac_evals"}
        wants_counts = "cost" in metrics or any(
            c_.get("metric") in run_counts and c_.get("method") == method for c_ in case.get("checks") or [])
        if wants_counts and method in xm.IMPLICIT and xnewton.supported(method):
            # Newton counts: the range of a stated family of correct solvers (verify/xnewton.py)
            if method == "glm4":
                gy = mine.get("glm_y")
                if gy is None:
                    gy = xrun.integrate(method, prob, dt, nsteps, t0, record=True).get("glm_y")
                cost_range = xnewton.glm_cost_metrics(prob, dt, t0, gy)
            elif mine.get("linear_path"):
                cost_range = xnewton.linear_cost_metrics(method, xnewton._coef(method, prob, dt)[1](t0)[2].size,
                                                         nsteps)
            else:
                tr = traj if traj is not None else xrun.integrate(method, prob, dt, nsteps, t0, record=True)["traj"]
                cost_range = xnewton.cost_metrics(method, prob, dt, t0, tr)
            for k, (o, lo, hi) in cost_range.items():
                mm[k] = o
        ours_metrics[(method, dt)] = mm
        unc = ours_unc.setdefault((method, dt), {})
        for k, (o, lo, hi) in cost_range.items():
            unc[k] = max(hi - o, o - lo)      # a threshold inside the family's range is a tie
        band = {}
        if chaotic is not None and chaotic.get("traj") is not None:
            # chaotic run: two of our own runs 4 eps apart diverge; each trajectory metric gets
            # the band 16 |m - m'| between them (the C++ run is a third such member)
            T2 = chaotic["traj"]
            tt2 = t0 + dt * np.arange(len(T2))
            alt = {}
            if "energy" in metrics:
                gp = int(get_path(run, "observed.grid_points") or 0)
                st = max(1, int(round(nsteps / (gp - 1)))) if gp >= 2 else 1
                alt.update({"energy." + k: v for k, v in metric_energy(prob, T2[::st], tt2[::st]).items()})
            if "temperature" in metrics and hasattr(prob, "temperature"):
                alt.update({"temperature." + k: v for k, v in metric_temperature(prob, T2).items()})
            if "poincare" in metrics and prob.forcing_period:
                stride = int(round(prob.forcing_period / dt))
                Zs, _, _ = reference_states(prob, case, t0 + dt * np.arange(0, nsteps + 1, stride))
                alt.update({"poincare." + k: v for k, v in poincare_metrics(prob, T2, dt, Zs).items()
                            if k not in ("sections", "transient_skipped", "_pairs")})
                priv["poincare._alt_hausdorff"] = alt["poincare.set_hausdorff"]
            if "momentum" in metrics and hasattr(prob, "linear_momentum"):
                for kk, vals in metric_momentum(prob, T2, dt, method).items():
                    alt.update({"momentum.%s.%s" % (kk, k): v for k, v in vals.items()})
            if "attractor" in metrics and hasattr(prob, "probe"):
                gp = int(get_path(run, "observed.grid_points") or 0)
                st = max(1, int(round(nsteps / (gp - 1)))) if gp >= 2 else 1
                alt.update({"attractor." + k: v for k, v in
                            metric_attractor(prob, T2, t0, dt, nsteps, st).items()})
            for k, v in alt.items():
                if isinstance(mm.get(k), float) and isinstance(v, float):
                    band[k] = FLOOR_K * abs(mm[k] - v)
                    if k in ("attractor.mean_se", "attractor.mean_rse"):
                        # a standard error from 10 batch means is itself a sample statistic with
                        # a relative spread of 1/sqrt(18) = 24 %: two estimates agree to a factor 2
                        band[k] = max(band[k], abs(mm[k]))
            rec["notes"].append("chaotic run: metric bands from our own 4-eps ensemble")
        # compare every other metric the report has, by name
        flat = flatten("", metrics, {})
        for key, th in sorted(flat.items()):
            if isinstance(th, str):
                continue            # provenance strings (table_source, formula_source, ...)
            # the step Jacobian's check against central differences (docs/conventions.md
            # "Derivative checks"): rounding-level disagreements of the kernel's own central
            # differences, not a property of the trajectory; its verdict is the status
            if key.startswith("conformal-symplectic.jacobian_check"):
                continue
            if key.startswith("error.") or key.endswith("wall_seconds") \
                    or key in ("conformal-symplectic.norm", "conformal-symplectic.status",
                               "conformal-symplectic.jacobian",
                               "stability.formula_source", "stability.eigenvalues"):
                continue
            if th is None or isinstance(mm.get(key), Undef):
                # null in the report: undefined there, its reason under `undefined.<name>`;
                # ours must be undefined by the same rule (docs/conventions.md, "Law residuals")
                ours = mm.get(key)
                why = get_path(metrics, ".".join(key.split(".")[:-1] + ["undefined", key.split(".")[-1]]))
                if th is None and key not in mm:
                    rec["notes"].append("metric %s not reproduced" % key)
                    rec.setdefault("not_reproduced", []).append(key)
                    continue
                comps.append(comp(key, repr(ours) if isinstance(ours, Undef) else ours,
                                  "undefined (%s)" % why if th is None else th,
                                  isinstance(ours, Undef) == (th is None), "both undefined, or both defined"))
                continue
            if key not in mm or mm[key] is None:
                rec["notes"].append("metric %s not reproduced" % key)
                rec.setdefault("not_reproduced", []).append(key)
                continue
            ours = mm[key]
            if chaotic is not None and key in ("poincare.pointwise_final", "poincare.pointwise_max",
                                               "poincare.set_hausdorff") and "poincare._pairs" in priv:
                # chaotic run: the trajectory and the reference decorrelate (the report's own
                # certified estimate is O(100)), so a pointwise distance after the transient is a
                # random draw from the distances between two independent points of the attractor.
                # Their distribution is estimated by ALL pairs (our section i, our reference's
                # section j), n^2 ~ 7e4 draws; a statistic agrees when it is inside the range that
                # distribution gives it (a statistical comparison, never pointwise):
                #   pointwise_final: one draw, inside [min, max] of the pair distances;
                #   pointwise_max: the maximum of n draws, between the 1e-3 quantile of that
                #     maximum (F^{-1}(1e-3^{1/n}), F the pairs' distribution) and the largest pair;
                #   set_hausdorff: the largest gap between two n-point samples of one attractor,
                #     an extreme value: within a factor 2 of the range over our own ensemble
                #     (our run and our run perturbed by 4 eps, each against our reference).
                D = np.sort(priv["poincare._pairs"].ravel())
                nsec = priv["poincare._pairs"].shape[0]
                t_ = num(th)
                if key.endswith("pointwise_final"):
                    lo, hi, why = float(D[0]), float(D[-1]), "one draw of the attractor's pair distances"
                elif key.endswith("pointwise_max"):
                    # (the largest of the ~n^2 sample pairs is itself a sample extreme and falls
                    # short of the attractor's diameter: another trajectory's maximum exceeded it
                    # by 0.1% (cimp on driven-pendulum-fig35-poincare), hence a 1% margin)
                    q = 1e-3 ** (1.0 / nsec)
                    lo, hi = float(D[min(len(D) - 1, int(q * len(D)))]), 1.01 * float(D[-1])
                    why = "max of %d draws: [1e-3 quantile, 1.01 x largest pair]" % nsec
                else:
                    ens = [float(ours), float(priv.get("poincare._alt_hausdorff", ours))]
                    lo, hi, why = 0.5 * min(ens), 2.0 * max(ens), "factor 2 around our ensemble %s" % ens
                comps.append(comp(key, ours, th, lo <= t_ <= hi, "statistical, chaotic run: in [%.4g, %.4g] (%s)"
                                  % (lo, hi, why)))
                unc[key] = max(hi - float(ours), float(ours) - lo)
                continue
            if key.startswith("dissipation-drift.") and key.split(".")[-1] in ("first", "last", "slope",
                                                                                "range", "slope_minus_reference",
                                                                                "max_abs_diff_reference"):
                # d = ln q_max + Gamma(t): our state agrees to `tol` relative (ln q to tol absolute),
                # Gamma(t) is rounded to 8 eps |Gamma|; slopes divide that by the time span
                G_end = abs(prob.Gamma(t0 + nsteps * dt) - prob.Gamma(t0))
                dfl = tol + 8 * EPS * (G_end + 1.0)
                if "slope" in key:
                    dfl *= 2.0 / max(nsteps * dt, TINY)
                unc[key] = dfl
                if isinstance(th, list):
                    ok = all(abs(a - num(b)) <= TOL_METRIC * abs(num(b)) + dfl for a, b in zip(ours, th))
                    comps.append(comp(key, ours, th, ok, "rel %g + %.2g per entry" % (TOL_METRIC, dfl)))
                else:
                    comps.append(cmp_rel(key, ours, th, TOL_METRIC, abs_floor=dfl))
                continue
            if key in cost_range:
                o, lo, hi = cost_range[key]
                t_ = num(th)
                comps.append(comp(key, o, th, lo - 1e-9 <= t_ <= hi + 1e-9,
                                  "within [%.6g, %.6g]: full to simplified Newton, tests 1e-8 to 1e-15 "
                                  "(verify/xnewton.py)" % (lo, hi)))
                continue
            if key.startswith("measure."):
                # a measure of the error: rel 1e-6 plus its floor propagated from the state bound
                # and the reference estimates (as error.*), which is also the verdicts' band
                fl = measure_floor.get(key, 0.0)
                unc[key] = fl
                comps.append(cmp_rel(key, ours, th, TOL_METRIC, abs_floor=fl + 1e-300,
                                     label="rel %g + propagated floor %.2g" % (TOL_METRIC, fl)))
                continue
            if key.startswith("energy-balance.") and key != "energy-balance.points":
                unc[key] = eb_floor if key != "energy-balance.max_rel" else eb_floor / max(diss.max(), TINY)
                comps.append(cmp_rel(key, ours, th, TOL_METRIC, abs_floor=eb_floor,
                                     label="rel %g + difference-quotient floor %.2g" % (TOL_METRIC, eb_floor)))
                continue
            if key in band and key.endswith(("step_res", "law_res", "table_res", "factor_dev", "global_res")):
                # chaotic run, a residual: factor 2 or both below its floor plus the ensemble band
                unc[key] = band[key]
                comps.append(cmp_resid(key, ours, th, slack=band[key]))
                continue
            if key in band and not key.endswith(("scale_at_max_step_res", "scale_at_max_law_res")):
                unc[key] = band[key]
                comps.append(cmp_rel(key, ours, th, TOL_METRIC, abs_floor=band[key],
                                     label="rel %g + ensemble band %.3g" % (TOL_METRIC, band[key])))
                continue
            if key.startswith("momentum.") and key.endswith(("factor_dev", "first_factor")):
                # a measured factor's round-off is eps S(z_n)/|X_n| per step (defined: <= 1e-8)
                fu = 8 * priv.get("momentum.%s._factor_u" % key.split(".")[1], 1e-8)
                unc[key] = fu
                if key.endswith("factor_dev"):
                    comps.append(cmp_resid(key, ours, th, slack=fu))
                else:
                    comps.append(cmp_rel(key, ours, th, TOL_METRIC, abs_floor=fu))
                continue
            if key.startswith("momentum.") and key.endswith("initial_norm"):
                # |sum of N vectors|: its round-off is N eps S(z_0) (summation order differs)
                kk = key.split(".")[1]
                fl = 4 * prob.n * EPS * mm.get("momentum.%s.scale_initial" % kk, 0.0)
                comps.append(cmp_rel(key, ours, th, TOL_METRIC, abs_floor=fl))
                continue
            if key.endswith(("max_step_abs", "max_law_abs")):
                # absolute numerator of a residual: its floor is the residual floor times the scale
                base = key.rsplit(".", 1)[0]
                sc = max([0.0] + [x for x in (num(flat.get(base + ".scale_initial")),
                                              priv.get(base + "._scale_max", 0.0),
                                              num(flat.get(base + ".scale_at_max_step_res")),
                                              num(flat.get(base + ".scale_at_max_law_res")))
                                  if isinstance(x, float) and math.isfinite(x)])
                unc[key] = TOL_RESID_FLOOR * sc + (256 * EPS * sc if mine.get("linear_path") else 0.0)
                comps.append(cmp_resid(key, ours, th, slack=unc[key]))
                continue
            if key.endswith(("scale_at_max_step_res", "scale_at_max_law_res")):
                # the scale at the step of the maximum: defined only when that maximum stands
                # above round-off (1e-10), as for conformal-symplectic.max_rel_step
                res_key = key.replace("scale_at_", "")
                if num(flat.get(res_key)) > 1e-10:
                    # the maximum may be a near-tie between steps (a linear map's residual on its
                    # scale is nearly phase-independent): any step whose residual is within the
                    # residual tolerance (rel 1e-6 + the linear path's 256 eps) of our maximum is
                    # a candidate, and theirs must be the scale at one of them (rel 1e-6)
                    base = key.rsplit(".", 1)[0]
                    st_, S_ = priv.get(base + "._step"), priv.get(base + "._S")
                    mx = float(np.max(st_))
                    cand = S_[st_ >= mx * (1 - TOL_METRIC) - 256 * EPS]
                    t_ = num(th)
                    ok = bool(np.any(np.abs(cand - t_) <= TOL_METRIC * abs(t_) + state_bound))
                    comps.append(comp(key, ours, th, ok, "scale at a step within rel 1e-6 of the max residual"
                                      " (%d candidates), rel 1e-6" % len(cand)))
                else:
                    rec["notes"].append("%s: argmax of a round-off residual, not compared" % key)
                continue
            if key.endswith("scale_initial"):
                # a function of z0 alone (a few sums of products): 64 eps
                comps.append(cmp_rel(key, ours, th, 64 * EPS, abs_floor=1e-300))
                continue
            if key.endswith("growth_ratio"):
                e0 = abs(float(prob.energy(prob.z0)))
                if mm.get("energy.max_abs_change", 1.0) <= 8 * math.sqrt(max(nsteps, 1)) * EPS * e0:
                    comps.append(comp(key, ours, th, True, "energy change at round-off: ratio undefined"))
                    continue
            if key in ("local-error.abs", "local-error.rel"):
                fl = priv.get("local-error.floor", 0.0)
                if key.endswith("rel"):
                    fl /= max(priv.get("local-error.norm", 0.0), TINY)
                unc[key] = fl
                comps.append(cmp_rel(key, ours, th, TOL_METRIC, abs_floor=fl))
                continue
            if key.startswith("precession.") and key.endswith(("total", "rate")):
                # the unwrapped turn is a sum of n angle increments, each rounded to a few eps
                # (atan2 of A, the remainder mod 2 pi, the sum): floor 8 pi n eps (rate: / span)
                unc[key] = 8 * math.pi * max(nsteps, 1) * EPS
                if key.endswith("rate"):
                    unc[key] /= max(nsteps * dt, TINY)
                comps.append(cmp_rel(key, ours, th, TOL_METRIC, abs_floor=unc[key]))
                continue
            if key == "conformal-symplectic.max_rel_step":
                # the step of the maximum is only defined when E_n is above round-off, and only
                # up to ties: dampsym's step agrees when our E_n there is the maximum to 1e-9
                # relative (a defect nearly constant over the steps has no well-defined argmax)
                if num(flat.get("conformal-symplectic.max_rel")) > 1e-10:
                    Er = priv.get("conformal-symplectic._Er")
                    ok = ours == th or (Er is not None and isinstance(th, (int, float))
                                        and 1 <= th <= len(Er)
                                        and Er[int(th) - 1] >= Er.max() * (1 - 1e-9))
                    comps.append(comp(key, ours, th, ok, "equal, or a tie to 1e-9"))
                continue
            if key.startswith("invariants.") and key.endswith("global_res_slope"):
                # slope of a residual whose round-off floor is 8 n eps (see below) over the span
                unc[key] = 8 * nsteps * EPS / max(nsteps * dt, TINY)
                comps.append(cmp_rel(key, ours, th, TOL_METRIC, abs_floor=unc[key]))
                continue
            if key.endswith("max_global_res"):
                # global residual accumulates one rounding per step on S(z_n): floor 8 n eps
                unc[key] = 8 * nsteps * EPS
                comps.append(cmp_resid(key, ours, th, slack=unc[key]))
                continue
            if key.startswith("invariants.") and key.endswith(("max_global_ratio_dev", "ratio_dev_slope")):
                # r_n carries u_n = eps S(z_n)/|e^{-2 Gamma} I_0| per step (<= 1e-8 where it is
                # resolved, else r is known to 1 %): floor 8 n max u_n, factor 2 above it
                u = priv.get(key.rsplit(".", 1)[0] + "._ratio_u", 1e-8)
                unc[key] = 8 * nsteps * u
                if key.endswith("slope"):
                    unc[key] /= max(nsteps * dt, TINY)
                    comps.append(cmp_rel(key, ours, th, TOL_METRIC, abs_floor=unc[key]))
                else:
                    comps.append(cmp_resid(key, ours, th, slack=unc[key]))
                continue
            if key == "stability.F_condition":
                # F's condition |half trace| < e^{-gamma h} decided within 4 eps is a tie
                margin = abs(mm["stability.half_trace"]) - math.exp(-prob.g * dt)
                tie = abs(margin) <= 4 * EPS * math.exp(-prob.g * dt)
                comps.append(comp(key, ours, th, ours == th or tie,
                                  "equal (a tie within 4 eps of e^{-gamma h} agrees)", margin=margin))
                continue
            if key.startswith("stability."):
                if key == "stability.matrix":
                    M, T = np.array(ours), np.array([[num(x) for x in r] for r in th])
                    dd = float(np.abs(M - T).max())
                    comps.append(comp(key, ours, th, dd <= TOL_STAB * np.abs(M).max(), "abs %g max|M|" % TOL_STAB))
                elif key == "stability.spectral_radius":
                    comps.append(cmp_rel(key, ours, th, TOL_RHO))
                elif key in ("stability.det_abs_err", "stability.half_trace_formula_abs_err"):
                    # |x - f| of two O(e^{-gamma h}) numbers each rounded a few times: factor 2
                    # or both below 8 eps max(1, |f|) (their round-off floor)
                    ref_ = abs(num(flat.get("stability.det_expected" if "det" in key else
                                            "stability.half_trace_formula")))
                    comps.append(cmp_resid(key, ours, th, slack=8 * EPS * max(1.0, ref_)))
                elif key in ("stability.det_rel_err", "stability.half_trace_formula_rel_err"):
                    comps.append(cmp_resid(key, ours, th, slack=8 * EPS))   # round-off quantities
                elif key == "stability.half_trace_exact_err":
                    comps.append(cmp_rel(key, ours, th, 1e-9, abs_floor=8 * EPS))
                else:
                    comps.append(cmp_rel(key, ours, th, TOL_STAB, abs_floor=1e-300))
            elif any(s in key for s in ("step_res", "law_res", "table_res",
                                        "conformal-symplectic.max",
                                        "conformal-symplectic.last")):
                # on the linear path a per-step residual also carries M's own rounding: 256 eps
                unc[key] = 256 * EPS if mine.get("linear_path") else 0.0
                comps.append(cmp_resid(key, ours, th, slack=unc[key]))
            elif key.startswith("energy."):
                # energy changes of a conservative run are round-off sums: they accumulate like a
                # random walk, floor 8 sqrt(n) eps |H0| (slopes: that floor over the run time)
                # (on the energy's scale S_H: the round-off of H = T + V is eps (T + |V|))
                e0 = abs(float(prob.energy(prob.z0)))
                if prob.energy_scale is not None:
                    e0 = max(e0, float(prob.energy_scale(prob.z0)))
                fl = 8 * math.sqrt(max(nsteps, 1)) * EPS * e0
                if "_res" in key:
                    fl /= max(e0, TINY)
                if "slope" in key:
                    fl /= max(nsteps * dt, TINY)
                if key.endswith("growth_ratio"):
                    fl = 0.0
                unc[key] = fl
                comps.append(cmp_rel(key, ours, th, TOL_METRIC, abs_floor=fl + 1e-300))
            elif isinstance(th, list) and isinstance(ours, list) and len(th) == len(ours):
                ok = all(abs(a - num(b)) <= TOL_METRIC * abs(num(b)) + 1e-12 for a, b in zip(ours, th))
                comps.append(comp(key, ours, th, ok, "rel %g per entry (+1e-12)" % TOL_METRIC))
            elif isinstance(th, (int, float)):
                comps.append(cmp_rel(key, ours, th, TOL_METRIC, abs_floor=1e-300))
        rec["verdict"] = "agree" if all(c["agree"] for c in comps) else "disagree"

    # order fits from OUR errors
    for method, mmd in sorted((case.get("method_metrics") or {}).items()):
        theirs = (mmd or {}).get("order")
        if theirs is None:
            continue
        rec = dict(case=cid, method=method, comparisons=[], notes=[])
        orders_out.append(rec)
        errs = my_err.get(method, {})
        if not errs:
            rec.update(verdict="not reproduced", reason="no errors of our own for %s" % method)
            continue
        est = max(v[1] for v in errs.values())
        t_ref = reference_states(prob, case, np.array([t_end]))[0][-1]
        floor = max(1000 * EPS * max(1.0, float(np.linalg.norm(t_ref))), 100 * est)
        fit = fit_order(list(errs.keys()), [v[0] for v in errs.values()], floor)
        ok_t = bool(theirs.get("ok"))
        if fit["ok"] and ok_t:
            c = cmp_rel("order.slope", fit["slope"], theirs.get("slope"), 0.0, abs_floor=TOL_ORDER,
                        label="abs %g" % TOL_ORDER)
        else:
            c = comp("order.ok", fit["ok"], ok_t, fit["ok"] == ok_t, "equal")
        rec["comparisons"].append(c)
        for m_, dt_ in ((method, d) for d in errs):
            ours_metrics.setdefault((m_, dt_), {})
        for key in ("slope", "r2"):
            if fit.get(key) is not None:
                for d in errs:
                    ours_metrics[(method, d)]["order." + key] = fit[key]
        ours_metrics.setdefault((method, None), {}).update(
            {"order.slope": fit.get("slope"), "order.r2": fit.get("r2")})
        rec["verdict"] = "agree" if c["agree"] else "disagree"

    # local order: fit of OUR one-step errors (floor 1000 eps max(1, |z|))
    for method, mmd in sorted((case.get("method_metrics") or {}).items()):
        theirs = (mmd or {}).get("local-order")
        if theirs is None:
            continue
        rec = dict(case=cid, method=method + " (local-order)", comparisons=[], notes=[])
        orders_out.append(rec)
        errs = my_local.get(method, {})
        if not errs:
            rec.update(verdict="not reproduced", reason="no local errors of our own")
            continue
        fit = fit_order(list(errs), list(errs.values()), 1000 * EPS * max(1.0, float(np.linalg.norm(prob.z0))))
        if fit["ok"] and theirs.get("ok"):
            cc = cmp_rel("local-order.slope", fit["slope"], theirs.get("slope"), 0.0, abs_floor=TOL_ORDER,
                         label="abs %g" % TOL_ORDER)
        else:
            cc = comp("local-order.ok", fit["ok"], bool(theirs.get("ok")), fit["ok"] == bool(theirs.get("ok")), "equal")
        rec["comparisons"].append(cc)
        rec["verdict"] = "agree" if cc["agree"] else "disagree"
        for d in errs:
            ours_metrics.setdefault((method, d), {})["local-order.slope"] = fit.get("slope")
        ours_metrics.setdefault((method, None), {})["local-order.slope"] = fit.get("slope")

    # stability sweep and trace-taylor (method-level): from OUR one-step matrices (verify/xsweep.py)
    for method, mmd in sorted((case.get("method_metrics") or {}).items()):
        for diag in ("stability-sweep", "trace-taylor"):
            theirs = (mmd or {}).get(diag)
            if theirs is None:
                continue
            rec = dict(case=cid, method=method + " (%s)" % diag, comparisons=[], notes=[])
            orders_out.append(rec)
            mine_ = ours_metrics.setdefault((method, None), {})
            unc_ = ours_unc.setdefault((method, None), {})
            if not isinstance(prob, xp.Oscillator) or method not in xm.METHODS:
                rec.update(verdict="not reproduced", reason="%s needs the oscillator and a known method" % diag)
                continue
            if diag == "stability-sweep":
                spec = sweep_spec(case)
                if spec is None:
                    rec.update(verdict="not reproduced", reason="case file with `stability_sweep` not found")
                    continue
                compare_sweep(xsweep.sweep(method, spec), theirs, rec["comparisons"], mine_, unc_)
            else:
                compare_trace_taylor(method, prob, case, theirs, rec["comparisons"], mine_, unc_)
            rec["verdict"] = "agree" if all(c_["agree"] for c_ in rec["comparisons"]) else "disagree"

    # every check's verdict from OUR value
    for chk in case.get("checks") or []:
        metric = chk.get("metric")
        method = chk.get("method")
        dt = chk.get("dt")
        rec = dict(case=cid, method=method, check=chk.get("name"), metric=metric, comparisons=[], notes=[])
        if dt is not None:
            rec["dt"] = float(dt)
        checks_out.append(rec)
        form = chk.get("form", "per-method")
        if form != "per-method" or chk.get("across_dt"):
            # A comparison check (docs/case-keys.md): ratio A/B or spread max/min of OUR values
            # at each step size, or the log-log slope of those values against dt.
            val = comparison_value(chk, case, ours_metrics)
            if isinstance(val, str):
                rec.update(verdict="not reproduced", reason=val)
                continue
            op, exp = chk.get("op"), num(chk.get("expected"))
            v = abs(val) if chk.get("abs") else val
            verdict = {"le": v <= exp, "ge": v >= exp, "lt": v < exp, "gt": v > exp,
                       "near": abs(v - exp) <= num(chk.get("tolerance", 0.0))}.get(op)
            # our inputs agree with the report's to the run tolerances (<= 1e-6 relative), so a
            # threshold within 1e-4 relative of our combined value is undecidable from here
            tie = op in ("le", "ge", "lt", "gt") and abs(v - exp) <= 1e-4 * max(abs(v), abs(exp))
            rec["comparisons"].append(comp("verdict", bool(verdict), bool(chk.get("passed")),
                                           bool(verdict) == bool(chk.get("passed")) or tie,
                                           "equal (undecidable within 1e-4 of the threshold)",
                                           note="our value %.6g" % v))
            rec["verdict"] = "agree" if rec["comparisons"][0]["agree"] else "disagree"
            continue
        mm = ours_metrics.get((method, None if dt is None else float(dt)))
        if mm is None and dt is None:
            mm = next((v for (m, d), v in ours_metrics.items() if m == method and metric in v), None)
        val = None if mm is None else mm.get(metric)
        if val is None:
            rec.update(verdict="not reproduced", reason="metric %s not recomputed" % metric)
            continue
        if isinstance(val, Undef):
            # a check on an undefined metric fails, whichever way it points (docs/conventions.md)
            rec["comparisons"].append(comp("verdict", False, bool(chk.get("passed")), not chk.get("passed"),
                                           "equal (a check on an undefined metric fails)",
                                           note="our value %r" % val))
            rec["verdict"] = "agree" if rec["comparisons"][0]["agree"] else "disagree"
            continue
        op, exp = chk.get("op"), num(chk.get("expected"))
        v = abs(val) if chk.get("abs") else val
        verdict = {"le": v <= exp, "ge": v >= exp, "lt": v < exp, "gt": v > exp,
                   "near": abs(v - exp) <= num(chk.get("tolerance", 0.0))}.get(op)
        if verdict is None:
            rec.update(verdict="not reproduced", reason="unknown op %s" % op)
            continue
        band = (ours_unc.get((method, None if dt is None else float(dt))) or {}).get(metric, 0.0)
        tie = op in ("le", "ge", "lt", "gt") and abs(v - exp) <= band
        rec["comparisons"].append(comp("verdict", bool(verdict), bool(chk.get("passed")),
                                       bool(verdict) == bool(chk.get("passed")) or tie,
                                       "equal (undecidable when the threshold lies in our round-off band)",
                                       note="our value %.6g, band %.2g" % (v, band)))
        rec["verdict"] = "agree" if rec["comparisons"][0]["agree"] else "disagree"
    # runs with metrics we could not recompute are "not reproduced" (partially)
    for r in runs_out:
        if r.get("verdict") == "agree" and r.get("not_reproduced"):
            r["verdict"] = "not reproduced"
            r["reason"] = "metrics not recomputed: " + ", ".join(r["not_reproduced"])
    return dict(runs=runs_out, orders=orders_out, checks=checks_out, case=cid,
                seconds=time.perf_counter() - t_case, cpu_seconds=time.process_time() - c_case,
                problem=case["problem"]["id"])


def _worker(case):
    try:
        with np.errstate(all="ignore"):     # diverged runs: inf/nan are compared as such
            return check_case(case)
    except BadInput as exc:
        return dict(bad_input=str(exc))


# ---------------------------------------------------------------------------------------
def finite_json(x):
    if isinstance(x, dict):
        return {k: finite_json(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [finite_json(v) for v in x]
    if isinstance(x, (float, np.floating)):
        return float(x) if math.isfinite(x) else None
    if isinstance(x, np.bool_):
        return bool(x)
    if isinstance(x, np.integer):
        return int(x)
    return x


def fmt(x):
    if isinstance(x, float):
        return "%.6g" % x
    if isinstance(x, list):
        return "[" + ", ".join(fmt(v) for v in x) + "]"
    return str(x)


def label(rec):
    s = "%s / %s" % (rec["case"], rec.get("method"))
    if rec.get("check"):
        s += " / check '%s'" % rec["check"]
    if rec.get("dt") is not None:
        s += " / dt=%g" % rec["dt"]
    return s


def count(recs):
    return {v: sum(r["verdict"] == v for r in recs) for v in ("agree", "disagree", "not reproduced")}


def write_markdown(path, result):
    s = result["summary"]
    L = ["# dampsym independent cross-check", "", "Report: `%s`  " % result["report"],
         "Time: %.2f s wall (every run integrated in full, no subsampling)" % result["elapsed_seconds"], "",
         "| | agree | disagree | not reproduced |", "|---|---|---|---|"]
    for k in ("runs", "orders", "checks"):
        L.append("| %s | %d | %d | %d |" % (k, s[k]["agree"], s[k]["disagree"], s[k]["not reproduced"]))
    L += ["", "## Time per case (one worker process each; CPU seconds do not depend on the machine's load)",
          "", "| case | problem | wall s | CPU s |", "|---|---|---|---|"]
    for c, p, t, u in result["timing"]:
        L.append("| %s | %s | %.2f | %.2f |" % (c, p, t, u))
    per = {}
    for c, p, t, u in result["timing"]:
        per[p] = per.get(p, 0.0) + u
    L += ["", "Per problem (CPU s): " + ", ".join("%s %.1f" % kv for kv in sorted(per.items(), key=lambda x: -x[1]))]
    allr = result["runs"] + result["orders"] + result["checks"]
    bad = [r for r in allr if r["verdict"] == "disagree"]
    if bad:
        L += ["", "## Disagreements", ""]
        for r in bad:
            for c in r["comparisons"]:
                if not c["agree"]:
                    L.append("- **%s**: %s ours %s, theirs %s (tolerance %s)" % (
                        label(r), c["quantity"], fmt(c["ours"]), fmt(c["theirs"]), c["tolerance"]))
    nr = [r for r in allr if r["verdict"] == "not reproduced"]
    if nr:
        L += ["", "## Not reproduced", ""] + ["- %s: %s" % (label(r), r.get("reason")) for r in nr]
    L += ["", "## Per comparison", "", "| item | verdict | quantity | ours | theirs | rel. diff | tolerance |",
          "|---|---|---|---|---|---|---|"]
    for r in allr:
        for c in r["comparisons"]:
            rd = c.get("rel_diff")
            L.append("| %s | %s | %s | %s | %s | %s | %s |" % (
                label(r), "agree" if c["agree"] else "**disagree**", c["quantity"],
                fmt(c["ours"]) if not isinstance(c["ours"], list) else "(vector)",
                fmt(c["theirs"]) if not isinstance(c["theirs"], list) else "(vector)",
                "%.2g" % rd if rd is not None else "", c["tolerance"]))
    with open(path, "w") as fh:
        fh.write("\n".join(L) + "\n")



def comparison_value(chk, case, ours_metrics):
    """OUR value of a ratio / spread / across-dt check, or a string saying why there is none."""
    metric = chk.get("metric")
    members = chk.get("methods") or [chk.get("method")]
    form = chk.get("form", "per-method")
    dts = [float(d) for d in (case.get("dt_ladder") or [])]
    if chk.get("dt") is not None:
        dts = [float(chk["dt"])]
    hs, values = [], []
    for d in dts:
        xs = []
        for m in members:
            v = (ours_metrics.get((m, d)) or {}).get(metric)
            if v is None or isinstance(v, Undef):
                return "metric %s not recomputed for %s at dt=%g" % (metric, m, d)
            xs.append(float(v))
        if form == "ratio":
            x = xs[0] / xs[1]
        elif form == "spread":
            x = max(xs) / min(xs)
        else:
            x = xs[0]
        hs.append(d)
        values.append(x)
    if not values:
        return "no step size to compare"
    if chk.get("across_dt"):
        if any(not (x > 0.0) or not math.isfinite(x) for x in values):
            return "log-log slope of non-positive values"
        lx = [math.log(h) for h in hs]
        ly = [math.log(x) for x in values]
        n = len(lx)
        mx, my = sum(lx) / n, sum(ly) / n
        sxx = sum((a - mx) ** 2 for a in lx)
        return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sxx
    return values[0]

def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("report")
    ap.add_argument("--out")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--strict", action="store_true",
                    help="exit 1 also when anything is not reproduced")
    args = ap.parse_args(argv)
    t_start = time.perf_counter()
    try:
        try:
            with open(args.report) as fh:
                report = json.load(fh)
        except (OSError, ValueError) as exc:
            raise BadInput("cannot read %s: %s" % (args.report, exc))
        # schema_version 2 moved the clock values out of the cases; the fields read here are
        # the same in 1 and 2.
        if not isinstance(report, dict) or report.get("schema_version") not in (1, 2) \
                or not isinstance(report.get("cases"), list):
            raise BadInput("%s is not a schema_version 1 or 2 dampsym report" % args.report)
        cases = report["cases"]
        for c in cases:
            if not isinstance(c, dict) or "id" not in c or "runs" not in c or "problem" not in c:
                raise BadInput("%s: a case lacks id/problem/runs" % args.report)
        # longest cases first (planned steps x dimension) so the pool stays busy
        cost = lambda c: -sum(int(r.get("steps_planned", r.get("steps", 0)) or 0) for r in c["runs"])
        order = sorted(range(len(cases)), key=lambda i: cost(cases[i]))
        # the 10^7-step runs allocate many 80 MB temporaries: keep freed memory in the heap
        # (glibc mallopt M_MMAP_MAX = 0, M_TRIM_THRESHOLD large) instead of returning it to the
        # kernel and page-faulting it back (a third of that case's time); inherited by the workers
        try:
            import ctypes
            libc = ctypes.CDLL("libc.so.6")
            libc.mallopt(-4, 0)
            libc.mallopt(-1, 1 << 40)
        except (OSError, AttributeError):
            pass
        # compile verify/xjit.py's loops once here (or load them from numba's cache); the
        # forked workers inherit them
        warm_s = xjit.warm()
        if args.jobs > 1:
            with Pool(args.jobs) as pool:
                res = pool.map(_worker, [cases[i] for i in order], chunksize=1)
        else:
            res = [_worker(cases[i]) for i in order]
        bad = [r for r in res if "bad_input" in r]
        if bad:
            raise BadInput(bad[0]["bad_input"])
        res = [r for _, r in sorted(zip(order, res))]
    except BadInput as exc:
        print("crosscheck: bad input: %s" % exc, file=sys.stderr)
        return 2
    runs = [x for r in res for x in r["runs"]]
    orders = [x for r in res for x in r["orders"]]
    checks = [x for r in res for x in r["checks"]]
    elapsed = time.perf_counter() - t_start
    result = dict(tool="verify/crosscheck.py", report=os.path.abspath(args.report), elapsed_seconds=elapsed,
                  summary=dict(runs=count(runs), orders=count(orders), checks=count(checks)),
                  timing=[(r["case"], r.get("problem", "?"), r["seconds"], r["cpu_seconds"]) for r in res],
                  cpu_seconds=sum(r["cpu_seconds"] for r in res), jit_warmup_seconds=warm_s,
                  coefficient_sources=xm.COEFFICIENT_SOURCES,
                  runs=runs, orders=orders, checks=checks)
    out = args.out or os.path.dirname(os.path.abspath(args.report))
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "crosscheck.json"), "w") as fh:
        json.dump(finite_json(result), fh, indent=1)
    write_markdown(os.path.join(out, "crosscheck.md"), result)
    for r in runs + orders + checks:
        if r["verdict"] == "disagree":
            print("DISAGREE %s: %s" % (label(r), "; ".join(
                "%s ours %s theirs %s (tol %s)" % (c["quantity"], fmt(c["ours"]) if not isinstance(c["ours"], list) else "(vector)",
                                                   fmt(c["theirs"]) if not isinstance(c["theirs"], list) else "(vector)",
                                                   c["tolerance"])
                for c in r["comparisons"] if not c["agree"])))
    s = result["summary"]
    print("crosscheck: runs %d agree, %d disagree, %d not reproduced; order fits %d/%d/%d; checks %d/%d/%d" % (
        s["runs"]["agree"], s["runs"]["disagree"], s["runs"]["not reproduced"],
        s["orders"]["agree"], s["orders"]["disagree"], s["orders"]["not reproduced"],
        s["checks"]["agree"], s["checks"]["disagree"], s["checks"]["not reproduced"]))
    print("crosscheck: wrote %s/crosscheck.{json,md} in %.2f s wall, %.1f s CPU in the workers"
          " (compiled loops: %s, %.2f s to compile or load them)"
          % (out, elapsed, result["cpu_seconds"], "numba" if xjit.HAVE_NUMBA else "off", warm_s))
    if args.strict and any(s[k]["not reproduced"] for k in s):
        print("crosscheck: --strict: %d item(s) not reproduced (reports/crosscheck.md lists them)"
              % sum(s[k]["not reproduced"] for k in s))
        return 1
    return 1 if any(s[k]["disagree"] for k in s) else 0


if __name__ == "__main__":
    sys.exit(main())
