"""Problems of the independent cross-check, written from the papers (HLW ch. I, B, F) and the
repository's docs (docs/conventions.md), never from dampsym's C++ sources.

Convention (docs/conventions.md §1): q' = grad T(p), p' = -grad V(q, t) - 2 gamma(t) p;
conformal form z' = N(t, z) - gamma(t) z with N = f + gamma z.  Every function below works on
arrays whose LAST axis is the state (any leading batch axes) and accepts complex input, so that
Jacobians are obtained exactly (to round-off) by the complex step.
"""
from typing import Any, Dict, Tuple
import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.special import iv

from . import xcache

EPS = np.finfo(float).eps


class Problem:
    """Base: separable q/p problem with mass vector `m` (T = sum p^2 / 2m)."""
    pid: str
    params: Tuple[str, ...]
    g: Any                  # the damping's constant gamma (time-dependent: gamma(t))
    m: Any                  # masses, one per component of q
    nq: int                 # components of q
    d: int                  # state dimension
    z0: Any                 # initial state
    V: Any                  # the potential V(q)
    separable = True
    canonical = True
    exact_available = False
    forcing_period: Any = None
    t_dependent_gamma = False

    def gamma(self, t: Any) -> Any:
        return self.g

    def Gamma(self, t: Any) -> Any:          # Gamma(t) = int_0^t gamma(s) ds
        return self.g * t

    def dT(self, p: Any) -> Any:
        return p / self.m

    def force(self, t: Any, q: Any) -> Any:        # -grad V(q, t)
        raise NotImplementedError

    def f(self, t: Any, z: Any) -> Any:
        q, p = z[..., :self.nq], z[..., self.nq:]
        return np.concatenate([self.dT(p), self.force(t, q) - 2.0 * self.gamma(t) * p], axis=-1)

    def N(self, t: Any, z: Any) -> Any:           # conformal form: f = N - gamma z
        q, p = z[..., :self.nq], z[..., self.nq:]
        g = self.gamma(t)
        return np.concatenate([self.dT(p) + g * q, self.force(t, q) - g * p], axis=-1)

    def energy(self, z: Any) -> Any:
        q, p = z[..., :self.nq], z[..., self.nq:]
        return 0.5 * np.sum(p * p / self.m, axis=-1) + self.V(q)

    # scale S_H of energy changes and errors (docs/conventions.md "Law residuals and their
    # scales"): T + |V| where H = T + V may cross zero; None where the docs define none
    energy_scale: Any = None

    def kinetic(self, z: Any) -> Any:
        p = z[..., self.nq:]
        return 0.5 * np.sum(p * p / self.m, axis=-1)

    def f_ref(self, t: Any, z: Any) -> Any:
        """The field for the DOP853 reference (one state, no batch axes); problems with one
        degree of freedom override it with the same formula in plain floats (numpy's per-call
        overhead dominated the reference solves)."""
        return self.f(t, z)

    # numerical reference: DOP853 at scipy's tightest tolerance, certified by a second solve
    def reference_grid(self, t0: Any, times: Any) -> Any:
        key = (t0, tuple(np.asarray(times).tolist()))
        cache = self.__dict__.setdefault("_refcache", {})
        if key not in cache:
            cache[key] = _reference_solves(self, t0, np.asarray(times, float))
        return cache[key]


@xcache.memo
def _reference_solves(prob: Problem, t0: Any, times: Any) -> Any:
    """Problem.reference_grid's two DOP853 solves: (states at times, their difference)."""
    sols = []
    for rtol, atol in ((1e-13, 1e-15), (2.3e-14, 1e-16)):
        s = solve_ivp(prob.f_ref, (t0, times[-1]), prob.z0, method="DOP853",
                      rtol=rtol, atol=atol, t_eval=times, dense_output=False)
        if not s.success:
            raise RuntimeError("reference failed: " + s.message)
        sols.append(s.y.T)
    return sols[1], float(np.max(np.linalg.norm(sols[0] - sols[1], axis=-1)))


class Oscillator(Problem):
    """q'' + 2 gamma q' + omega^2 q = 0 (F(2.5))."""
    pid = "oscillator"
    params = ("omega", "gamma", "q0", "p0")
    exact_available = True

    def __init__(self, omega: Any, gamma: Any, q0: Any, p0: Any) -> None:
        self.w, self.g = float(omega), float(gamma)
        self.nq, self.d, self.m = 1, 2, 1.0
        self.z0 = np.array([q0, p0], float)

    def force(self, t: Any, q: Any) -> Any:
        return -self.w ** 2 * q

    def V(self, q: Any) -> Any:
        return 0.5 * self.w ** 2 * q[..., 0] ** 2

    def invariants(self) -> Any:   # H_gamma = (w^2 q^2 + p^2)/2 + g q p (B Ex. 1.2), decays e^{-2Gamma}
        return {"H_gamma": lambda z: 0.5 * (self.w ** 2 * z[..., 0] ** 2 + z[..., 1] ** 2)
                + self.g * z[..., 0] * z[..., 1]}

    def invariant_scales(self) -> Any:   # |z|^T |A| |z|: the sum of the magnitudes of H_gamma's terms
        return {"H_gamma": lambda z: 0.5 * (self.w ** 2 * z[..., 0] ** 2 + z[..., 1] ** 2)
                + self.g * np.abs(z[..., 0] * z[..., 1])}

    def energy_scale(self, z: Any) -> Any:    # definite energy: H itself
        return self.energy(z)

    def exact(self, t0: Any, t: Any) -> Any:
        """Exact state at times t (array) in every regime; z' = A z, A + gI = B, B^2 = -beta^2 I."""
        t = np.atleast_1d(np.asarray(t, float)) - t0
        g, w = self.g, self.w
        b2 = (w - g) * (w + g)
        C, S = np.empty_like(t), np.empty_like(t)
        for k, tk in enumerate(t):
            x = b2 * tk * tk
            if abs(x) <= 1.0:
                c, s, tc, ts = 0.0, 0.0, 1.0, tk
                for j in range(14):
                    c += tc
                    s += ts
                    tc *= -x / ((2 * j + 1) * (2 * j + 2))
                    ts *= -x / ((2 * j + 2) * (2 * j + 3))
                e = math.exp(-g * tk)
                C[k], S[k] = e * c, e * s
            elif b2 > 0:
                beta = math.sqrt(b2)
                e = math.exp(-g * tk)
                C[k], S[k] = e * math.cos(beta * tk), e * math.sin(beta * tk) / beta
            else:
                C[k] = S[k] = math.nan     # over-damped: eigen-decomposition below
        q0, p0 = self.z0
        out = np.stack([C * q0 + S * (g * q0 + p0), C * p0 + S * (-w * w * q0 - g * p0)], axis=-1)
        # over-damped (|b2 t^2| > 1, b2 < 0): q = a e^{l1 t} + b e^{l2 t} with the roots
        # l1 = -w^2/(kap + g) (slow, no cancellation), l2 = -(kap + g), l2 - l1 = -2 kap;
        # a = (l2 q0 - p0)/(l2 - l1), b = (p0 - l1 q0)/(l2 - l1).  The C, S form above would
        # cancel e^{l1 t} terms in p (1 - g/kap ~ w^2/2g^2): that lost ~1e-14 at gamma = 1e3.
        od = np.isnan(C)
        if od.any():
            kap = math.sqrt(-b2)
            l1, l2 = -w * w / (kap + g), -(kap + g)
            a, b = (l2 * q0 - p0) / (-2 * kap), (p0 - l1 * q0) / (-2 * kap)
            e1, e2 = np.exp(l1 * t[od]), np.exp(l2 * t[od])
            out[od] = np.stack([a * e1 + b * e2, a * l1 * e1 + b * l2 * e2], axis=-1)
        return out


