"""Compiled (numba) step loops of the independent cross-check for the long scalar runs that
numpy cannot vectorise: Kepler, the rigid body, the driven pendulum, the N-body problems.

The formulas are the cross-check's own (verify/xmethods.py, verify/xscalar.py, from the papers):
the same expressions in the same order of operations, so on Kepler, the rigid body and the driven
pendulum a compiled run reproduces the plain-float run of verify/xscalar.py bit for bit
(xjit_selftest below); on the N-body problems the pair forces are summed in pair order (numpy's
einsum may group them differently: round-off only).  Coefficients come from verify/xmethods.py
(typed rationals, Gauss tableaux from Legendre roots, BS's GLM), never from dampsym.

Without python3-numba (or with XC_NO_NUMBA=1) integrate() returns None and verify/xrun.py uses
its plain-Python loops: same results, only slower.  Compiled code is cached beside this module
(__pycache__) or, where that directory is read-only, in numba's per-user cache directory."""
from typing import Any
import math
import os

import numpy as np

from . import xmethods as xm

try:
    if os.environ.get("XC_NO_NUMBA"):
        raise ImportError("XC_NO_NUMBA set")
    import numba
    HAVE_NUMBA = True
except ImportError:       # the plain-Python loops of xrun.py / xscalar.py are used instead
    HAVE_NUMBA = False

EPS = float(np.finfo(float).eps)

# problem codes of the compiled fields
KEPLER, RIGID, DRIVEN, NBODY_GRAV, NBODY_LJ, DRIVEN_N = 0, 1, 2, 3, 4, 5
# method codes
ERK, SEULER, SEULER_ADJ, VERLET, CSV1, CSV2 = 0, 1, 2, 3, 4, 5

