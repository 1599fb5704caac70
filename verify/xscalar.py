"""Plain-float step loops for the long runs on small problems (Kepler, rigid body): the same
mathematics as verify/xmethods.py (same coefficient sources: the Gauss tableaux of xmethods,
B (2.5) factors, BS's GLM), written on Python lists because numpy's per-call overhead
dominates 3- and 4-vectors.  tests: verify/test_crosscheck_negative.py and the agreement of
both paths (xscalar_selftest below)."""
from typing import Any, Dict, List
import math

import numpy as np

from . import refmath
from . import xmethods as xm


def kepler_fields() -> Any:
    def force(t: Any, q: Any) -> Any:
        x, y = q
        r2 = x * x + y * y
        r3 = r2 * math.sqrt(r2)
        return [-x / r3, -y / r3]
    return force


def rigid_fields(prob: Any) -> Any:
    a1, a2, a3 = (1.0 / v for v in prob.I)
    eps = prob.eps

    def N(t: Any, z: Any) -> Any:
        z1, z2, z3 = z
        return [z3 * z2 * a3 - z2 * z3 * a2, -z3 * z1 * a3 + z1 * z3 * a1, z2 * z1 * a2 - z1 * z2 * a1]

    def f(t: Any, z: Any) -> Any:
        g = 0.5 * eps * math.cos(2.0 * t)
        n = N(t, z)
        return [n[i] - g * z[i] for i in range(3)]
    return N, f


def driven_fields(prob: Any) -> Any:
    """B 3.2.2: q'' + 2 gamma q' + lambda^2 sin q = f sin t, as xproblems.DrivenPendulum."""
    lam2, F, g = prob.lam ** 2, prob.F, prob.g

    def force(t: Any, q: Any) -> Any:
        return -lam2 * math.sin(q) + F * math.sin(t)

    def f(t: Any, z: Any) -> Any:
        return [z[1], force(t, z[0]) - 2.0 * g * z[1]]

    def N(t: Any, z: Any) -> Any:
        return [z[1] + g * z[0], force(t, z[0]) - g * z[1]]
    return force, f, N


def _csv_scalar(prob: Any, force: Any, h: Any, which: Any) -> Any:
    """F (2.12) / F (2.16) on one degree of freedom (m = 1), the formulas of xmethods.csv1_step
    and csv2_step."""
    if which == "csv1":
        def step_csv1(t: Any, z: Any) -> Any:
            e1 = math.exp(-2.0 * xm.dGamma(prob, t, 0.5 * h))
            e2 = math.exp(-2.0 * xm.dGamma(prob, t + 0.5 * h, 0.5 * h))
            q, p = z
            ph = e1 * p + 0.5 * h * force(t, q)
            q1 = q + h * ph
            return [q1, e2 * (ph + 0.5 * h * force(t + h, q1))], 0
        return step_csv1

    def step(t: Any, z: Any) -> Any:
        x = xm.dGamma(prob, t, h)
        a, b, e = 1 + 0.5 * x, 1 - 0.5 * x, math.exp(-0.5 * x)
        q, p = z
        ph = (e * p + 0.5 * h * force(t, q)) / a
        q1 = refmath.ieee_div(e * (a * e * q + h * ph), b)  # x = 2: inf, as dampsym
        return [q1, e * (b * ph + 0.5 * h * force(t + h, q1))], 0
    return step


def _erk(f: Any, A: Any, b: Any, c: Any, h: Any) -> Any:
    s = len(b)

    def step(t: Any, z: Any) -> Any:
        K: List[Any] = []
        for i in range(s):
            zi = list(z)
            for j in range(i):
                if A[i][j]:
                    zi = [zi[k] + h * A[i][j] * K[j][k] for k in range(len(z))]
            K.append(f(t + c[i] * h, zi))
        return [z[k] + h * sum(b[i] * K[i][k] for i in range(s)) for k in range(len(z))]
    return step