class Pendulum(Problem):
    """q'' + 2 gamma q' + sin q = 0 (F(4.5) with its 2 gamma q misprint fixed)."""
    pid = "pendulum"
    params = ("gamma", "q0", "p0")

    def __init__(self, gamma: Any, q0: Any, p0: Any) -> None:
        self.g = float(gamma)
        self.nq, self.d, self.m = 1, 2, 1.0
        self.z0 = np.array([q0, p0], float)

    def force(self, t: Any, q: Any) -> Any:
        return -np.sin(q)

    def V(self, q: Any) -> Any:
        return -np.cos(q[..., 0])

    def f_ref(self, t: Any, z: Any) -> Any:
        q, p = z
        return np.array([p, -math.sin(q) - 2.0 * self.g * p])

    def energy_scale(self, z: Any) -> Any:    # T + 1: the amplitude of V = -cos q does not vanish
        return self.kinetic(z) + 1.0


class DrivenPendulum(Problem):
    """q'' + 2 gamma q' + lambda^2 sin q = f sin t (B 3.2.2), forcing period 2 pi."""
    pid = "driven-pendulum"
    params = ("f", "gamma", "lambda", "q0", "p0")
    forcing_period = 2.0 * math.pi

    def __init__(self, f: Any, gamma: Any, q0: Any, p0: Any, **kw: Any) -> None:
        self.F, self.g, self.lam = float(f), float(gamma), float(kw["lambda"])
        self.nq, self.d, self.m = 1, 2, 1.0
        self.z0 = np.array([q0, p0], float)

    def force(self, t: Any, q: Any) -> Any:
        return -self.lam ** 2 * np.sin(q) + self.F * np.sin(t)

    def V(self, q: Any) -> Any:
        return -self.lam ** 2 * np.cos(q[..., 0])

    def f_ref(self, t: Any, z: Any) -> Any:
        q, p = z
        return np.array([p, -self.lam ** 2 * math.sin(q) + self.F * math.sin(t) - 2.0 * self.g * p])


class Hill(Problem):
    """q'' + 2 gamma(t) q' + kappa^2 q = 0, gamma(t) = eps cos(2t) / 2 (B 3.1.2)."""
    pid = "hill"
    params = ("epsilon", "kappa", "q0", "p0")
    t_dependent_gamma = True

    def __init__(self, epsilon: Any, kappa: Any, q0: Any, p0: Any) -> None:
        self.eps, self.k = float(epsilon), float(kappa)
        self.nq, self.d, self.m = 1, 2, 1.0
        self.z0 = np.array([q0, p0], float)

    def gamma(self, t: Any) -> Any:
        return 0.5 * self.eps * np.cos(2.0 * t)

    def Gamma(self, t: Any) -> Any:
        return 0.25 * self.eps * np.sin(2.0 * t)

    def force(self, t: Any, q: Any) -> Any:
        return -self.k ** 2 * q

    def f_ref(self, t: Any, z: Any) -> Any:
        q, p = z
        return np.array([p, -self.k ** 2 * q - self.eps * math.cos(2.0 * t) * p])

    def V(self, q: Any) -> Any:
        return 0.5 * self.k ** 2 * q[..., 0] ** 2