if HAVE_NUMBA:
    def jit(fn: Any) -> Any:
        try:               # cached machine code: __pycache__ here, else numba's user cache dir
            return numba.njit(cache=True, nogil=True)(fn)
        except RuntimeError:       # no writable cache location at all: compile in memory
            return numba.njit(nogil=True)(fn)

    @jit
    def _settled(m: Any, last: Any, it: Any, zero: Any) -> Any:
        """xmethods.settled, compiled (the same test)."""
        return m <= 2 * EPS or zero or (it >= 3 and m >= last and m <= 1e-11)

    @jit
    def _force(code: Any, t: Any, q: Any, P: Any, out: Any) -> None:
        """-grad V(q, t) of the separable problems (xproblems / xscalar formulas)."""
        if code == KEPLER:                       # HLW (2.1)
            x, y = q[0], q[1]
            r2 = x * x + y * y
            r3 = r2 * math.sqrt(r2)
            out[0] = -x / r3
            out[1] = -y / r3
        elif code == DRIVEN:                     # B 3.2.2: -lambda^2 sin q + f sin t
            out[0] = -P[0] * math.sin(q[0]) + P[1] * math.sin(t)
        else:                                    # pair potentials HLW (2.10), (3.2)
            n, dim = int(P[0]), int(P[1])
            c1, sig = P[2], P[3]                 # G (gravity) or 4 eps_LJ; sigma
            for k in range(n * dim):
                out[k] = 0.0
            for i in range(n):
                for j in range(i + 1, n):
                    r2 = 0.0
                    for d in range(dim):
                        dd = q[i * dim + d] - q[j * dim + d]
                        r2 += dd * dd
                    if code == NBODY_GRAV:       # phi'(r)/r = G m_i m_j / r^3
                        w = c1 * (P[4 + i] * P[4 + j]) / (r2 * math.sqrt(r2))
                    else:                        # 4 eps (-12 s^12 r^-14 + 6 s^6 r^-8)
                        s6 = math.pow(sig ** 2 / r2, 3.0)
                        w = c1 * (-12.0 * s6 * s6 + 6.0 * s6) / r2
                    for d in range(dim):
                        wd = w * (q[i * dim + d] - q[j * dim + d])
                        out[i * dim + d] -= wd
                        out[j * dim + d] += wd

    @jit
    def _field(code: Any, t: Any, z: Any, P: Any, m: Any, g: Any, out: Any) -> None:
        """f(t, z): separable problems [p / m, force - 2 gamma p]; the rigid body B (1.7)."""
        d = z.shape[0]
        if code == DRIVEN_N:                     # conformal field N = f + gamma z (xscalar)
            _force(DRIVEN, t, z[:1], P, out[1:])
            out[1] = out[1] - g * z[1]
            out[0] = z[1] + g * z[0]
            return
        if code == RIGID:
            a1, a2, a3, eps = P[0], P[1], P[2], P[3]
            z1, z2, z3 = z[0], z[1], z[2]
            gt = 0.5 * eps * math.cos(2.0 * t)
            out[0] = (z3 * z2 * a3 - z2 * z3 * a2) - gt * z1
            out[1] = (-z3 * z1 * a3 + z1 * z3 * a1) - gt * z2
            out[2] = (z2 * z1 * a2 - z1 * z2 * a1) - gt * z3
            return
        nq = d // 2
        _force(code, t, z[:nq], P, out[nq:])
        for k in range(nq):
            p = z[nq + k]
            out[nq + k] = out[nq + k] - 2.0 * g * p
            out[k] = p / m[k]

    @jit
    def _explicit_step(code: Any, meth: Any, P: Any, m: Any, g: Any, t: Any, h: Any, z: Any, A: Any, b: Any,
                       c: Any, K: Any, zi: Any, fq: Any, fq1: Any) -> None:
        """One step of method `meth` from (t, z), in place (K, zi, fq, fq1: scratch)."""
        d = z.shape[0]
        nq = d // 2
        s = b.shape[0]
        if meth == ERK:                      # xscalar._erk, same order of operations
            for i in range(s):
                for k in range(d):
                    zi[k] = z[k]
                for j in range(i):
                    if A[i, j] != 0.0:
                        hA = h * A[i, j]
                        for k in range(d):
                            zi[k] = zi[k] + hA * K[j, k]
                _field(code, t + c[i] * h, zi, P, m, g, K[i])
            for k in range(d):
                acc = b[0] * K[0, k]
                for i in range(1, s):
                    acc = acc + b[i] * K[i, k]
                z[k] = z[k] + h * acc
        elif meth == SEULER:                 # HLW (1.8), p implicit (linear, closed form)
            _force(code, t, z[:nq], P, fq)
            den = 1 + 2 * g * h
            for k in range(nq):
                p1 = (z[nq + k] + h * fq[k]) / den
                z[nq + k] = p1
                z[k] = z[k] + h * (p1 / m[k])
        elif meth == SEULER_ADJ:
            for k in range(nq):
                z[k] = z[k] + h * (z[nq + k] / m[k])
            _force(code, t + h, z[:nq], P, fq)
            for k in range(nq):
                p = z[nq + k]
                z[nq + k] = p + h * (fq[k] - 2 * g * p)
        elif meth == VERLET:                 # HLW (3.7) with the damping term
            _force(code, t, z[:nq], P, fq)
            den = 1 + g * h
            for k in range(nq):
                z[nq + k] = (z[nq + k] + 0.5 * h * fq[k]) / den
                z[k] = z[k] + h * (z[nq + k] / m[k])
            _force(code, t + h, z[:nq], P, fq)
            for k in range(nq):
                ph = z[nq + k]
                z[nq + k] = ph + 0.5 * h * (fq[k] - 2 * g * ph)
        elif meth == CSV1:                   # F (2.12), constant gamma (xscalar._csv_scalar)
            e1 = math.exp(-2.0 * (g * (0.5 * h)))
            e2 = e1
            _force(code, t, z[:nq], P, fq)
            for k in range(nq):
                ph = e1 * z[nq + k] + 0.5 * h * fq[k]
                z[nq + k] = ph
                z[k] = z[k] + h * ph
            _force(code, t + h, z[:nq], P, fq1)
            for k in range(nq):
                z[nq + k] = e2 * (z[nq + k] + 0.5 * h * fq1[k])
        else:                                # CSV2, F (2.16), constant gamma, x < 2
            x = g * h
            a, bb, e = 1 + 0.5 * x, 1 - 0.5 * x, math.exp(-0.5 * x)
            _force(code, t, z[:nq], P, fq)
            for k in range(nq):
                ph = (e * z[nq + k] + 0.5 * h * fq[k]) / a
                z[nq + k] = ph
                z[k] = e * (a * e * z[k] + h * ph) / bb
            _force(code, t + h, z[:nq], P, fq1)
            for k in range(nq):
                z[nq + k] = e * (bb * z[nq + k] + 0.5 * h * fq1[k])

    @jit
    def _run(code: Any, meth: int, P: Any, m: Any, g: Any, z0: Any, t0: Any, h: Any, nsteps: int, A: Any, b: Any, c: Any, record: bool, limit: Any) -> Any:
        """nsteps steps of method `meth`; returns (steps done, status 0 ok / 1 diverged,
        final state, trajectory (nsteps + 1 rows when record, else 1))."""
        d = z0.shape[0]
        nq = d // 2
        s = b.shape[0]
        z = z0.copy()
        traj = np.empty((nsteps + 1 if record else 1, d))
        traj[0] = z
        K = np.empty((s, d))
        zi = np.empty(d)
        fq = np.empty(max(nq, 1))
        fq1 = np.empty(max(nq, 1))
        n = 0
        status = 0
        for n in range(1, nsteps + 1):
            t = t0 + (n - 1) * h
            _explicit_step(code, meth, P, m, g, t, h, z, A, b, c, K, zi, fq, fq1)
            if record:
                traj[n] = z
            bad = False
            for k in range(d):
                if not abs(z[k]) < limit:
                    bad = True
            if bad:
                status = 1
                break
        if not record:
            traj[0] = z
        return n, status, z, traj

    @jit
    def _glm_solve(code: Any, P: Any, m: Any, t: Any, h: Any, a: Any, base: Any, Mi: Any, y: Any, fy: Any) -> Any:
        """One diagonally implicit GLM stage, Y = base + h a f(t, Y), simplified Newton with the
        given inverse, to round-off (xscalar.GLMScalar._solve, same operations)."""
        d = base.shape[0]
        for k in range(d):
            y[k] = base[k]
        R = np.empty(d)
        dy = np.empty(d)
        last = math.inf
        it = 0
        while True:
            it += 1
            _field(code, t, y, P, m, 0.0, fy)
            for k in range(d):
                R[k] = y[k] - base[k] - h * a * fy[k]
            num = 0.0
            for r in range(d):
                acc = Mi[r, 0] * R[0]
                for q in range(1, d):
                    acc = acc + Mi[r, q] * R[q]
                dy[r] = acc
                if abs(acc) > num:
                    num = abs(acc)
            den = 0.0
            for k in range(d):
                y[k] = y[k] - dy[k]
                if abs(y[k]) > den:
                    den = abs(y[k])
            mm = num / max(den, 1e-300)
            if _settled(mm, last, it, num == 0.0):
                _field(code, t, y, P, m, 0.0, fy)
                return it
            last = mm
            if it > 100 or not math.isfinite(mm):
                return -1

    @jit
    def _glm_chunk(code: Any, P: Any, m: Any, t0: Any, h: Any, n0: Any, nsteps: int, yv: Any, Mi0: Any, Mi1: Any, A: Any, U: Any, B: Any, V: Any, traj: Any, limit: Any) -> Any:
        """Steps n0+1 .. n0+nsteps of BS's GLM with fixed Newton inverses (xscalar.GLMScalar.step);
        returns (last step done, status 0 ok / 1 diverged / 2 solve failed, Newton its, max its)."""
        d = yv.shape[1]
        Y1 = np.empty(d)
        K1 = np.empty(d)
        Y2 = np.empty(d)
        K2 = np.empty(d)
        base = np.empty(d)
        tot, mx = 0, 0
        n = n0
        for n in range(n0 + 1, n0 + nsteps + 1):
            t = t0 + (n - 1) * h
            for k in range(d):
                base[k] = U[0, 0] * yv[0, k] + U[0, 1] * yv[1, k]
            # stage i at t + c_i h, c = A e (as xmethods.GLM; the time-dependent gamma)
            i1 = _glm_solve(code, P, m, t + (A[0, 0] + A[0, 1]) * h, h, A[0, 0], base, Mi0, Y1, K1)
            if i1 < 0:
                return n, 2, tot, mx
            for k in range(d):
                base[k] = (U[1, 0] * yv[0, k] + U[1, 1] * yv[1, k]) + h * A[1, 0] * K1[k]
            i2 = _glm_solve(code, P, m, t + (A[1, 0] + A[1, 1]) * h, h, A[1, 1], base, Mi1, Y2, K2)
            if i2 < 0:
                return n, 2, tot, mx
            for i in range(2):
                for k in range(d):
                    Y2[k] = h * (B[i, 0] * K1[k] + B[i, 1] * K2[k]) + V[i, 0] * yv[0, k] + V[i, 1] * yv[1, k]
                if i == 0:
                    for k in range(d):
                        Y1[k] = Y2[k]
            for k in range(d):
                yv[0, k] = Y1[k]
                yv[1, k] = Y2[k]
            tot += i1 + i2
            if i1 + i2 > mx:
                mx = i1 + i2
            if traj.shape[0] > 1:
                traj[n] = yv
            for k in range(d):
                if not abs(yv[0, k]) < limit:
                    return n, 1, tot, mx
        return n, 0, tot, mx


