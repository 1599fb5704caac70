"""Step loops of the independent cross-check (numpy; no dampsym code)."""
from typing import Any
import math

import numpy as np

from . import refmath
from . import xcache
from . import xjit
from . import xscalar
from . import xmethods as xm


@xcache.memo
def integrate(method: str, prob: Any, h: Any, nsteps: int, t0: Any, record: bool = False, blowup: Any = None) -> Any:
    """nsteps steps of size h from (t0, z0), time t0 + n h.  Returns dict(status, steps, z,
    traj (every state incl. z0, when record), newton (total iterations), newton_max, message).
    status: ok | diverged (non-finite, or |z| > blowup |z0| when blowup is given) |
    solve-failed | not-applicable."""
    z = np.array(prob.z0, float)
    limit = math.inf if blowup is None else blowup * max(1.0, float(np.max(np.abs(z))))
    out = dict(status="ok", steps=0, z=z, traj=None, newton=0, newton_max=0, message="")
    try:
        if method in xm.MULTIVALUE:
            glm = xm.GLM(prob, h, xm.FILE_GLM.get(method))
            stepf = None
        else:
            stepf = xm.make_stepper(method, prob, h)
    except xm.NotApplicable as exc:
        out.update(status="not-applicable", message=str(exc))
        return out
    # linear fast path: runs whose trajectory is not needed, and the 10^6+ step stress runs
    # (a fixed rounded M biases round-off-level conservation metrics, so recorded runs step)
    if linear_ok(method, prob) and (not record or nsteps >= 1_000_000):
        return integrate_linear(method, prob, h, nsteps, t0, record, limit, out)
    # compiled loops (python3-numba) where available: verify/xjit.py, same formulas
    compiled = xjit.integrate(method, prob, h, nsteps, t0, record, limit, out)
    if compiled is not None:
        return compiled
    fast = scalar_stepper(method, prob, h)
    if fast is not None:
        compiled = xjit.integrate_scalar(method, prob, h, nsteps, record, limit, out)
        if compiled is not None:
            return compiled
        return integrate_scalar(fast, prob, nsteps, record, limit, out)
    small = xscalar.make(method, prob, h)
    if small is not None:
        return integrate_small(small, prob, nsteps, t0, h, record, limit, out)
    traj: Any = np.empty((nsteps + 1, prob.d)) if record else None
    if record:
        traj[0] = z
    n = 0
    try:
        if stepf is None:
            y = glm.start(t0, z)
            glm_y = [np.array(y)]
        for n in range(1, nsteps + 1):
            t = t0 + (n - 1) * h
            if stepf is None:
                y, it = glm.step(t, y)
                z = y[0]
                if record:
                    glm_y.append(np.array(y))
            else:
                z, it = stepf(t, z)
            out["newton"] += it
            out["newton_max"] = max(out["newton_max"], it)
            if record:
                traj[n] = z
            if not np.all(np.abs(z) < limit):
                out.update(status="diverged", message="diverged at step %d" % n)
                break
    except xm.SolveFailed as exc:
        out.update(status="solve-failed", message="%s at step %d" % (exc, n))
    except xm.NotApplicable as exc:
        out.update(status="not-applicable", message=str(exc))
        n = 0
    except (OverflowError, FloatingPointError):
        out.update(status="diverged", message="overflow at step %d" % n)
    out.update(steps=n, z=z, traj=traj[:n + 1] if record else None)
    if record and stepf is None and out["status"] == "ok":
        out["glm_y"] = np.array(glm_y)          # the GLM's full state y^[n] (Newton counts)
    return out


def step_jacobian(method: str, prob: Any, h: Any, t: Any, z: Any) -> Any:
    """Exact Jacobian of one step of the method at (t, z) by the complex step (all d directions
    in one batched step; implicit stages converged in real and imaginary parts).  An implicit
    RK-family step polishes its stages by two full Newton updates
    (xmethods.complex_step_polished), so that the derivatives are those of the converged stages
    even where the simplified iteration contracts slowly (a large step)."""
    d = prob.d
    Z = np.asarray(z, float)[None, :] + 1e-30j * np.eye(d)
    stepf = xm.make_stepper(method, prob, h)
    Z1, _ = getattr(stepf, "complex_step", stepf)(t, Z)
    return (np.imag(Z1) / 1e-30).T


def linear_ok(method: str, prob: Any) -> Any:
    """The oscillator with constant gamma is linear and autonomous: every method's step is
    z -> M z with M our own one-step matrix (complex step of our own step map)."""
    return type(prob).__name__ == "Oscillator" and method not in xm.MULTIVALUE