class RigidBody(Problem):
    """B(1.7): z' = S(z) z - gamma(t) z, gamma = eps cos(2t)/2; Casimir |z|^2 and energy
    sum z_i^2 / (2 I_i) both decay as e^{-2 Gamma} (B(3.10))."""
    pid = "rigid-body"
    params = ("I1", "I2", "I3", "epsilon", "z1", "z2", "z3")
    separable = False
    canonical = False
    t_dependent_gamma = True
    exact_available = True

    def __init__(self, I1: Any, I2: Any, I3: Any, epsilon: Any, z1: Any, z2: Any, z3: Any) -> None:
        self.I = np.array([I1, I2, I3], float)
        self.eps = float(epsilon)
        self.d = 3
        self.z0 = np.array([z1, z2, z3], float)

    def gamma(self, t: Any) -> Any:
        return 0.5 * self.eps * np.cos(2.0 * t)

    def Gamma(self, t: Any) -> Any:
        return 0.25 * self.eps * np.sin(2.0 * t)

    def N(self, t: Any, z: Any) -> Any:
        a1, a2, a3 = 1.0 / self.I
        z1, z2, z3 = z[..., 0], z[..., 1], z[..., 2]
        # rows of S(z) z from B(1.7)
        return np.stack([z3 * z2 * a3 - z2 * z3 * a2, -z3 * z1 * a3 + z1 * z3 * a1,
                         z2 * z1 * a2 - z1 * z2 * a1], axis=-1)

    def f(self, t: Any, z: Any) -> Any:
        return self.N(t, z) - self.gamma(t) * z

    def energy(self, z: Any) -> Any:
        return 0.5 * np.sum(z * z / self.I, axis=-1)

    def invariants(self) -> Any:
        return {"casimir": lambda z: np.sum(z * z, axis=-1), "energy": self.energy}

    def invariant_scales(self) -> Any:   # both definite: |I| itself
        return {k: (lambda z, f=f: np.abs(f(z))) for k, f in self.invariants().items()}

    def energy_scale(self, z: Any) -> Any:
        return self.energy(z)

    def tau(self, t: Any) -> Any:
        """tau(t) = int_0^t e^{-Gamma(s)} ds, Gamma = a sin 2s, a = eps/4, by the Jacobi-Anger
        series e^{-a sin th} = I0(a) + 2 sum_k I_k(a) cos(k (th + pi/2)) integrated termwise."""
        a = 0.25 * self.eps
        t = np.asarray(t, float)
        out = iv(0, a) * t
        for k in range(1, 40):
            ck = iv(k, a)
            if ck < 1e-300:
                break
            out = out + 2.0 * ck * (np.sin(k * (2.0 * t + 0.5 * math.pi)) - math.sin(k * 0.5 * math.pi)) / (2.0 * k)
        return out

    def free_body(self, y0: Any, taus: Any) -> Any:
        """Closed form of the free rigid body y' = N(y) (Euler's equations; HLW ch. I, B(1.7)) by
        Jacobi elliptic functions, derived here (docs/conventions.md §2).  With a_i = 1/I_i the
        equations y_i' = (a_k - a_j) y_j y_k are invariant under cyclic relabelling, so the axis of
        the middle a is made index 2.  C = |y|^2, E = sum a_i y_i^2, P = E - a3 C, Q = a1 C - E,
        alpha = a1 - a2, beta = a2 - a3 (same sign s), then (y2')^2 = (P - beta y2^2)(Q - alpha y2^2):
          P/beta > Q/alpha (about axis 1): y = (s1 sqrt(P/(a1-a3)) dn u, sqrt(Q/alpha) sn u,
            sqrt(Q/(a1-a3)) cn u), m = beta Q/(alpha P), u' = s1 s sqrt(alpha P);
          P/beta < Q/alpha (about axis 3): y = (sqrt(P/(a1-a3)) cn u, sqrt(P/beta) sn u,
            s3 sqrt(Q/(a1-a3)) dn u), m = alpha P/(beta Q), u' = s3 s sqrt(beta Q);
        u = u0 + u' tau, u0 = F(am, m) with am = atan2(sn u0, cn u0) from y0.  Returns None on
        the separatrix (m within 1e-6 of 1) or on an axis (then the DOP853 solve is used)."""
        from scipy.special import ellipj, ellipkinc, ellipk
        a = 1.0 / self.I
        r = next((r for r in range(3) if sorted(a)[1] == a[(1 + r) % 3]), None)
        if r is None:
            return None
        perm = [(i + r) % 3 for i in range(3)]
        a1, a2, a3 = a[perm]
        y = np.asarray(y0, float)[perm]
        al, be, d13 = a1 - a2, a2 - a3, a1 - a3
        if al * be <= 0 or d13 == 0:
            return None
        sg = math.copysign(1.0, d13)
        C = float(np.dot(y, y))
        E = float(np.dot(a[perm], y * y))
        P, Q = E - a3 * C, a1 * C - E
        if P / be > Q / al:
            m = be * Q / (al * P)
            B, A, D = math.sqrt(Q / al), math.sqrt(P / d13), math.sqrt(Q / d13)
            s1 = math.copysign(1.0, y[0])
            nu = s1 * sg * math.sqrt(al * P)
            ph = math.atan2(y[1] / B, y[2] / D)
            kind = 1
        else:
            m = al * P / (be * Q)
            B, A, D = math.sqrt(P / be), math.sqrt(P / d13), math.sqrt(Q / d13)
            s3 = math.copysign(1.0, y[2])
            nu = s3 * sg * math.sqrt(be * Q)
            ph = math.atan2(y[1] / B, y[0] / A)
            kind = 3
        if not (0.0 <= m < 1.0 - 1e-6):
            return None
        u0 = float(ellipkinc(ph, m))
        K4 = 4.0 * float(ellipk(m))
        u = u0 + nu * np.asarray(taus, float)
        u = u - K4 * np.round(u / K4)            # sn, cn, dn have period 4K
        sn, cn, dn, _ = ellipj(u, m)
        out = np.empty((len(u), 3))
        if kind == 1:
            Y = np.stack([s1 * A * dn, B * sn, D * cn], axis=-1)
        else:
            Y = np.stack([A * cn, B * sn, s3 * D * dn], axis=-1)
        out[:, perm] = Y
        # round-off: the phase u carries ~4 eps |u| (+ u0's few eps), amplified by |dy/du| <= |y|
        self.free_estimate = float(8 * EPS * (1.0 + np.max(np.abs(nu * np.asarray(taus))) + abs(u0))
                                   * math.sqrt(C))
        return out

    def exact(self, t0: Any, t: Any) -> Any:
        """N is homogeneous of degree 2, so z(t) = e^{-Gamma(t)} y(tau(t)) with y the free body
        (docs/conventions.md §2), y in closed form (free_body: Jacobi elliptic functions).  Where
        the closed form does not apply (separatrix, body on an axis) the free body is integrated
        by DOP853 at scipy's tightest tolerance in tau, the estimate the difference to a 10x
        looser solve."""
        t = np.atleast_1d(np.asarray(t, float))
        G0 = self.Gamma(t0)
        taus = self.tau(t) - self.tau(t0)
        # the body starts at z0 at t0: y(0) = e^{Gamma(t0)} z0 in the rescaled time from t0
        y0 = self.z0 * math.exp(G0)
        sc = np.exp(-self.Gamma(t))[:, None]
        Yc = self.free_body(y0, taus)
        if Yc is not None:
            self.exact_estimate = float(np.max(sc)) * self.free_estimate
            return sc * Yc
        order = np.argsort(taus)
        tt = taus[order]
        sols = []
        for rtol, atol in ((1e-13, 1e-15), (2.3e-14, 1e-16)):
            # tau measured from t0: z(t) = e^{-Gamma(t)} y(tau(t) - tau(t0)) with y(0) = e^{Gamma(t0)} z0
            s_ = solve_ivp(lambda s__, y: self.N(0.0, y), (0.0, max(tt[-1], 1e-300)), y0,
                           method="DOP853", rtol=rtol, atol=atol, t_eval=tt)
            sols.append(s_.y.T)
        Y = np.empty((len(t), 3))
        Y[order] = sols[1]
        Y2 = np.empty((len(t), 3))
        Y2[order] = sols[0]
        self.exact_estimate = float(np.max(np.linalg.norm(sc * (Y - Y2), axis=-1)))
        return sc * Y


class Kepler(Problem):
    """HLW(2.1)-(2.9): q'' = -q/|q|^3, q(0) = (1-e, 0), p(0) = (0, sqrt((1+e)/(1-e)))."""
    pid = "kepler"
    params = ("e",)
    exact_available = True

    def __init__(self, e: Any, gamma: Any = 0.0) -> None:
        self.e, self.g = float(e), float(gamma)
        self.nq, self.d, self.m = 2, 4, 1.0
        self.z0 = np.array([1 - self.e, 0.0, 0.0, math.sqrt((1 + self.e) / (1 - self.e))])

    def force(self, t: Any, q: Any) -> Any:
        r2 = np.sum(q * q, axis=-1, keepdims=True)
        return -q / (r2 * np.sqrt(r2))

    def V(self, q: Any) -> Any:
        return -1.0 / np.sqrt(np.sum(q * q, axis=-1))

    def invariants(self) -> Any:   # angular momentum L = q1 p2 - q2 p1 (HLW (2.4))
        return {"angular_momentum": lambda z: z[..., 0] * z[..., 3] - z[..., 1] * z[..., 2]}

    # The momentum diagnostic: L = q x p has the law (central force); p has none (the fixed
    # centre exerts a force on the body). Scales |p| and |q||p| (docs/conventions.md).
    linear_momentum_law = False
    n = 1   # one body (the momentum round-off floors count bodies)

    def linear_momentum(self, z: Any) -> Any:
        return z[..., 2:4]

    def linear_momentum_scale(self, z: Any) -> Any:
        return np.hypot(z[..., 2], z[..., 3])

    def angular_momentum(self, z: Any) -> Any:
        return (z[..., 0] * z[..., 3] - z[..., 1] * z[..., 2])[..., None]

    def angular_momentum_scale(self, z: Any) -> Any:
        return np.hypot(z[..., 0], z[..., 1]) * np.hypot(z[..., 2], z[..., 3])

    def invariant_scales(self) -> Any:   # |q1 p2| + |q2 p1|, the magnitudes of L's terms
        return {"angular_momentum": lambda z: np.abs(z[..., 0] * z[..., 3]) + np.abs(z[..., 1] * z[..., 2])}

    def energy_scale(self, z: Any) -> Any:    # T + |V| = |p|^2/2 + 1/|q|
        return self.kinetic(z) + np.abs(self.V(z[..., :2]))

    def runge_lenz(self, z: Any) -> Any:
        """Laplace-Runge-Lenz vector A = (p2 L - q1/r, -p1 L - q2/r): the perihelion direction."""
        q1, q2, p1, p2 = z[..., 0], z[..., 1], z[..., 2], z[..., 3]
        L, r = q1 * p2 - q2 * p1, np.hypot(q1, q2)
        return np.stack([p2 * L - q1 / r, -p1 * L - q2 / r], axis=-1)

    def exact(self, t0: Any, t: Any) -> Any:
        """Kepler's equation E - e sin E = t - t0 (period 2 pi, a = 1), solved by Newton."""
        e = self.e
        M = np.atleast_1d(np.asarray(t, float)) - t0
        M = np.mod(M, 2 * math.pi)
        E = M + e * np.sin(M)
        for _ in range(60):
            dE = (E - e * np.sin(E) - M) / (1 - e * np.cos(E))
            E = E - dE
            if np.all(np.abs(dE) <= 4 * EPS * np.maximum(1.0, np.abs(E))):
                break
        s, c = np.sin(E), np.cos(E)
        Ed = 1.0 / (1 - e * c)
        b = math.sqrt(1 - e * e)
        self.exact_estimate = 0.0
        return np.stack([c - e, b * s, -s * Ed, b * c * Ed], axis=-1)