if HAVE_NUMBA:
    @jit
    def _impl_chunk(code: Any, P: Any, m: Any, g: Any, t0: Any, h: Any, n0: Any, nmax: int, z: Any, Phi: Any, A: Any, b: Any, phi0: Any, c: Any, Mi: Any, traj: Any, limit: Any) -> Any:
        """Steps n0+1 .. of an implicit RK-family method with a fixed simplified-Newton inverse
        (xscalar._implicit, same operations): at most 8 steps, stopping after a slow solve (more
        than 6 iterations), when the caller refreshes the inverse.  Returns (last step done,
        status 0 ok / 1 diverged / 2 solve failed, iterations, max iterations, slow)."""
        d = z.shape[0]
        s = b.shape[0]
        Z = np.empty((s, d))
        K = np.empty((s, d))
        R = np.empty(s * d)
        g0 = np.empty(d)
        tot, mx = 0, 0
        n = n0
        for n in range(n0 + 1, min(n0 + 8, nmax) + 1):
            t = t0 + (n - 1) * h
            _field(code, t, z, P, m, g, g0)
            for i in range(s):
                for k in range(d):
                    Z[i, k] = Phi[i] * z[k] + h * c[i] * g0[k]
            last = math.inf
            it = 0
            while True:
                it += 1
                for j in range(s):
                    _field(code, t + c[j] * h, Z[j], P, m, g, K[j])
                for i in range(s):
                    for k in range(d):
                        acc = A[i, 0] * K[0, k]
                        for j in range(1, s):
                            acc = acc + A[i, j] * K[j, k]
                        R[i * d + k] = Z[i, k] - Phi[i] * z[k] - h * acc
                num = 0.0
                den = 0.0
                for r in range(s * d):
                    acc = Mi[r, 0] * R[0]
                    for q in range(1, s * d):
                        acc = acc + Mi[r, q] * R[q]
                    i, k = r // d, r % d
                    Z[i, k] -= acc
                    if abs(acc) > num:
                        num = abs(acc)
                    if abs(Z[i, k]) > den:
                        den = abs(Z[i, k])
                mm = num / max(den, 1e-300)
                if not math.isfinite(mm):
                    return n, 2, tot, mx, False
                if _settled(mm, last, it, num == 0.0):
                    break
                last = mm
                if it > 100:
                    return n, 2, tot, mx, False
            for j in range(s):
                _field(code, t + c[j] * h, Z[j], P, m, g, K[j])
            for k in range(d):
                acc = b[0] * K[0, k]
                for i in range(1, s):
                    acc = acc + b[i] * K[i, k]
                z[k] = phi0 * z[k] + h * acc
            tot += it
            if it > mx:
                mx = it
            if traj.shape[0] > 1:
                traj[n] = z
            for k in range(d):
                if not abs(z[k]) < limit:
                    return n, 1, tot, mx, it > 6
            if it > 6:
                return n, 0, tot, mx, True
        return n, 0, tot, mx, False


