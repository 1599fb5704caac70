"""Newton iteration counts of the implicit methods, recomputed independently (cross-check).

How many Newton iterations a step takes is not a property of the method: it depends on the
Newton variant (full Newton, or the Jacobian frozen at the step's start), on the predictor and on
the convergence test, and near round-off on the floating-point path (the last update is a few
ulps, above or below the test by chance).  docs/ states none of these for dampsym, so the
cross-check does not pretend to reproduce one exact count.  It computes the counts of a stated
FAMILY of correct solvers on every step of its own trajectory, and a reported count agrees when
it lies inside the family's range:

  - the stage equations Z_i = Phi_i z_n + h sum_j A_ij G(t_n + c_j h, Z_j) of the method as
    xmethods defines them (coefficients from xmethods: Gauss tableaux from Legendre roots, B (2.5)
    factors, B (2.13)), predictor Z_i = Phi_i z_n (the state carried by the stage's own factor);
  - variants: full Newton (stage Jacobian at every iterate) and simplified Newton (Jacobian at
    the predictor, frozen for the step);
  - test: stop after the first iteration whose update satisfies |dZ|_inf <= tau |Z|_inf, from
    the loosest test tau = 1e-8 ~ sqrt(eps) (after which one more quadratically convergent
    iteration changes nothing above round-off) to the tightest, the cross-check's own round-off
    test (xmethods.settled: update <= 2 eps, or from the third iteration an update <= 1e-11 that
    stopped decreasing).  Counts grow as the test
    tightens and simplified Newton never takes fewer iterations than full Newton, so the range
    is [full Newton at tau = 1e-8, the larger of both variants under the round-off test].

The count reported as "ours" is full Newton at tau = 1e-12.  Evaluations: one G per stage per
iteration (rhs in [s lo, s (hi + 1)]: with or without a final evaluation of the stage slopes);
Jacobians per step in [s (one per stage, frozen), s hi (one per stage per iteration)].
All steps of the run are solved at once (numpy batch over steps), never a subsample.
"""
from typing import Any, Dict, List
import math

import numpy as np

from . import xcache
from . import xmethods as xm

MAX_IT = 40
EPS = np.finfo(float).eps


def _coef(method: str, prob: Any, h: Any) -> Any:
    if method in xm.FILE_RK:
        return xm.file_coef(method, prob, h)
    if method in xm.FILE_ERK:
        return xm.file_erk_coef(method, prob, h)
    if method == "implicit-euler":
        return prob.f, xm.plain_coef([[1.0]], [1.0], [1.0])
    if method in ("implicit-midpoint", "gauss1", "gauss2", "gauss3"):
        A, b, c = xm.GAUSS[1 if method == "implicit-midpoint" else int(method[-1])]
        return prob.f, xm.plain_coef(A, b, c)
    if method in ("cimp", "glifrk1", "glifrk2", "glifrk3"):
        A, b, c = xm.GAUSS[1 if method == "cimp" else int(method[-1])]
        return prob.N, xm.ifrk_coef(prob, A, b, c, h)
    if method == "etdrk2":
        def coef(t: Any) -> Any:
            x = xm.dGamma(prob, t, h)
            return (np.array([math.exp(-0.5 * x)]), np.array([[xm._sinhc(x)]]),
                    np.array([xm._phi1(x)]), math.exp(-x), np.array([0.5]))
        return prob.N, coef
    return None, None


SUPPORTED = {"glm4", "implicit-euler", "implicit-midpoint", "gauss1", "gauss2", "gauss3", "cimp", "glifrk1",
             "glifrk2", "glifrk3", "etdrk2"}


def supported(method: str) -> bool:
    return method in SUPPORTED


def _jac_batch(G: Any, tt: Any, Z: Any) -> Any:
    """Stage Jacobians dG/dz at (tt[n], Z[n]) for a batch, by the complex step: (N, d, d)."""
    N, d = Z.shape
    J = np.empty((N, d, d))
    for j in range(d):
        Zc = Z.astype(complex)
        Zc[:, j] += 1e-30j
        J[:, :, j] = np.imag(G(tt, Zc)) / 1e-30
    return J