class NBodyBase(Problem):
    """N bodies in `dim` dimensions with pair potentials (HLW (2.10), (3.1)), damping -2 gamma p
    (F 2.1.2, B 3.3).  State [q_1..q_N, p_1..p_N], each block body-major."""

    def setup(self, masses: Any, q: Any, p: Any, dim: Any, gamma: Any) -> None:
        self.masses = np.asarray(masses, float)
        self.n, self.dim, self.g = len(self.masses), int(dim), float(gamma)
        self.nq = self.n * self.dim
        self.d = 2 * self.nq
        self.m = np.repeat(self.masses, self.dim)
        self.z0 = np.concatenate([np.asarray(q, float), np.asarray(p, float)])
        iu = np.triu_indices(self.n, 1)
        self.pi, self.pj = iu
        self.inc = np.zeros((len(self.pi), self.n))
        self.inc[np.arange(len(self.pi)), self.pi] = 1.0
        self.inc[np.arange(len(self.pi)), self.pj] = -1.0

    # the pair potential phi(r) and phi'(r)/r as functions of r^2, per pair (a mixin below, or
    # chosen per instance by NBody)
    pair_phi: Any
    pair_dphi_over_r: Any

    def force(self, t: Any, q: Any) -> Any:
        X = q.reshape(q.shape[:-1] + (self.n, self.dim))
        D = X[..., self.pi, :] - X[..., self.pj, :]            # q_i - q_j
        r2 = np.sum(D * D, axis=-1)
        w = self.pair_dphi_over_r(r2)[..., None] * D           # grad_{q_i} phi_ij
        Fo = -np.einsum("kn,...kd->...nd", self.inc, w)        # force on i is -w, on j +w
        return Fo.reshape(q.shape)

    def V(self, q: Any) -> Any:
        X = q.reshape(q.shape[:-1] + (self.n, self.dim))
        D = X[..., self.pi, :] - X[..., self.pj, :]
        return np.sum(self.pair_phi(np.sum(D * D, axis=-1)), axis=-1)

    def linear_momentum(self, z: Any) -> Any:
        P = z[..., self.nq:].reshape(z.shape[:-1] + (self.n, self.dim))
        return P.sum(axis=-2)

    def energy_scale(self, z: Any) -> Any:    # T + |V|, V the total pair potential
        return self.kinetic(z) + np.abs(self.V(z[..., :self.nq]))

    def linear_momentum_scale(self, z: Any) -> Any:   # sum_i |p_i|_2
        P = z[..., self.nq:].reshape(z.shape[:-1] + (self.n, self.dim))
        return np.sum(np.linalg.norm(P, axis=-1), axis=-1)

    def angular_momentum_scale(self, z: Any) -> Any:  # sum_i |q_i|_2 |p_i|_2
        X = z[..., :self.nq].reshape(z.shape[:-1] + (self.n, self.dim))
        P = z[..., self.nq:].reshape(z.shape[:-1] + (self.n, self.dim))
        return np.sum(np.linalg.norm(X, axis=-1) * np.linalg.norm(P, axis=-1), axis=-1)

    def angular_momentum(self, z: Any) -> Any:
        X = z[..., :self.nq].reshape(z.shape[:-1] + (self.n, self.dim))
        P = z[..., self.nq:].reshape(z.shape[:-1] + (self.n, self.dim))
        if self.dim == 2:
            return np.sum(X[..., 0] * P[..., 1] - X[..., 1] * P[..., 0], axis=-1)[..., None]
        return np.cross(X, P).sum(axis=-2)


class Gravity:
    G: float
    mm: Any         # m_i m_j per pair

    def pair_phi(self, r2: Any) -> Any:
        return -self.G * self.mm / np.sqrt(r2)

    def pair_dphi_over_r(self, r2: Any) -> Any:      # phi = -G mi mj / r  ->  phi'(r)/r = G mi mj / r^3
        return self.G * self.mm / (r2 * np.sqrt(r2))


class LennardJones:
    sig: float
    lje: float

    def pair_phi(self, r2: Any) -> Any:             # HLW (3.2): 4 eps ((s/r)^12 - (s/r)^6)
        s6 = (self.sig ** 2 / r2) ** 3
        return 4.0 * self.lje * (s6 * s6 - s6)

    def pair_dphi_over_r(self, r2: Any) -> Any:     # phi'(r)/r = 4 eps (-12 s^12 r^-14 + 6 s^6 r^-8)
        s6 = (self.sig ** 2 / r2) ** 3
        return 4.0 * self.lje * (-12.0 * s6 * s6 + 6.0 * s6) / r2


class NBody(NBodyBase):
    pid = "nbody"
    params = ("G", "dim", "gamma", "lj_epsilon", "lj_sigma", "masses", "p", "potential", "q")

    def __init__(self, G: Any, dim: Any, gamma: Any, lj_epsilon: Any, lj_sigma: Any, masses: Any, p: Any, potential: Any, q: Any) -> None:
        self.setup(masses, q, p, dim, gamma)
        self.G, self.lje, self.sig = float(G), float(lj_epsilon), float(lj_sigma)
        self.kind = int(potential)      # 0 gravity, 1 Lennard-Jones (docs: nbody potential)
        self.mm = self.masses[self.pi] * self.masses[self.pj]
        me: Any = self      # the mixins' pair functions on this instance's constants
        if self.kind == 0:
            self.pair_phi = lambda r2: Gravity.pair_phi(me, r2)
            self.pair_dphi_over_r = lambda r2: Gravity.pair_dphi_over_r(me, r2)
        else:
            self.pair_phi = lambda r2: LennardJones.pair_phi(me, r2)
            self.pair_dphi_over_r = lambda r2: LennardJones.pair_dphi_over_r(me, r2)