def _implicit(G: Any, coef: Any, h: Any, d: Any, field: Any) -> Any:
    """Z_i = Phi_i z + h sum_j A_ij G(t + c_j h, Z_j); z1 = phi0 z + h sum b_i G(Z_i); simplified
    Newton with the matrix refreshed every 8 steps (or when the coefficients change), iterated
    to round-off exactly as xmethods.rk_family_step, and as there a step it cannot solve by full
    Newton (xmethods.full_newton_step on `field`, G's numpy form)."""
    cache: Dict[str, Any] = {"age": 99, "key": None}

    def step(t: Any, z: Any) -> Any:
        try:
            return simplified(t, z)
        except xm.SolveFailed:
            cache["slow"] = True
            z1, it = xm.full_newton_step(field, coef, h, t, np.array(z, float))
            return [float(x) for x in z1], it

    def simplified(t: Any, z: Any) -> Any:
        Phi, A, b, phi0, c = coef(t)
        s = len(b)
        key = A.tobytes()
        if cache["key"] != key or cache["age"] >= 8 or cache.get("slow"):
            J = xm.jac_cs(field, t, np.array(z))
            cache.update(key=key, age=0, slow=False,
                         Minv=np.linalg.inv(np.eye(s * d) - h * np.kron(A, J)).tolist())
        cache["age"] += 1
        Mi = cache["Minv"]
        Al = A.tolist()
        g0 = G(t, z)
        Z = [[Phi[i] * z[k] + h * c[i] * g0[k] for k in range(d)] for i in range(s)]
        last, it = math.inf, 0
        while True:
            it += 1
            K = [G(t + c[j] * h, Z[j]) for j in range(s)]
            R = []
            for i in range(s):
                R += [Z[i][k] - Phi[i] * z[k] - h * sum(Al[i][j] * K[j][k] for j in range(s))
                      for k in range(d)]
            dZ = [sum(Mi[r][q] * R[q] for q in range(s * d)) for r in range(s * d)]
            num = den = 0.0
            for i in range(s):
                for k in range(d):
                    Z[i][k] -= dZ[i * d + k]
                    num = max(num, abs(dZ[i * d + k]))
                    den = max(den, abs(Z[i][k]))
            m = num / max(den, 1e-300)
            if not math.isfinite(m):
                raise xm.SolveFailed("non-finite Newton iterate")
            if xm.settled(m, last, it, num == 0.0):
                break
            last = m
            if it > 100:
                raise xm.SolveFailed("Newton did not converge")
        cache["slow"] = it > 6
        K = [G(t + c[j] * h, Z[j]) for j in range(s)]
        return [phi0 * z[k] + h * sum(b[i] * K[i][k] for i in range(s)) for k in range(d)], it
    return step


class GLMScalar:
    def __init__(self, f: Any, jac: Any, h: Any, d: Any) -> None:
        self.f, self.jac, self.h, self.d = f, jac, h, d
        self.age = 99
        self.A = xm.GLM_A.tolist()
        self.U, self.B, self.V = xm.GLM_U.tolist(), xm.GLM_B.tolist(), xm.GLM_V.tolist()

    def _solve(self, t: Any, base: Any, a: Any, Mi: Any) -> Any:
        f, h, d = self.f, self.h, self.d
        y = list(base)
        last, it = math.inf, 0
        while True:
            it += 1
            fy = f(t, y)
            R = [y[k] - base[k] - h * a * fy[k] for k in range(d)]
            dy = [sum(Mi[r][q] * R[q] for q in range(d)) for r in range(d)]
            num = max(abs(v) for v in dy)
            y = [y[k] - dy[k] for k in range(d)]
            m = num / max(max(abs(v) for v in y), 1e-300)
            if xm.settled(m, last, it, num == 0.0):
                return y, f(t, y), it
            last = m
            if it > 100:
                raise xm.SolveFailed("GLM stage did not converge")

    def _inv(self, t: Any, z: Any, A: Any) -> Any:
        J = self.jac(t, np.array(z))
        return [np.linalg.inv(np.eye(self.d) - self.h * A[k][k] * J).tolist() for k in range(2)]

    def start(self, t: Any, y0: Any) -> Any:
        A0 = xm.GLM_A0.tolist()
        Mi = self._inv(t, y0, A0)
        h, d = self.h, self.d
        # stage i at t + c_i h, c = A0 e (xmethods.GLM: a time-dependent gamma)
        Y1, K1, _ = self._solve(t + sum(A0[0]) * h, y0, A0[0][0], Mi[0])
        base = [y0[k] + h * A0[1][0] * K1[k] for k in range(d)]
        Y2, K2, _ = self._solve(t + sum(A0[1]) * h, base, A0[1][1], Mi[1])
        S = xm.GLM_S
        return [list(y0), [h * (S[0] * K1[k] + S[1] * K2[k]) for k in range(d)]]

    def step(self, t: Any, yv: Any) -> Any:
        h, d, A, U, B, V = self.h, self.d, self.A, self.U, self.B, self.V
        if self.age >= 8:
            self.Mi = self._inv(t, yv[0], A)
            self.age = 0
        self.age += 1
        Yp = [[U[i][0] * yv[0][k] + U[i][1] * yv[1][k] for k in range(d)] for i in range(2)]
        # stage i at t + c_i h, c = A e (BS: U's first column is e and y2 carries no time)
        Y1, K1, i1 = self._solve(t + (A[0][0] + A[0][1]) * h, Yp[0], A[0][0], self.Mi[0])
        base = [Yp[1][k] + h * A[1][0] * K1[k] for k in range(d)]
        Y2, K2, i2 = self._solve(t + (A[1][0] + A[1][1]) * h, base, A[1][1], self.Mi[1])
        return [[h * (B[i][0] * K1[k] + B[i][1] * K2[k]) + V[i][0] * yv[0][k] + V[i][1] * yv[1][k]
                 for k in range(d)] for i in range(2)], i1 + i2