def _integrate_implicit(method: str, prob: Any, code: Any, P: Any, m: Any, g: Any, h: Any, nsteps: int, t0: Any, record: bool, limit: Any, out: Any) -> Any:
    """Gauss / implicit midpoint (plain tableaux) and cimp / glifrk (B (2.5) with constant
    gamma, so constant coefficients) as xscalar._implicit: each Newton inverse, refreshed every 8
    steps and after a slow solve, in Python; the steps in between compiled.  On the N-body
    problems this replaces xmethods.rk_family_step (same initial guess, residual, convergence
    test and refresh rule; sums in another order: round-off only)."""
    A0, b0, c0 = xm.GAUSS[1 if method in ("implicit-midpoint", "cimp") else int(method[-1])]
    if method in ("cimp", "glifrk1", "glifrk2", "glifrk3"):
        if code != DRIVEN or prob.t_dependent_gamma:
            return None
        coef, fcode, F = xm.ifrk_coef(prob, A0, b0, c0, h), DRIVEN_N, prob.N
    else:
        if code not in (KEPLER, DRIVEN, RIGID, NBODY_GRAV, NBODY_LJ):
            return None
        coef, fcode, F = xm.plain_coef(A0, b0, c0), code, prob.f
    Phi, A, b, phi0, c = coef(t0)
    Phi, A, b, c = (np.ascontiguousarray(x, dtype=float) for x in (Phi, A, b, c))
    s, d = len(b), prob.d
    z = np.array(prob.z0, float)
    traj = np.empty((nsteps + 1 if record else 1, d))
    traj[0] = z
    n = 0
    while n < nsteps:
        J = xm.jac_cs(F, t0 + n * h, np.array(z))
        Mi = np.linalg.inv(np.eye(s * d) - h * np.kron(A, J))
        n1, status, its, mx, slow = _impl_chunk(fcode, P, m, g, float(t0), float(h), n, nsteps, z,
                                                Phi, A, b, float(phi0), c, Mi, traj, float(limit))
        out["newton"] += its              # the steps before a failed one count, as in xrun
        out["newton_max"] = max(out["newton_max"], mx)
        if status == 2:    # that step by full Newton (xmethods.full_newton_step), then on
            try:
                z1, it = xm.full_newton_step(F, coef, h, t0 + (n1 - 1) * h, np.array(z))
            except xm.SolveFailed:
                out.update(status="solve-failed", message="Newton did not converge at step %d" % n1)
                n = n1
                break
            z[:] = z1
            out["newton"] += it
            out["newton_max"] = max(out["newton_max"], it)
            if record:
                traj[n1] = z
            status = 0 if np.all(np.abs(z) < limit) else 1
        n = n1
        if status == 1:
            out.update(status="diverged", message="diverged at step %d" % n)
            break
    out.update(steps=n, z=z, traj=traj[:n + 1] if record else None, compiled=True)
    return out