class OuterSolarSystem(Gravity, NBodyBase):
    """HLW (2.10), Table 2.2 (typed from the table), G and m0 from HLW I.2; p = m q'."""
    pid = "outer-solar-system"
    params = ("gamma",)

    def __init__(self, gamma: Any = 0.0) -> None:
        masses = [1.00000597682, 0.000954786104043, 0.000285583733151, 0.0000437273164546,
                  0.0000517759138449, 1.0 / 1.3e8]
        pos = [0, 0, 0, -3.5023653, -3.8169847, -1.5507963, 9.0755314, -3.0458353, -1.6483708,
               8.3101420, -16.2901086, -7.2521278, 11.4707666, -25.7294829, -10.8169456,
               -15.5387357, -25.2225594, -3.1902382]
        vel = [0, 0, 0, 0.00565429, -0.00412490, -0.00190589, 0.00168318, 0.00483525, 0.00192462,
               0.00354178, 0.00137102, 0.00055029, 0.00288930, 0.00114527, 0.00039677,
               0.00276725, -0.00170702, -0.00136504]
        mom = np.repeat(masses, 3) * np.array(vel)
        self.setup(masses, pos, mom, 3, gamma)
        self.G = 2.95912208286e-4
        self.mm = self.masses[self.pi] * self.masses[self.pj]


KB = 1.380658e-23


class Argon(LennardJones, NBodyBase):
    """HLW I.3: 7 argon atoms in a plane, Lennard-Jones, Table 3.1 data; p = m q'."""
    pid = "argon"
    params = ("gamma",)

    def __init__(self, gamma: Any = 0.0) -> None:
        m = 66.34e-27
        x = [0.00, 0.02, 0.34, 0.36, -0.02, -0.35, -0.31]
        y = [0.00, 0.39, 0.17, -0.21, -0.40, -0.16, 0.21]
        vx = [-30, 50, -70, 90, 80, -40, -80]
        vy = [-20, -90, -60, 40, 90, 100, -60]
        pos = np.ravel(np.column_stack([x, y]))
        mom = m * np.ravel(np.column_stack([vx, vy])).astype(float)
        self.setup([m] * 7, pos, mom, 2, gamma)
        self.lje, self.sig = 119.8 * KB, 0.341

    def temperature(self, z: Any) -> Any:   # HLW (3.8): T = sum m |v|^2 / (2 N k_B)
        p = z[..., self.nq:]
        return np.sum(p * p / self.m, axis=-1) / (2 * self.n * KB)


class LotkaVolterra(Problem):
    """HLW (1.1): u' = u (v - 2), v' = v (1 - u); first integral I = ln u - u + 2 ln v - v."""
    pid = "lotka-volterra"
    params = ("u0", "v0")
    separable = False
    canonical = False
    partitioned_halves = True   # z = (u, v), HLW (1.7): HLW's symplectic Euler (1.8) applies

    def __init__(self, u0: Any, v0: Any) -> None:
        self.d = 2
        self.z0 = np.array([u0, v0], float)

    def gamma(self, t: Any) -> Any:
        return 0.0

    def Gamma(self, t: Any) -> Any:
        return 0.0 * t

    def f(self, t: Any, z: Any) -> Any:
        u, v = z[..., 0], z[..., 1]
        return np.stack([u * (v - 2.0), v * (1.0 - u)], axis=-1)

    N = f

    def invariants(self) -> Any:
        return {"I": lambda z: np.log(z[..., 0]) - z[..., 0] + 2 * np.log(z[..., 1]) - z[..., 1]}

    def invariant_scales(self) -> Any:   # I <= 2 ln 2 - 3 < 0 on the whole domain: |I| itself
        return {"I": lambda z: np.abs(self.invariants()["I"](z))}