def make(method: str, prob: Any, h: Any) -> Any:
    """A plain-float stepper (step(t, z_list) -> (z1, its)) or a GLMScalar, or None."""
    kind = type(prob).__name__
    if kind == "Kepler":
        force = kepler_fields()

        def f(t: Any, z: Any) -> Any:
            fq = force(t, z[:2])
            return [z[2], z[3], fq[0], fq[1]]
        if method in xm.EXPLICIT_RK:
            A, b, c = xm.EXPLICIT_RK[method]
            st = _erk(f, A, b, c, h)
            return lambda t, z: (st(t, z), 0)
        if method == "symplectic-euler":      # gamma = 0 here
            def step(t: Any, z: Any) -> Any:
                fq = force(t, z[:2])
                p = [z[2] + h * fq[0], z[3] + h * fq[1]]
                return [z[0] + h * p[0], z[1] + h * p[1], p[0], p[1]], 0
            return step
        if method == "stormer-verlet":
            def step(t: Any, z: Any) -> Any:
                fq = force(t, z[:2])
                ph = [z[2] + 0.5 * h * fq[0], z[3] + 0.5 * h * fq[1]]
                q1 = [z[0] + h * ph[0], z[1] + h * ph[1]]
                f1 = force(t + h, q1)
                return q1 + [ph[0] + 0.5 * h * f1[0], ph[1] + 0.5 * h * f1[1]], 0
            return step
        if method in ("implicit-midpoint", "gauss1", "gauss2", "gauss3"):
            A, b, c = xm.GAUSS[1 if method == "implicit-midpoint" else int(method[-1])]
            return _implicit(f, xm.plain_coef(A, b, c), h, 4, prob.f)
        return None
    if kind == "DrivenPendulum":
        force, f, N = driven_fields(prob)
        if method in xm.EXPLICIT_RK:
            A, b, c = xm.EXPLICIT_RK[method]
            st = _erk(f, A, b, c, h)
            return lambda t, z: (st(t, z), 0)
        if method in ("csv1", "csv2"):
            return _csv_scalar(prob, force, h, method)
        if method in ("gauss1", "gauss2", "gauss3", "implicit-midpoint"):
            A, b, c = xm.GAUSS[1 if method == "implicit-midpoint" else int(method[-1])]
            return _implicit(f, xm.plain_coef(A, b, c), h, 2, prob.f)
        if method in ("cimp", "glifrk1", "glifrk2", "glifrk3"):
            A, b, c = xm.GAUSS[1 if method == "cimp" else int(method[-1])]
            return _implicit(N, xm.ifrk_coef(prob, A, b, c, h), h, 2, prob.N)
        return None
    if kind == "RigidBody":
        N, f = rigid_fields(prob)
        if method in xm.EXPLICIT_RK:
            A, b, c = xm.EXPLICIT_RK[method]
            st = _erk(f, A, b, c, h)
            return lambda t, z: (st(t, z), 0)
        if method in ("gauss1", "gauss2", "gauss3", "implicit-midpoint"):
            A, b, c = xm.GAUSS[1 if method == "implicit-midpoint" else int(method[-1])]
            return _implicit(f, xm.plain_coef(A, b, c), h, 3, prob.f)
        if method in ("cimp", "glifrk1", "glifrk2", "glifrk3"):
            A, b, c = xm.GAUSS[1 if method == "cimp" else int(method[-1])]
            return _implicit(N, xm.ifrk_coef(prob, A, b, c, h), h, 3, prob.N)
        if method == "glm4":
            return GLMScalar(f, lambda t, z: xm.jac_cs(prob.f, t, z), h, 3)
    return None