def iteration_updates(method: str, prob: Any, h: Any, t0: Any, traj: Any, full: bool = True) -> Any:
    """For every step n (from our own z_n), the relative update |dZ|/|Z| of Newton iterations
    1..MAX_IT: array (MAX_IT, steps)."""
    G, coef = _coef(method, prob, h)
    z = np.asarray(traj[:-1], float)
    N, d = z.shape
    t = t0 + h * np.arange(N)
    if getattr(prob, "t_dependent_gamma", False):
        co = [coef(tk) for tk in t]
        Phi = np.stack([c_[0] for c_ in co])                 # (N, s)
        A = np.stack([c_[1] for c_ in co])                   # (N, s, s)
        c = co[0][4]
    else:
        Phi0, A0, _, _, c = coef(t0)
        Phi = np.broadcast_to(Phi0, (N, len(c)))
        A = np.broadcast_to(A0, (N, len(c), len(c)))
    s = len(c)
    Zp = Phi[:, :, None] * z[:, None, :]
    tt = t[:, None] + c[None, :] * h                          # (N, s)
    return _system_updates(G, A, Zp, tt, h, full), s


def _system_updates(G: Any, A: Any, Zp: Any, tt: Any, h: Any, full: bool) -> Any:
    """Newton on all stages Z = Zp + h (A (x) I) G(tt, Z) for a batch of steps (Zp (N, s, d),
    A (N, s, s), tt (N, s)) from the predictor Zp: the relative updates (MAX_IT, N)."""
    N, s, d = Zp.shape
    Z = Zp.copy()
    eye = np.eye(s * d)
    U = np.empty((MAX_IT, N))
    Minv = None
    for it in range(MAX_IT):
        K = np.stack([G(tt[:, i:i + 1], Z[:, i, :]) for i in range(s)], axis=1)
        R = Z - Zp - h * np.einsum("nij,njd->nid", A, K)
        if full or Minv is None:
            Jb = np.zeros((N, s * d, s * d))
            for i in range(s):
                Ji = _jac_batch(G, tt[:, i:i + 1], Z[:, i, :])
                for k in range(s):
                    Jb[:, k * d:(k + 1) * d, i * d:(i + 1) * d] = -h * A[:, k, i, None, None] * Ji
            Minv = np.linalg.inv(Jb + eye)
        dZ = np.einsum("nab,nb->na", Minv, R.reshape(N, s * d)).reshape(N, s, d)
        Z = Z - dZ
        with np.errstate(invalid="ignore", divide="ignore"):
            U[it] = np.max(np.abs(dZ), axis=(1, 2)) / np.maximum(np.max(np.abs(Z), axis=(1, 2)), 1e-300)
        if _all_done(U, it):
            break
    return U


def _all_done(U: Any, it: Any) -> bool:
    """Every step has met the round-off test by iteration it (0-based): later rows are set to
    0 (no further update counts), which changes no count of the family."""
    if it < 2:
        return False
    stop = np.zeros(U.shape[1], bool)
    for k in range(it + 1):
        stop |= _settled(U, k)
    if stop.all() and np.all(np.min(U[:it + 1], axis=0) <= 1e-12):
        U[it + 1:] = 0.0
        return True
    return False


def _count(U: Any, tau: Any) -> Any:
    ok = U <= tau
    cnt = np.argmax(ok, axis=0) + 1
    cnt[~ok.any(axis=0)] = MAX_IT
    return cnt


def _settled(U: Any, k: int) -> Any:
    """xmethods.settled for iteration k + 1 of every step of a batch (U: relative updates)."""
    stop = U[k] <= 2 * EPS
    if k >= 2:
        stop |= (U[k] >= U[k - 1]) & (U[k] <= 1e-11)
    return stop