S_EULER, S_HEUN, S_RK3, S_RK4, S_CSV1, S_CSV2, S_CIMP = 0, 1, 2, 3, 4, 5, 6
SCALAR_METHODS = {"euler": S_EULER, "heun": S_HEUN, "rk3": S_RK3, "rk4": S_RK4, "csv1": S_CSV1,
                  "csv2": S_CSV2, "cimp": S_CIMP}

if HAVE_NUMBA:
    @jit
    def _dv(pend: Any, w2: Any, q: Any) -> Any:   # V'(q): sin q (pendulum) or omega^2 q
        return math.sin(q) if pend else w2 * q

    @jit
    def _ddv(pend: Any, w2: Any, q: Any) -> Any:
        return math.cos(q) if pend else w2

    @jit
    def _scalar_run(meth: str, pend: Any, w2: Any, g: Any, h: Any, q: Any, p: Any, nsteps: int, record: bool, limit: Any) -> Any:
        """verify/refmath.py's one-degree-of-freedom steppers (the second, scalar implementation
        of xrun.scalar_stepper), same operations: returns (steps, status 0 ok / 1 diverged /
        2 solve failed, q, p, trajectory)."""
        traj = np.empty((nsteps + 1 if record else 1, 2))
        traj[0, 0], traj[0, 1] = q, p
        g2 = 2.0 * g
        e1 = math.exp(-g * h)
        a2, b2, e2 = 1.0 + 0.5 * g * h, 1.0 - 0.5 * g * h, math.exp(-0.5 * g * h)
        hh = 0.5 * h
        n = 0
        for n in range(1, nsteps + 1):
            if meth == S_EULER:                  # HLW (1.4)
                kq, kp = p, -_dv(pend, w2, q) - g2 * p
                q, p = q + h * kq, p + h * kp
            elif meth == S_HEUN:                 # B (3.8)
                k1q, k1p = p, -_dv(pend, w2, q) - g2 * p
                xq, xp = q + h * k1q, p + h * k1p
                k2q, k2p = xp, -_dv(pend, w2, xq) - g2 * xp
                q, p = q + 0.5 * h * (k1q + k2q), p + 0.5 * h * (k1p + k2p)
            elif meth == S_RK3:                  # Kutta
                k1q, k1p = p, -_dv(pend, w2, q) - g2 * p
                xq, xp = q + 0.5 * h * k1q, p + 0.5 * h * k1p
                k2q, k2p = xp, -_dv(pend, w2, xq) - g2 * xp
                xq, xp = q + h * (-k1q + 2.0 * k2q), p + h * (-k1p + 2.0 * k2p)
                k3q, k3p = xp, -_dv(pend, w2, xq) - g2 * xp
                q, p = q + h * (k1q + 4.0 * k2q + k3q) / 6.0, p + h * (k1p + 4.0 * k2p + k3p) / 6.0
            elif meth == S_RK4:
                k1q, k1p = p, -_dv(pend, w2, q) - g2 * p
                xq, xp = q + 0.5 * h * k1q, p + 0.5 * h * k1p
                k2q, k2p = xp, -_dv(pend, w2, xq) - g2 * xp
                xq, xp = q + 0.5 * h * k2q, p + 0.5 * h * k2p
                k3q, k3p = xp, -_dv(pend, w2, xq) - g2 * xp
                xq, xp = q + h * k3q, p + h * k3p
                k4q, k4p = xp, -_dv(pend, w2, xq) - g2 * xp
                q, p = (q + h * (k1q + 2.0 * k2q + 2.0 * k3q + k4q) / 6.0,
                        p + h * (k1p + 2.0 * k2p + 2.0 * k3p + k4p) / 6.0)
            elif meth == S_CSV1:                 # F (2.12)
                ph = e1 * p - 0.5 * h * _dv(pend, w2, q)
                q1 = q + h * ph
                q, p = q1, e1 * (ph - 0.5 * h * _dv(pend, w2, q1))
            elif meth == S_CSV2:                 # F (2.16)
                ph = (e2 * p - 0.5 * h * _dv(pend, w2, q)) / a2
                q1 = e2 * (a2 * e2 * q + h * ph) / b2
                q, p = q1, e2 * (b2 * ph - 0.5 * h * _dv(pend, w2, q1))
            else:                                # CIMP, F (2.3), Newton with the exact Jacobian
                aq, ap = e2 * q, e2 * p
                wq, wp = aq + h * (ap + g * aq), ap + h * (-_dv(pend, w2, aq) - g * ap)
                last = math.inf
                ok = False
                for _ in range(60):
                    mq, mp = 0.5 * (wq + aq), 0.5 * (wp + ap)
                    rq = wq - aq - h * (mp + g * mq)
                    rp = wp - ap - h * (-_dv(pend, w2, mq) - g * mp)
                    j11, j12 = 1.0 - hh * g, -hh
                    j21, j22 = hh * _ddv(pend, w2, mq), 1.0 + hh * g
                    det = j11 * j22 - j12 * j21
                    dq = (rq * j22 - rp * j12) / det
                    dp = (rp * j11 - rq * j21) / det
                    wq, wp = wq - dq, wp - dp
                    size = abs(dq) + abs(dp)
                    scale = abs(wq) + abs(wp)
                    if size <= 4.0 * EPS * scale or size == 0.0:
                        ok = True
                        break
                    if size >= last and size <= 1e-10 * scale:
                        ok = True
                        break
                    last = size
                if not ok:
                    return n, 2, q, p, traj
                if not (math.isfinite(wq) and math.isfinite(wp)):
                    return n, 3, q, p, traj
                q, p = e2 * wq, e2 * wp
            if record:
                traj[n, 0], traj[n, 1] = q, p
            if not abs(q) < limit or not abs(p) < limit:
                return n, 1, q, p, traj
        return n, 0, q, p, traj