def integrate_linear(method: str, prob: Any, h: Any, nsteps: int, t0: Any, record: bool, limit: Any, out: Any) -> Any:
    """z_n = M^n z0 with M our own one-step matrix (complex step of our own step map), in
    80-bit long double: block starts z_{kB} by the chain M^B (formed by B products), the states
    inside all blocks at once by B vectorised applications of M.  Same mathematics as stepping;
    M is the rounded double one-step matrix, so the final state may drift by n eps relative
    from a stepping computation (the comparison's floor for these runs)."""
    try:
        M = step_jacobian(method, prob, h, t0, np.zeros(prob.d))
    except xm.NotApplicable as exc:
        out.update(status="not-applicable", message=str(exc))
        return out
    ld = np.longdouble
    Ml = M.astype(ld)
    B = 1024 if nsteps >= 100_000 else 64
    K = -(-nsteps // B)                      # number of blocks
    PB = np.eye(prob.d, dtype=ld)
    for _ in range(B):
        PB = Ml @ PB
    S = np.empty((K, prob.d), dtype=ld)
    S[0] = np.asarray(prob.z0, dtype=ld)
    full = np.empty((K * B + 1, prob.d))     # z_{kB + j} (rounded to double) at row kB + j
    with np.errstate(over="ignore", invalid="ignore"):
        for k in range(1, K):
            S[k] = PB @ S[k - 1]
        Zj = S                               # z_{kB + j} for all k, j = 0 .. B
        for j in range(B):
            full[j:K * B:B] = Zj
            Zj = Zj @ Ml.T
        full[K * B] = Zj[-1]
    full = full[:nsteps + 1]
    bad = ~np.all(np.abs(full) < limit, axis=-1)
    n = nsteps
    if bad.any():
        n = int(np.argmax(bad))
        out.update(status="diverged", message="diverged at step %d" % n)
    out.update(steps=n, z=full[n], traj=full[:n + 1] if record else None, linear_path=True)
    return out


def scalar_stepper(method: str, prob: Any, h: Any) -> Any:
    """One-degree-of-freedom oscillator and pendulum with constant gamma: the second, scalar
    implementation of euler/heun/rk3/rk4/csv1/csv2/cimp in verify/refmath.py (plain floats,
    ~10x faster than numpy on 2-vectors; tests/ compare both implementations)."""
    kind = type(prob).__name__
    if kind not in ("Oscillator", "Pendulum") or method not in refmath.METHODS:
        return None
    rp: Any
    if kind == "Oscillator":
        rp = refmath.Oscillator(prob.w, prob.g, prob.z0[0], prob.z0[1])
    else:
        rp = refmath.Pendulum(prob.g, prob.z0[0], prob.z0[1])
    try:
        return refmath.make_step(method, rp, h)
    except refmath.NotApplicable:
        return None


def integrate_scalar(step: Any, prob: Any, nsteps: int, record: bool, limit: Any, out: Any) -> Any:
    q, p = float(prob.z0[0]), float(prob.z0[1])
    qs: Any = [q] if record else None
    ps: Any = [p] if record else None
    n = 0
    try:
        for n in range(1, nsteps + 1):
            q, p = step(q, p)
            if record:
                qs.append(q)
                ps.append(p)
            if not abs(q) < limit or not abs(p) < limit:
                out.update(status="diverged", message="diverged at step %d" % n)
                break
    except refmath.SolveFailed as exc:
        out.update(status="solve-failed", message="%s at step %d" % (exc, n))
    except OverflowError:
        out.update(status="diverged", message="overflow at step %d" % n)
    out.update(steps=n, z=np.array([q, p]),
               traj=np.column_stack([qs, ps]) if record else None)
    return out


def integrate_small(stepper: Any, prob: Any, nsteps: int, t0: Any, h: Any, record: bool, limit: Any, out: Any) -> Any:
    z = [float(v) for v in prob.z0]
    traj: Any = [list(z)] if record else None
    glm_y: Any = None
    glm = isinstance(stepper, xscalar.GLMScalar)
    n = 0
    try:
        if glm:
            y = stepper.start(t0, z)
            glm_y = [y] if record else None
        for n in range(1, nsteps + 1):
            t = t0 + (n - 1) * h
            if glm:
                y, it = stepper.step(t, y)
                z = y[0]
                if record:
                    glm_y.append(y)
            else:
                z, it = stepper(t, z)
            out["newton"] += it
            out["newton_max"] = max(out["newton_max"], it)
            if record:
                traj.append(z)
            if not all(abs(v) < limit for v in z):
                out.update(status="diverged", message="diverged at step %d" % n)
                break
    except xm.SolveFailed as exc:
        out.update(status="solve-failed", message="%s at step %d" % (exc, n))
    except OverflowError:
        out.update(status="diverged", message="overflow at step %d" % n)
    out.update(steps=n, z=np.array(z), traj=np.array(traj) if record else None)
    if glm and record and out["status"] == "ok":
        out["glm_y"] = np.array(glm_y)          # the GLM's full state y^[n] (Newton counts)
    return out