def _count_roundoff(U: Any) -> Any:
    """The tight end: xmethods' own round-off test (settled): stop when the update is <= 2 eps,
    or from the third iteration on when it stopped decreasing below 1e-11."""
    n = U.shape[1]
    cnt = np.full(n, MAX_IT)
    done = np.zeros(n, bool)
    for it in range(MAX_IT):
        stop = _settled(U, it)
        new = stop & ~done
        cnt[new] = it + 1
        done |= stop
    return cnt


@xcache.memo
def cost_metrics(method: str, prob: Any, h: Any, t0: Any, traj: Any) -> Any:
    """{metric: (ours, lo, hi)} for cost.* and run.* counts (see the module docstring)."""
    Uf, s = iteration_updates(method, prob, h, t0, traj, full=True)
    Us, _ = iteration_updates(method, prob, h, t0, traj, full=False)
    n = Uf.shape[1]
    mid = _count(Uf, 1e-12)
    lo = _count(Uf, 1e-8)
    hi = np.maximum(_count_roundoff(Us), _count_roundoff(Uf))
    out = {
        "cost.newton_iters_per_step": (mid.mean(), lo.mean(), hi.mean()),
        "cost.max_newton_iters": (int(mid.max()), int(lo.max()), int(hi.max())),
        "cost.rhs_evals_per_step": (s * mid.mean(), s * lo.mean(), s * (hi.mean() + 1)),
        "cost.jac_evals_per_step": (s * mid.mean(), float(s), s * hi.mean()),
        "run.newton_iters": (int(mid.sum()), int(lo.sum()), int(hi.sum())),
        "run.rhs_evals": (int(s * mid.sum()), int(s * lo.sum()), int(s * (hi.sum() + n))),
        "run.jac_evals": (int(s * mid.sum()), s * n, int(s * hi.sum())),
    }
    return out


def linear_cost_metrics(method: str, s: Any, n: Any) -> Any:
    """A linear problem (the oscillator): the stage equations are linear, so the first Newton
    iterate solves them (to round-off) and the second update is round-off: 2 iterations per step
    with any tau in [1e-15, 1e-8] when the first update is not itself below tau (z_n != 0) —
    an argument, not a measurement, used for the 10^6+ step runs that take the linear path."""
    it = 2
    return {
        "cost.newton_iters_per_step": (float(it), float(it), float(it)),
        "cost.max_newton_iters": (it, it, it),
        "cost.rhs_evals_per_step": (float(s * it), float(s * it), float(s * (it + 1))),
        "cost.jac_evals_per_step": (float(s * it), float(s), float(s * it)),
        "run.newton_iters": (it * n, it * n, it * n),
        "run.rhs_evals": (s * it * n, s * it * n, s * (it + 1) * n),
        "run.jac_evals": (s * it * n, s * n, s * it * n),
    }


def _stage_updates(f: Any, t: Any, base: Any, ha: Any, full: bool) -> Any:
    """Newton on y = base + ha f(t, y) for a batch of steps (N, d) from the predictor y = base:
    (relative updates (MAX_IT, N), converged y, f(y))."""
    N, d = base.shape
    y = base.copy()
    U = np.empty((MAX_IT, N))
    Minv = None
    eye = np.eye(d)
    for it in range(MAX_IT):
        R = y - base - ha * f(t, y)
        if full or Minv is None:
            Minv = np.linalg.inv(eye - ha * _jac_batch(f, t, y))
        dy = np.einsum("nab,nb->na", Minv, R)
        y = y - dy
        with np.errstate(invalid="ignore", divide="ignore"):
            U[it] = np.max(np.abs(dy), axis=1) / np.maximum(np.max(np.abs(y), axis=1), 1e-300)
        if _all_done(U, it):
            break
    return U, y, f(t, y)