def integrate_scalar(method: str, prob: Any, h: Any, nsteps: int, record: bool, limit: Any, out: Any) -> Any:
    """xrun.integrate_scalar (refmath's steppers on the oscillator and the pendulum) compiled, or
    None."""
    if not HAVE_NUMBA or method not in SCALAR_METHODS:
        return None
    kind = type(prob).__name__
    if kind == "Oscillator":
        pend, w2 = False, float(prob.w) ** 2
    elif kind == "Pendulum":
        pend, w2 = True, 0.0
    else:
        return None
    g = float(prob.g)
    if method == "csv2" and 1.0 - 0.5 * g * h == 0.0:
        return None                      # a division by zero: the plain path's IEEE inf
    n, status, q, p, traj = _scalar_run(SCALAR_METHODS[method], pend, w2, g, float(h), float(prob.z0[0]),
                                        float(prob.z0[1]), int(nsteps), bool(record), float(limit))
    if status == 1:
        out.update(status="diverged", message="diverged at step %d" % n)
    elif status >= 2:
        out.update(status="solve-failed", message="%s at step %d" % (
            "Newton did not converge" if status == 2 else "Newton produced a non-finite iterate", n))
    out.update(steps=n, z=np.array([q, p]), traj=traj[:n + (0 if status >= 2 else 1)].copy() if record else None,
               compiled=True)
    return out


def _setup(prob: Any) -> Any:
    """(problem code, parameter vector, mass vector, gamma) or None."""
    kind = type(prob).__name__
    d = prob.d
    ones = np.ones(d)
    if kind == "Kepler":
        return KEPLER, np.zeros(1), ones, float(prob.g)
    if kind == "RigidBody":
        a = 1.0 / prob.I
        return RIGID, np.array([a[0], a[1], a[2], prob.eps]), ones, 0.0
    if kind == "DrivenPendulum":
        return DRIVEN, np.array([prob.lam ** 2, prob.F, prob.g]), ones, float(prob.g)
    if kind in ("OuterSolarSystem", "Argon") or (kind == "NBody"):
        grav = kind == "OuterSolarSystem" or (kind == "NBody" and prob.kind == 0)
        c1 = float(prob.G) if grav else 4.0 * float(prob.lje)
        sig = 0.0 if grav else float(prob.sig)
        P = np.concatenate([[prob.n, prob.dim, c1, sig], prob.masses])
        return (NBODY_GRAV if grav else NBODY_LJ), P, np.asarray(prob.m, float), float(prob.g)
    return None


def _method(method: str, prob: Any) -> Any:
    if method in xm.EXPLICIT_RK:
        A, b, c = xm.EXPLICIT_RK[method]
        return ERK, np.array(A, float), np.array(b, float), np.array(c, float)
    none = (np.zeros((1, 1)), np.zeros(1), np.zeros(1))
    if type(prob).__name__ == "RigidBody":
        return None
    table = {"symplectic-euler": SEULER, "symplectic-euler-adjoint": SEULER_ADJ, "stormer-verlet": VERLET}
    if type(prob).__name__ == "DrivenPendulum":
        table = {"csv1": CSV1, "csv2": CSV2}
    if method not in table:
        return None
    return (table[method],) + none