class KleinGordon(Problem):
    """Damped Klein-Gordon u_tt = u_xx - c u - 2 gamma u_t (B (4.3); B's gamma is ours,
    docs/pde.md 1.) on [-pi, pi), periodic, semi-discretised as in B (5.2) with the central
    second difference of B (1.14): M points x_n = -pi + n dx, dx = 2 pi / M,
        u' = v,  v' = (delta_x^2 - c) u - 2 gamma v,  (delta_x^2 u)_n = (u_{n+1} - 2 u_n + u_{n-1})/dx^2,
    a separable damped Hamiltonian system with q = u, p = v (docs/pde.md "Damped Klein-Gordon"):
    H = sum_n [v_n^2/2 + (u_{n+1} - u_n)^2/(2 dx^2) + c u_n^2/2], since -dH/du_n = (delta_x^2 u)_n - c u_n.
    Initial state: B (5.1) u = e^{-gamma t} cos(K x - W t), W = sqrt(K^2 + c - gamma^2), at t = 0:
    u = cos K x, v = u_t = -gamma cos K x + W sin K x.  Invariant: the momentum I = dx sum v delta_x u
    (B (5.7) on the grid, delta_x u = (u_{n+1} - u_{n-1})/(2 dx)), conformal with e^{-2 gamma t}
    (B (5.8), Theorem 5.1), on the scale dx sum |v| |delta_x u| (docs/pde.md)."""
    pid = "klein-gordon"
    params = ("M", "c", "gamma", "K", "exact_pde")

    def field_size(self) -> Any:   # the field u = q on the grid (field-drift, B (5.6))
        return self.M
    exact_available = True

    def __init__(self, M: Any, c: Any, gamma: Any, K: Any, exact_pde: Any = 0.0) -> None:
        """exact_pde = 1: the exact solution is the PDE's (4.3) from the trigonometric
        interpolant of the state (each mode with k^2 instead of the grid's symbol; B (5.1))."""
        if M != int(M) or K != int(K) or M < 2:
            raise TypeError("M and K must be whole numbers, M >= 2")
        self.M, self.c, self.g, self.K = int(M), float(c), float(gamma), int(K)
        self.nq, self.d, self.m = self.M, 2 * self.M, 1.0
        self.dx = 2.0 * math.pi / self.M
        self.x = -math.pi + self.dx * np.arange(self.M)
        if not self.K ** 2 + self.c > self.g ** 2:
            raise TypeError("K^2 + c must exceed gamma^2 (real W in B (5.1))")
        W = math.sqrt(self.K ** 2 + self.c - self.g ** 2)
        ph = self.K * self.x
        self.z0 = np.concatenate([np.cos(ph), -self.g * np.cos(ph) + W * np.sin(ph)])
        # Fourier symbol of -delta_x^2 + c on mode j (theta_j = 2 pi j / M = j dx):
        # omega_j^2 = c + 4 sin^2(theta_j / 2) / dx^2 (the stencil applied to e^{i j x_n})
        j = np.arange(self.M // 2 + 1)
        self.w2 = self.c + (2.0 * np.sin(0.5 * j * self.dx) / self.dx) ** 2
        if exact_pde:
            self.w2 = self.c + j.astype(float) ** 2

    def force(self, t: Any, q: Any) -> Any:
        return (np.roll(q, 1, axis=-1) - 2.0 * q + np.roll(q, -1, axis=-1)) / self.dx ** 2 - self.c * q

    def V(self, q: Any) -> Any:
        du = np.roll(q, -1, axis=-1) - q
        return np.sum(0.5 * du * du / self.dx ** 2 + 0.5 * self.c * q * q, axis=-1)

    def _dxu(self, z: Any) -> Any:
        u = z[..., :self.M]
        return (np.roll(u, -1, axis=-1) - np.roll(u, 1, axis=-1)) / (2.0 * self.dx)

    def invariants(self) -> Any:
        return {"momentum": lambda z: self.dx * np.sum(z[..., self.M:] * self._dxu(z), axis=-1)}

    def invariant_scales(self) -> Any:
        return {"momentum": lambda z: self.dx * np.sum(np.abs(z[..., self.M:]) * np.abs(self._dxu(z)), axis=-1)}

    def exact(self, t0: Any, t: Any) -> Any:
        """Exact solution of the semi-discrete system from (t0, z0): the real DFT diagonalises the
        circulant delta_x^2, each mode j is the damped oscillator a'' + 2 gamma a' + omega_j^2 a = 0:
            a(tau) = e^{-gamma tau} [a0 C + (b0 + gamma a0) S],  b(tau) = e^{-gamma tau} [b0 C - (gamma b0 + omega^2 a0) S],
        C = cos(beta tau), S = sin(beta tau)/beta, beta^2 = omega_j^2 - gamma^2 (cosh/sinh for beta^2 < 0;
        the even series of both for |beta^2 tau^2| <= 1, exact at beta = 0).  Estimate (round-off of
        this evaluation): 8 eps [(log2 M + 4) |z(t)| + |z(t)|_{(1 + |beta| tau)}], the second the
        amplitude-weighted phase error eps |beta| tau of each mode (Parseval), maximised over t."""
        tau = np.atleast_1d(np.asarray(t, float)) - t0
        M, g = self.M, self.g
        A0 = np.fft.rfft(self.z0[:M])
        B0 = np.fft.rfft(self.z0[M:])
        w = np.sqrt(self.w2)
        b2 = (w - g) * (w + g)
        x = b2[None, :] * tau[:, None] ** 2
        T = np.broadcast_to(tau[:, None], x.shape)
        # |x| <= 1: cos / cosh and sin/beta / sinh/kappa as one even series in x (14 terms: the
        # next term is below eps); else the closed forms
        C, S = np.zeros_like(x), np.zeros_like(x)
        tc, ts = np.ones_like(x), np.array(T)
        for i in range(14):
            C += tc
            S += ts
            tc = tc * (-x / ((2 * i + 1) * (2 * i + 2)))
            ts = ts * (-x / ((2 * i + 2) * (2 * i + 3)))
        be = np.sqrt(np.abs(b2))[None, :]
        osc = (np.abs(x) > 1.0) & (b2[None, :] > 0)
        ovd = (np.abs(x) > 1.0) & (b2[None, :] < 0)
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            C = np.where(osc, np.cos(be * T), np.where(ovd, np.cosh(be * T), C))
            S = np.where(osc, np.sin(be * T) / be, np.where(ovd, np.sinh(be * T) / be, S))
        e = np.exp(-g * tau)[:, None]
        A = e * (A0 * C + (B0 + g * A0) * S)
        B = e * (B0 * C - (g * B0 + self.w2 * A0) * S)
        u = np.fft.irfft(A, n=M, axis=-1)
        v = np.fft.irfft(B, n=M, axis=-1)
        Z = np.concatenate([u, v], axis=-1)
        Z[tau == 0.0] = self.z0          # z(t0) = z0 exactly
        wgt = 1.0 + be * np.abs(T)
        ph = np.sqrt(np.sum(np.fft.irfft(np.abs(A) * wgt, n=M, axis=-1) ** 2
                            + np.fft.irfft(np.abs(B) * wgt, n=M, axis=-1) ** 2, axis=-1))
        zn = np.linalg.norm(Z, axis=-1)
        self.exact_estimate = float(8 * EPS * np.max((math.log2(M) + 4) * zn + ph))
        return Z


class KleinGordonBox(KleinGordon):
    """The semi-discretisation B's box scheme (5.5) tends to as dt -> 0 (docs/pde.md): (5.5) in
    y = e^{gamma t} u is A_x^2 (D_t)^2 y = (D_x^2 + (gamma^2 - c) A_x^2)(A_t)^2 y with B (1.14)'s
    forward A_x u_n = (u_n + u_{n+1})/2, D_x u_n = (u_{n+1} - u_n)/dx, whose dt -> 0 limit is
    y'' = (L + gamma^2 - c) y, i.e.  u' = v, v' = (L - c) u - 2 gamma v  with L = A_x^{-2} D_x^2.
    L is applied by its Fourier symbol ((e^{i theta} - 1)/dx)^2 / ((1 + e^{i theta})/2)^2
    = -(2/dx)^2 tan^2(theta/2) (real: L is a symmetric circulant), nonzero denominator for odd M.
    Separable, q = u, p = v, V = sum (-u L u + c u^2)/2; the momentum dx sum v delta_x u is still
    conformal (delta_x is skew and commutes with L).  Exact solution: KleinGordon's, mode by mode
    with omega_j^2 = c + (2/dx)^2 tan^2(theta_j/2).  The real operator is applied to the real and
    imaginary parts separately so that the complex-step Jacobian stays exact."""
    pid = "klein-gordon-box"

    def __init__(self, M: Any, c: Any, gamma: Any, K: Any, exact_pde: Any = 0.0) -> None:
        super().__init__(M, c, gamma, K, exact_pde)
        if self.M % 2 == 0 or self.M < 3:
            raise TypeError("klein-gordon-box needs an odd M >= 3")
        ei = np.exp(2j * math.pi * np.arange(self.M) / self.M)
        self.l_symbol = ((ei - 1.0) / self.dx) ** 2 / (0.5 * (1.0 + ei)) ** 2
        if not exact_pde:
            j = np.arange(self.M // 2 + 1)
            self.w2 = self.c - self.l_symbol[j].real

    def _L(self, u: Any) -> Any:
        if np.iscomplexobj(u):
            return self._L(u.real) + 1j * self._L(u.imag)
        return np.real(np.fft.ifft(self.l_symbol * np.fft.fft(u, axis=-1), axis=-1))

    def force(self, t: Any, q: Any) -> Any:
        return self._L(q) - self.c * q

    def V(self, q: Any) -> Any:
        return np.sum(0.5 * (-q * self._L(q) + self.c * q * q), axis=-1)


class Burgers(Problem):
    """Modified Burgers u_t + u u_x = -2 gamma u (B (4.5)) on [-pi, pi), periodic, semi-discretised
    as in B (5.9): (5.9) couples the odd and even grid points through one half of the forward and
    backward differences over the coarse (every other point) index, which on the full grid is the
    central difference of u^2/2:  u_j' = -(u_{j+1}^2 - u_{j-1}^2) / (4 dx) - 2 gamma u_j.
    B writes it z' = D grad H - 2 gamma z: the whole state is damped with 2 gamma, so in the
    conformal form z' = N - gamma_c z of docs/conventions.md gamma_c = 2 gamma (docs/pde.md).
    Casimir C = dx sum u (B (5.13)): sum_j N_j telescopes, so C' = -2 gamma C = -gamma_c C, i.e.
    C = e^{-Gamma} C_0: half the exponent of the e^{-2 Gamma} law (invariant_rates).  Initial
    state: the standard normal density (B 5.2.1)."""
    pid = "burgers"
    params = ("M", "gamma")
    separable = False
    canonical = False

    def __init__(self, M: Any, gamma: Any) -> None:
        if M != int(M) or M < 2:
            raise TypeError("M must be a whole number >= 2")
        self.M = int(M)
        self.gB = float(gamma)
        self.g = 2.0 * self.gB           # gamma_c of the conformal form
        self.d = self.M
        self.dx = 2.0 * math.pi / self.M
        x = -math.pi + self.dx * np.arange(self.M)
        self.z0 = np.exp(-0.5 * x * x) / math.sqrt(2.0 * math.pi)
        self.invariant_rates = {"casimir": 0.5}

    def N(self, t: Any, z: Any) -> Any:
        return -(np.roll(z, -1, axis=-1) ** 2 - np.roll(z, 1, axis=-1) ** 2) / (4.0 * self.dx)

    def f(self, t: Any, z: Any) -> Any:
        return self.N(t, z) - self.g * z

    def invariants(self) -> Any:
        return {"casimir": lambda z: self.dx * np.sum(z, axis=-1)}

    def invariant_scales(self) -> Any:
        return {"casimir": lambda z: self.dx * np.sum(np.abs(z), axis=-1)}

    def pde_solution(self, t0: Any, t: Any) -> Any:
        """B (4.5)'s own solution from the Gaussian at time t (started at t0) on the grid, by
        characteristics: u = u0(xi) e^{-2 gB tau}, x = xi + u0(xi) s, s = (1 - e^{-2 gB tau})/(2 gB),
        xi by bisection (vectorised over the grid); None from the shock on (s >= 1/phi(1))."""
        tau = t - t0
        s = tau if self.gB == 0 else -math.expm1(-2.0 * self.gB * tau) / (2.0 * self.gB)
        if not tau >= 0 or s >= math.sqrt(2.0 * math.pi * math.e):
            return None
        x = -math.pi + self.dx * np.arange(self.M)
        umax = 1.0 / math.sqrt(2.0 * math.pi)

        def u0(xi: Any) -> Any:
            w = xi - 2.0 * math.pi * np.floor((xi + math.pi) / (2.0 * math.pi))
            return np.exp(-0.5 * w * w) / math.sqrt(2.0 * math.pi)

        lo, hi = x - umax * s, x.copy()
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            neg = mid + u0(mid) * s - x < 0
            lo, hi = np.where(neg, mid, lo), np.where(neg, hi, mid)
        return u0(0.5 * (lo + hi)) * math.exp(-2.0 * self.gB * tau)

    def structure(self) -> Any:
        """B's structure matrix D of (5.9) (D[j, j+1] = 1, D[j, j-1] = -1; this problem only, not
        the box or upwind semi-discretisations): the E_n law is Psi D Psi^T = e^{-2 dGamma} D."""
        if self.pid != "burgers":
            return None
        return np.roll(np.eye(self.M), 1, axis=1) - np.roll(np.eye(self.M), -1, axis=1)


class BurgersBox(Burgers):
    """The semi-discretisation B's box scheme (5.12) tends to as dt -> 0 (docs/pde.md):
    A_x (u' + 2 gamma u) + D_x (u^2/2) = 0 with B (1.14)'s forward A_x u_n = (u_n + u_{n+1})/2,
    D_x u_n = (u_{n+1} - u_n)/dx, i.e. N = -A_x^{-1} D_x (u^2/2); A_x is inverted here by its
    Fourier symbol (1 + e^{i theta_j})/2, nonzero for odd M.  The real linear operator is applied
    to the real and imaginary parts separately so that the complex-step Jacobian stays exact."""
    pid = "burgers-box"

    def __init__(self, M: Any, gamma: Any) -> None:
        super().__init__(M, gamma)
        if self.M % 2 == 0:
            raise TypeError("burgers-box needs an odd M")
        th = 2.0 * math.pi * np.arange(self.M) / self.M
        self.ax_symbol = 0.5 * (1.0 + np.exp(1j * th))

    def _ainv(self, r: Any) -> Any:
        return np.real(np.fft.ifft(np.fft.fft(r, axis=-1) / self.ax_symbol, axis=-1))

    def N(self, t: Any, z: Any) -> Any:
        w = 0.5 * z * z
        r = -(np.roll(w, -1, axis=-1) - w) / self.dx
        if np.iscomplexobj(r):
            return self._ainv(r.real) + 1j * self._ainv(r.imag)
        return self._ainv(r)


class BurgersUpwind(Burgers):
    """The semi-discretisation NSFD (4.18) tends to as dt -> 0: u_j' = -u_j (u_j - u_{j-1})/dx
    - 2 gamma u_j.  Not conservative (sum u_j (u_j - u_{j-1}) = (1/2) sum (u_j - u_{j-1})^2), so the
    Casimir law is no law of this flow: it is kept for NSFD's negative control (docs/pde.md)."""
    pid = "burgers-upwind"

    def N(self, t: Any, z: Any) -> Any:
        return -z * (z - np.roll(z, 1, axis=-1)) / self.dx


class SchrodingerBase(Problem):
    """i psi_t + psi_xx + V'(|psi|^2) psi + 2 i gamma psi = 0 (B (4.7), F = 0) on [-L, L),
    periodic, with the central second difference d2 of B (1.14) for psi_xx (the spatial operator
    of B's IF (4.15), ETD (5.27), IMP (5.28)).  Real form psi = q + i p:
        q' = -(d2 p + V' p) - 2 gamma q,   p' = d2 q + V' q - 2 gamma p,
    both halves damped with 2 gamma: gamma_c = 2 gamma in z' = N - gamma_c z (docs/pde.md), so
    quadratic invariants decay as e^{-2 Gamma} = e^{-4 gamma t} (B: 'e^{4 gamma t} I_k', (5.29)).
    Canonical up to the sign of J (q' = -dH/dp, p' = dH/dq).  Invariants from B (5.29) with
    the spectral derivative (numpy FFT here): I1 = Im dx sum conj(psi) Dx psi, I2 = dx sum |psi|^2,
    I3 = dx sum (-|Dx psi|^2 + V(|psi|^2))."""
    separable = False
    canonical = True
    params: Tuple[str, ...] = ("M", "L", "gamma", "lambda", "initial", "A", "k")
    Vp: Any         # V'(|psi|^2)

    def __init__(self, M: Any, L: Any, gamma: Any, A: Any, k: Any, initial: Any, **kw: Any) -> None:
        lam = kw.pop("lambda")
        if kw:
            raise TypeError("unknown parameters %s" % sorted(kw))
        if M != int(M) or k != int(k) or M < 2:
            raise TypeError("M and k must be whole numbers, M >= 2")
        self.M, self.L, self.gB, self.lam = int(M), float(L), float(gamma), float(lam)
        self.g = 2.0 * self.gB
        self.d, self.nq = 2 * self.M, self.M
        self.dx = 2.0 * self.L / self.M
        x = -self.L + self.dx * np.arange(self.M)
        if int(initial) == 0:     # plane wave A e^{i k (pi/L) x}
            psi = float(A) * np.exp(1j * int(k) * (math.pi / self.L) * x)
        elif int(initial) == 2:   # A sech(A x) (B Fig 5.10: 3 sech 3x)
            psi = (float(A) / np.cosh(float(A) * x)).astype(complex)
        else:                     # B Fig 5.9 as printed
            psi = np.exp(5j * x) / np.cosh(x + 1.0) + 1.5 * np.exp(-5j * x) / np.cosh(1.5 * (x - 5.0))
        self.z0 = np.concatenate([psi.real, psi.imag])
        # spectral wavenumbers (numpy order), Nyquist mode differentiated to 0
        kk = 2.0 * math.pi * np.fft.fftfreq(self.M, d=self.dx)
        if self.M % 2 == 0:
            kk[self.M // 2] = 0.0
        self.kk = kk

    def _d2(self, u: Any) -> Any:
        return (np.roll(u, 1, axis=-1) - 2.0 * u + np.roll(u, -1, axis=-1)) / self.dx ** 2

    def N(self, t: Any, z: Any) -> Any:
        q, p = z[..., :self.M], z[..., self.M:]
        vp = self.Vp(q * q + p * p)
        return np.concatenate([-(self._d2(p) + vp * p), self._d2(q) + vp * q], axis=-1)

    def f(self, t: Any, z: Any) -> Any:
        return self.N(t, z) - self.g * z

    def _psi(self, z: Any) -> Any:
        return z[..., :self.M] + 1j * z[..., self.M:]

    def _Dx(self, psi: Any) -> Any:
        return np.fft.ifft(1j * self.kk * np.fft.fft(psi, axis=-1), axis=-1)

    def mass(self, z: Any) -> Any:
        psi = self._psi(z)
        return self.dx * np.sum(np.abs(psi) ** 2, axis=-1)


class Schrodinger(SchrodingerBase):
    """Linear: V(eta) = lambda eta (B (5.19)); I1, I2, I3 all e^{-4 gamma t} (B 5.3.1 (iii))."""
    pid = "schrodinger"
    exact_available = True

    def Vp(self, eta: Any) -> Any:
        return self.lam + 0.0 * eta

    def invariants(self) -> Any:
        def I1(z: Any) -> Any:
            psi = self._psi(z)
            return self.dx * np.sum(np.imag(np.conj(psi) * self._Dx(psi)), axis=-1)

        def I3(z: Any) -> Any:
            psi = self._psi(z)
            return self.dx * np.sum(-np.abs(self._Dx(psi)) ** 2 + self.lam * np.abs(psi) ** 2, axis=-1)
        return {"momentum": I1, "mass": self.mass, "energy": I3}

    def invariant_scales(self) -> Any:
        # docs/pde.md: (dx/M) sum |k_j| |psi_hat_j|^2, I2, (dx/M) sum (k_j^2 + |lambda|) |psi_hat_j|^2
        def spec(z: Any, w: Any) -> Any:
            ph = np.abs(np.fft.fft(self._psi(z), axis=-1)) ** 2
            return self.dx / self.M * np.sum(w * ph, axis=-1)
        return {"momentum": lambda z: spec(z, np.abs(self.kk)), "mass": self.mass,
                "energy": lambda z: spec(z, self.kk ** 2 + abs(self.lam))}

    def exact(self, t0: Any, t: Any) -> Any:
        """Each DFT mode j of the semi-discrete system: psi_hat' = (i (lambda - kd_j^2) - 2 gamma) psi_hat,
        kd_j^2 = 4 sin^2(pi j / M) / dx^2 (the symbol of d2).  Estimate: 8 eps (log2 M + 4) |z| plus the
        phase round-off eps |lambda - kd^2| tau of each mode."""
        tau = np.atleast_1d(np.asarray(t, float)) - t0
        j = np.fft.fftfreq(self.M, 1.0) * self.M
        kd2 = (2.0 * np.sin(math.pi * j / self.M) / self.dx) ** 2
        c0 = np.fft.fft(self._psi(self.z0))
        lam = (1j * (self.lam - kd2))[None, :] * tau[:, None] - 2.0 * self.gB * tau[:, None]
        psi = np.fft.ifft(c0[None, :] * np.exp(lam), axis=-1)
        Z = np.concatenate([psi.real, psi.imag], axis=-1)
        Z[tau == 0.0] = self.z0
        zn = np.linalg.norm(Z, axis=-1)
        ph = np.max(np.abs(self.lam - kd2)) * np.abs(tau)
        self.exact_estimate = float(8 * EPS * np.max((math.log2(self.M) + 4 + ph) * zn))
        return Z


class NLS(SchrodingerBase):
    """Cubic: V(eta) = lambda eta^2 / 2, V' = lambda |psi|^2; I2 has a law (B 5.3.1 (ii)); I1 is
    listed with the PDE's law, which the semi-discrete flow keeps only up to the aliasing of
    |psi|^2 psi (B Fig 5.9's R1, docs/pde.md)."""
    pid = "nls"

    def Vp(self, eta: Any) -> Any:
        return self.lam * eta

    def momentum(self, z: Any) -> Any:
        psi = self._psi(z)
        return self.dx * np.sum(np.imag(np.conj(psi) * self._Dx(psi)), axis=-1)

    def invariants(self) -> Any:
        return {"momentum": self.momentum, "mass": self.mass}

    def invariant_scales(self) -> Any:
        def s1(z: Any) -> Any:
            ph = np.abs(np.fft.fft(self._psi(z), axis=-1)) ** 2
            return self.dx / self.M * np.sum(np.abs(self.kk) * ph, axis=-1)
        return {"momentum": s1, "mass": self.mass}


class NLSDriven(NLS):
    """Damped driven NLS (B (4.7) with F(t) = Gamma e^{i(omega0 t + alpha)}, 5.3.2.3, Fig 5.10):
    i psi_t = -psi_xx - V' psi - 2 i gamma psi + F, so psi_t gains -i F:
        q' += Gamma sin(omega0 t + alpha),   p' += -Gamma cos(omega0 t + alpha).
    No invariant follows a law.  probe: |psi| at the grid point nearest x = 0 (B's amplitude)."""
    pid = "nls-driven"
    params = SchrodingerBase.params + ("Gamma", "omega0", "alpha")

    def __init__(self, Gamma: Any, omega0: Any, alpha: Any, **kw: Any) -> None:
        super().__init__(**kw)
        self.G, self.w0, self.al = float(Gamma), float(omega0), float(alpha)

    def N(self, t: Any, z: Any) -> Any:
        out = super().N(t, z)
        th = self.w0 * np.asarray(t) + self.al   # t may be the stages' times (s, 1) of an RK step
        out[..., :self.M] += self.G * np.sin(th)
        out[..., self.M:] += -self.G * np.cos(th)
        return out

    def invariants(self) -> Any:
        return {}

    def invariant_scales(self) -> Any:
        return {}

    def probe(self, z: Any) -> float:
        n = min(max(int(round(self.L / self.dx)), 0), self.M - 1)
        return float(math.hypot(z[n], z[self.M + n]))


_CLASSES: Tuple[Any, ...] = (Oscillator, Pendulum, DrivenPendulum, Hill, RigidBody, Kepler, NBody,
                             OuterSolarSystem, Argon, LotkaVolterra, KleinGordon, KleinGordonBox, Burgers,
                             BurgersBox, BurgersUpwind, Schrodinger, NLS, NLSDriven)
PROBLEMS: Dict[str, Any] = {c.pid: c for c in _CLASSES}


def make_problem(pid: str, params: Dict[str, Any]) -> Any:
    cls = PROBLEMS[pid]
    kw = {}
    for k, v in params.items():
        kw[k] = v if isinstance(v, list) else float(v)
    return cls(**kw)