def _glm_stages(prob: Any, h: Any, t: Any, Yp: Any, A: Any, c: Any) -> Any:
    """A general linear method's stage solves on a batch of steps (Yp = U y^[n], (N, s, d)), by
    both variants of the family: {full: per-step iterations (round-off test, tau 1e-12, tau
    1e-8)}, with the step's evaluations and Jacobians as (lo, hi) functions of those counts.
    Lower-triangular A: the stages one after the other, stage i's equation from the converged
    slopes of the earlier ones; an explicit stage is one evaluation.  Full A: all stages at once
    (s evaluations per iteration, s Jacobians per matrix).  Evaluations: (ours and the lower end,
    the upper end) as functions of the counts; Jacobians: (full Newton's, one per matrix)."""
    N, s, d = Yp.shape
    res: Dict[bool, Any] = {}
    if not xm.lower_triangular(A):
        tt = t + c[None, :] * h
        for full in (True, False):
            U = _system_updates(prob.f, np.broadcast_to(A, (N, s, s)), Yp, tt, h, full)
            res[full] = (_count_roundoff(U), _count(U, 1e-12), _count(U, 1e-8))
        return res, (lambda it: s * it, lambda it: s * (it + 1)), (lambda it: s * it, s)
    implicit = [i for i in range(s) if A[i, i] != 0.0]
    explicit = s - len(implicit)
    for full in (True, False):
        K: List[Any] = []
        tot = [np.zeros(N, int) for _ in range(3)]
        for i in range(s):
            base = Yp[:, i] + h * sum((A[i, j] * K[j] for j in range(i)), np.zeros((N, d)))
            if A[i, i] == 0.0:
                K.append(prob.f(t + c[i] * h, base))
                continue
            Ui, _, Ki = _stage_updates(prob.f, t + c[i] * h, base, h * A[i, i], full)
            K.append(Ki)
            for k, cnt in enumerate((_count_roundoff(Ui), _count(Ui, 1e-12), _count(Ui, 1e-8))):
                tot[k] = tot[k] + cnt
        res[full] = tuple(tot)
    m = len(implicit)
    return res, (lambda it: it + explicit, lambda it: it + m + explicit), (lambda it: it, m)


@xcache.memo
def glm_cost_metrics(prob: Any, h: Any, t0: Any, Y: Any, coefs: Any) -> Any:
    """A general linear method (BS; xmethods.GLM, glm4 or a method file's): its stages solved by
    the family of Newton solvers above on every step of OUR y^[n] (Y: (steps + 1, r, d)), as
    _glm_stages.  The starting method's stages (from y_0, predictor U0 y_0) may be counted in the
    first step or not: the upper end counts them."""
    Yn = np.asarray(Y[:-1], float)
    N = Yn.shape[0]
    t = (t0 + h * np.arange(N))[:, None]
    k = coefs
    res, rhs, jac = _glm_stages(prob, h, t, np.einsum("ij,njd->nid", k["U"], Yn), k["A"], k["c"])
    hi = np.maximum(res[True][0], res[False][0])
    mid, lo = res[True][1], res[True][2]
    rhs_hi, jac_hi = rhs[1](hi), jac[0](hi)
    if len(k["c0"]):
        Y0 = k["U0"][None, :, None] * Yn[:1, 0][:, None, :]
        sres, srhs, sjac = _glm_stages(prob, h, t[:1], Y0, k["A0"], k["c0"])
        st = np.maximum(sres[True][0], sres[False][0])
        hi, rhs_hi, jac_hi = hi.copy(), rhs_hi.copy(), jac_hi.copy()
        hi[0] += st[0]
        rhs_hi[0] += srhs[0](st)[0]
        jac_hi[0] += sjac[0](st)[0]
    return {
        "cost.newton_iters_per_step": (mid.mean(), lo.mean(), hi.mean()),
        "cost.max_newton_iters": (int(mid.max()), int(lo.max()), int(hi.max())),
        "cost.rhs_evals_per_step": (rhs[0](mid).mean(), rhs[0](lo).mean(), rhs_hi.mean()),
        "cost.jac_evals_per_step": (jac[0](mid).mean(), float(jac[1]), jac_hi.mean()),
        "run.newton_iters": (int(mid.sum()), int(lo.sum()), int(hi.sum())),
        "run.rhs_evals": (int(rhs[0](mid).sum()), int(rhs[0](lo).sum()), int(rhs_hi.sum())),
        "run.jac_evals": (int(jac[0](mid).sum()), jac[1] * N, int(jac_hi.sum())),
    }