def integrate(method: str, prob: Any, h: Any, nsteps: int, t0: Any, record: bool, limit: Any, out: Any) -> Any:
    """A compiled run for xrun.integrate (same result dictionary), or None when this
    method/problem has no compiled loop (or numba is not available)."""
    if not HAVE_NUMBA:
        return None
    if method in xm.NLS_B and getattr(prob, "pid", "") in xm.NLS_FAMILY:
        return _integrate_nls(method, prob, h, nsteps, t0, record, limit, out)
    su = _setup(prob)
    if su is None:
        return None
    code, P, m, g = su
    if method == "glm4" and code == RIGID:
        return _integrate_glm(prob, code, P, m, h, nsteps, t0, record, limit, out)
    if method in ("implicit-midpoint", "gauss1", "gauss2", "gauss3", "cimp", "glifrk1", "glifrk2",
                  "glifrk3"):
        return _integrate_implicit(method, prob, code, P, m, g, h, nsteps, t0, record, limit, out)
    mt = _method(method, prob)
    if mt is None:
        return None
    meth, A, b, c = mt
    if meth == CSV2 and not (g * h < 2):
        return None                      # xmethods raises NotApplicable: let it
    if code in (NBODY_GRAV, NBODY_LJ) and getattr(prob, "t_dependent_gamma", False):
        return None
    n, status, z, traj = _run(code, meth, P, m, g, np.array(prob.z0, float), float(t0), float(h),
                              int(nsteps), A, b, c, bool(record), float(limit))
    if status == 1:
        out.update(status="diverged", message="diverged at step %d" % n)
    out.update(steps=n, z=z, traj=traj[:n + 1] if record else None, compiled=True)
    return out


def _integrate_glm(prob: Any, code: Any, P: Any, m: Any, h: Any, nsteps: int, t0: Any, record: bool, limit: Any, out: Any) -> Any:
    """BS's GLM on the rigid body: the starting method and each Newton inverse (refreshed every
    8 steps at (t_n, y_n[0]), as xscalar.GLMScalar) in Python, the 8 steps in between compiled."""
    from . import xscalar
    N, f = xscalar.rigid_fields(prob)
    glm = xscalar.GLMScalar(f, lambda t, z: xm.jac_cs(prob.f, t, z), h, 3)
    z0 = [float(v) for v in prob.z0]
    yv = np.array(glm.start(t0, z0), float)
    A, U, B, V = xm.GLM_A, xm.GLM_U, xm.GLM_B, xm.GLM_V
    traj = np.empty((nsteps + 1 if record else 1, 2, prob.d))
    traj[0] = yv
    n = 0
    while n < nsteps:
        Mi = glm._inv(t0 + n * h, yv[0].tolist(), A.tolist())
        k = min(8, nsteps - n)
        n1, status, its, mx = _glm_chunk(code, P, m, float(t0), float(h), n, k, yv,
                                         np.array(Mi[0]), np.array(Mi[1]), A, U, B, V, traj, float(limit))
        out["newton"] += its
        out["newton_max"] = max(out["newton_max"], mx)
        if status == 2:
            out.update(status="solve-failed", message="GLM stage did not converge at step %d" % n1)
            n = n1
            break
        n = n1
        if status == 1:
            out.update(status="diverged", message="diverged at step %d" % n)
            break
    z = yv[0].copy()
    out.update(steps=n, z=z, traj=traj[:n + 1, 0].copy() if record else None, compiled=True)
    if record and out["status"] == "ok":
        out["glm_y"] = traj[:n + 1].copy()
    return out


def warm() -> Any:
    """Compile (or load from the cache) every kernel once, in the parent process before the
    worker pool forks, so that the workers inherit the machine code instead of each compiling
    it again.  Returns the seconds spent."""
    import time
    t = time.perf_counter()
    if HAVE_NUMBA:
        one = np.ones(1)
        _run(KEPLER, ERK, one, np.ones(4), 0.0, np.array([0.5, 0.0, 0.0, 1.5]), 0.0, 0.01, 1,
             np.zeros((1, 1)), one, np.zeros(1), True, math.inf)
        yv = np.array([[4.0, 3.0, 0.0], [0.0, 0.0, 0.0]])
        M = np.eye(3)
        _glm_chunk(RIGID, np.array([0.25, 1 / 3, 0.5, 0.0]), np.ones(3), 0.0, 0.01, 0, 1, yv, M, M,
                   xm.GLM_A, xm.GLM_U, xm.GLM_B, xm.GLM_V, np.empty((1, 2, 3)), math.inf)
        _scalar_run(S_EULER, True, 0.0, 0.1, 0.01, 1.0, 0.0, 1, True, math.inf)
    return time.perf_counter() - t


# ---- B's NLS schemes (4.15), (5.27), (5.28): the fixed-point iteration of xmethods.nls_b_step,
# compiled, with a radix-2 FFT of our own (numba has no numpy.fft): M a power of two only.
if HAVE_NUMBA:
    @jit
    def _fft2(a: Any, w: Any, inverse: bool) -> None:
        """In-place iterative radix-2 FFT of a (length M = 2^k), twiddles w[k] = e^{-2 pi i k/M},
        k < M/2; the inverse conjugates the twiddles and divides by M."""
        M = a.size
        j = 0
        for i in range(1, M):                   # bit reversal
            bit = M >> 1
            while j & bit:
                j ^= bit
                bit >>= 1
            j |= bit
            if i < j:
                a[i], a[j] = a[j], a[i]
        size = 2
        while size <= M:
            half = size // 2
            step = M // size
            for start in range(0, M, size):
                for k in range(half):
                    tw = w[k * step]
                    if inverse:
                        tw = tw.conjugate()
                    u = a[start + k]
                    v = a[start + k + half] * tw
                    a[start + k] = u + v
                    a[start + k + half] = u - v
            size *= 2
        if inverse:
            for i in range(M):
                a[i] = a[i] / M

    @jit
    def _nls_loop(psi0: Any, w: Any, sym: Any, c2: Any, ey: Any, back: Any, lam: Any, cubic: bool, G: Any, w0: Any, al: Any, t0: Any, h: Any, nsteps: int, record: bool,
                  limit: Any) -> Any:
        M = psi0.size
        psi = psi0.copy()
        traj = np.empty((nsteps + 1 if record else 1, 2 * M))
        for i in range(M):
            traj[0, i] = psi[i].real
            traj[0, M + i] = psi[i].imag
        Y = np.empty(M, np.complex128)
        Phi = np.empty(M, np.complex128)
        r = np.empty(M, np.complex128)
        its_total = 0
        its_max = 0
        eps = 2.220446049250313e-16
        for n in range(1, nsteps + 1):
            t = t0 + (n - 1) * h
            F = G * complex(math.cos(w0 * (t + 0.5 * h) + al), math.sin(w0 * (t + 0.5 * h) + al))
            for i in range(M):
                Y[i] = ey * psi[i]
                Phi[i] = Y[i]
            last = np.inf
            done = False
            it = 0
            while it < 200 and not done:
                it += 1
                for i in range(M):
                    eta = Phi[i].real ** 2 + Phi[i].imag ** 2
                    vp = lam * eta if cubic else lam
                    r[i] = c2 * Y[i] - vp * Phi[i] + F
                _fft2(r, w, False)
                for i in range(M):
                    r[i] = r[i] / sym[i]
                _fft2(r, w, True)
                dmax = 0.0
                mag = 0.0
                for i in range(M):
                    dmax = max(dmax, abs(r[i] - Phi[i]))
                    mag = max(mag, abs(r[i]))
                    Phi[i] = r[i]
                m = dmax / max(mag, 1e-300)
                if m <= 2 * eps or (it >= 3 and m >= 0.5 * last and m <= 1e-11):
                    done = True
                last = m
            its_total += it
            its_max = max(its_max, it)
            if not done:
                return n - 1, 2, psi, traj, its_total, its_max
            bad = False
            for i in range(M):
                psi[i] = back * (2.0 * Phi[i] - Y[i])
                if not (abs(psi[i].real) < limit and abs(psi[i].imag) < limit):
                    bad = True
            if record:
                for i in range(M):
                    traj[n, i] = psi[i].real
                    traj[n, M + i] = psi[i].imag
            if bad:
                return n, 1, psi, traj, its_total, its_max
        return nsteps, 0, psi, traj, its_total, its_max


def _integrate_nls(method: str, prob: Any, h: Any, nsteps: int, t0: Any, record: bool, limit: Any, out: Any) -> Any:
    """xmethods.nls_b_step's scheme (same equations, same iteration and stopping rule), compiled;
    None (the numpy loop) unless M is a power of two."""
    M = prob.M
    if M < 2 or M & (M - 1):
        return None
    g, dx = prob.gB, prob.dx
    imp = method == "nls-imp"
    kappa = g * h / math.sinh(g * h) if (method == "nls-etd" and g != 0.0) else 1.0
    ey = 1.0 if imp else math.exp(-g * h)
    c2 = 2j * kappa / h
    sym = (c2 + (2j * g if imp else 0.0) - 4.0 * np.sin(math.pi * np.arange(M) / M) ** 2 / dx ** 2
           ).astype(np.complex128)
    w = np.exp(-2j * math.pi * np.arange(M // 2) / M)
    driven = prob.pid == "nls-driven"
    z0 = np.asarray(prob.z0, float)
    psi0 = (z0[:M] + 1j * z0[M:]).astype(np.complex128)
    n, status, psi, traj, its, itmax = _nls_loop(
        psi0, w, sym, c2, ey, ey, float(prob.lam), prob.pid != "schrodinger",
        float(prob.G) if driven else 0.0, float(prob.w0) if driven else 0.0,
        float(prob.al) if driven else 0.0, float(t0), float(h), int(nsteps), bool(record),
        float(limit))
    out["newton"] += int(its)
    out["newton_max"] = max(out["newton_max"], int(itmax))
    if status == 1:
        out.update(status="diverged", message="diverged at step %d" % n)
    elif status == 2:
        out.update(status="solve-failed", message="%s: fixed-point iteration did not converge at step %d" % (method, n + 1))
    z = np.concatenate([psi.real, psi.imag])
    out.update(steps=n, z=z, traj=traj[:n + 1] if record else None, compiled=True)
    return out
