"""Methods of the independent cross-check, written from the papers and docs/conventions.md,
never from dampsym's C++ sources or coefficient tables.  How each method's coefficients are
obtained is stated at its definition (and summarised in COEFFICIENT_SOURCES).

make_stepper(method, problem, h) returns step(t, z) -> (z1, newton_iterations); z may carry
leading batch axes and may be complex (the complex step of the step map gives its exact
Jacobian; implicit stages are then iterated until both the real and the imaginary parts have
converged, i.e. the implicit-function-theorem derivative).
"""
from typing import Any, Dict, List, Optional
import math
from fractions import Fraction

import mpmath
import numpy as np
import scipy.linalg as sla

EPS = np.finfo(float).eps


class NotApplicable(Exception):
    pass


class SolveFailed(Exception):
    pass


# ----------------------------------------------------------------------------------------
# Gauss-Legendre collocation tableaux from the roots of the Legendre polynomial (30 digits)
# ----------------------------------------------------------------------------------------
def gauss_tableau(s: Any) -> Any:
    """c_i = (1 + x_i)/2 with x_i the roots of P_s; A_ij = int_0^{c_i} l_j (collocation
    condition sum_j A_ij c_j^{k-1} = c_i^k / k, k = 1..s); b_j = int_0^1 l_j.  Solved in 30-digit
    mpmath and rounded once (BS; B Example 2.1)."""
    mpmath.mp.dps = 30
    P = lambda x: mpmath.legendre(s, x)
    xs = [mpmath.findroot(P, mpmath.cos(mpmath.pi * (i + 0.75) / (s + 0.5))) for i in range(s)]
    c = sorted([(1 + x) / 2 for x in xs])
    Vt = mpmath.matrix(s, s)
    for k in range(s):
        for j in range(s):
            Vt[k, j] = c[j] ** k
    A = np.zeros((s, s))
    for i in range(s):
        rhs = mpmath.matrix([c[i] ** (k + 1) / (k + 1) for k in range(s)])
        row = mpmath.lu_solve(Vt, rhs)
        A[i] = [float(v) for v in row]
    rhs = mpmath.matrix([mpmath.mpf(1) / (k + 1) for k in range(s)])
    b = np.array([float(v) for v in mpmath.lu_solve(Vt, rhs)])
    return A, b, np.array([float(v) for v in c])


GAUSS = {s: gauss_tableau(s) for s in (1, 2, 3)}
# wrong-coefficient hook for the negative test: XC_PERTURB_GAUSS=s,i,j,delta perturbs A_ij
import os as _os  # noqa: E402
if _os.environ.get("XC_PERTURB_GAUSS"):
    _s, _i, _j, _d = _os.environ["XC_PERTURB_GAUSS"].split(",")
    GAUSS[int(_s)][0][int(_i), int(_j)] += float(_d)

EXPLICIT_RK = {   # (A, b, c) exact rationals
    "euler": ([[0]], [1], [0]),                                           # HLW (1.4)
    "heun": ([[0, 0], [1, 0]], [0.5, 0.5], [0, 1]),                       # B (3.8), trapezoid
    "rk3": ([[0, 0, 0], [0.5, 0, 0], [-1, 2, 0]], [1 / 6, 2 / 3, 1 / 6], [0, 0.5, 1]),  # Kutta
    "rk4": ([[0, 0, 0, 0], [0.5, 0, 0, 0], [0, 0.5, 0, 0], [0, 0, 1, 0]],
            [1 / 6, 1 / 3, 1 / 3, 1 / 6], [0, 0.5, 0.5, 1]),             # classical
}

COEFFICIENT_SOURCES = {
    "euler": "HLW (1.4): A = 0, b = 1",
    "heun": "B (3.8): explicit trapezoid, typed rationals",
    "rk3": "Kutta's third order (F ch.4): c = (0, 1/2, 1), b = (1/6, 2/3, 1/6), typed rationals",
    "rk4": "classical RK4 tableau, typed rationals",
    "implicit-euler": "HLW (1.5): A = b = c = 1",
    "implicit-midpoint": "HLW (1.6) = 1-stage Gauss, from the Legendre root",
    "gauss1": "Legendre root of P_1, collocation conditions solved in 30-digit mpmath",
    "gauss2": "Legendre roots of P_2, collocation conditions solved in 30-digit mpmath",
    "gauss3": "Legendre roots of P_3, collocation conditions solved in 30-digit mpmath",
    "glifrk1": "B (2.5) on the 1-stage Gauss tableau above; factors e^{-(Gamma(t+c h)-Gamma(t))}",
    "glifrk2": "B (2.5) on the 2-stage Gauss tableau above (cf. B (2.12))",
    "glifrk3": "B (2.5) on the 3-stage Gauss tableau above",
    "cimp": "F (2.3): integrating factor e^{+-x/2} around the implicit midpoint (= B (2.11))",
    "etdrk2": "B (2.13): a = sinh(x/2)/x, b = -expm1(-x)/x, phi = e^{-x/2}, phi0 = e^{-x}",
    "cse-if": "B (2.18) with B's gamma h = 2x",
    "cse-etd": "B (2.19) with B's gamma h = 2x: coefficient -expm1(-2x)/(2x)",
    "csv1": "F (2.12)",
    "csv2": "F (2.16)",
    "csv1-perk": "B (2.20) tableau pair with B's gamma h = 2x",
    "csv2-perk": "B (2.21) tableau pair with B's gamma h = 2x and the e^{-x/2} factor restored "
                 "in A^_21, A^_22, b^ (docs/conventions.md §6)",
    "etdprk2": "B (2.22) tableau pair with B's gamma h = 2x",
    "symplectic-euler": "HLW (1.8) with u = p implicit (damping at p_{n+1}, closed form), v = q explicit",
    "symplectic-euler-adjoint": "adjoint of HLW (1.8): q explicit with p_n, p explicit with q_{n+1}",
    "stormer-verlet": "HLW (3.6)-(3.7): Psi^{ie}_{h/2} o Psi^{ei}_{h/2} on the full vector field",
    "symplectic-euler-partitioned": "HLW (1.8) on (1.7): u_{n+1} = u_n + h a(u_{n+1}, v_n), "
                                    "v_{n+1} = v_n + h b(u_{n+1}, v_n)",
    "glm4": "Butcher's G-symplectic GLM (BS): A, U, B, V and the starting method typed from "
            "the slides' surds (3 +- sqrt 3)/6 etc., sqrt evaluated in double",
    "kg-box": "B (5.5) u-form with B (1.14)'s forward A_x, D_x by their Fourier symbols; the start "
              "and the v estimate as docs/pde.md states them",
}


# ----------------------------------------------------------------------------------------
# complex-step Jacobian of a vector field
# ----------------------------------------------------------------------------------------
def jac_cs(F: Any, t: Any, z: Any) -> Any:
    d = z.shape[-1]
    zz = np.asarray(z, float)[None, :] + 1e-30j * np.eye(d)
    return (np.imag(F(t, zz)) / 1e-30).T


def _converged(dZ: Any, Z: Any, last: Any, it: Any) -> Any:
    """Round-off convergence of an implicit iteration, separately for the real and imaginary
    parts: returns (done, measure)."""
    dr, zr = np.max(np.abs(dZ.real)), np.max(np.abs(Z.real))
    if np.iscomplexobj(Z):
        di, zi = np.max(np.abs(dZ.imag)), np.max(np.abs(Z.imag))
        m = max(dr / max(zr, 1e-300), di / max(zi, 1e-300) if zi > 0 else 0.0)
    else:
        m = dr / max(zr, 1e-300)
    return settled(m, last, it, dr == 0.0), m


def settled(m: float, last: float, it: int, zero: bool = False) -> bool:
    """The round-off test of an implicit iteration from its relative update m (and the
    previous one, last): m <= 2 eps (or a zero update), or from the third iteration on an
    update below 1e-11 that stopped decreasing (m >= last): the round-off floor.  (Stopping
    at m >= last / 2 left a slowly contracting simplified iteration -- a large step -- up to
    theta/(1 - theta) 1e-11 short of the solution, theta = m / last.)"""
    return bool(m <= 2 * EPS or zero or (it >= 3 and m >= last and m <= 1e-11))


# ----------------------------------------------------------------------------------------
# Generic exponential / integrating-factor / plain RK kernel on a field G (N or f):
#   Z_i = Phi_i z + h sum_j A_ij G(t + c_j h, Z_j);  z1 = phi0 z + h sum_i b_i G(t + c_i h, Z_i)
# ----------------------------------------------------------------------------------------
def rk_family_step(G: Any, coef: Any, h: Any, implicit: bool) -> Any:
    cache: Dict[Any, Any] = {}

    def stages(t: Any, z: Any) -> Any:
        """The implicit stages (..., s, d) and the iterations: simplified Newton, the matrix
        I - h A (x) J(t, z) refreshed every 8 steps, when the coefficients change (time-dependent
        gamma) or after a slow solve; the iteration is run to round-off, so the reuse changes
        nothing but the iteration count."""
        Phi, A, b, phi0, c = coef(t)
        s, d = len(b), z.shape[-1]
        tt = (t + c * h)[:, None]
        Zp = Phi[:, None] * z[..., None, :]
        key = (A.tobytes(), bool(np.iscomplexobj(z)))
        if cache.get("key") != key or cache["age"] >= 8 or cache["slow"]:
            zr = z.real if np.iscomplexobj(z) else z
            J = jac_cs(G, t, zr.reshape(-1, d)[0])
            cache.update(key=key, age=0, slow=False,
                         Minv=np.linalg.inv(np.eye(s * d) - h * np.kron(A, J)))
        cache["age"] += 1
        Minv = cache["Minv"]
        Z, it = simplified_newton(G, A, h, tt, Zp, Zp + h * c[:, None] * G(t, z)[..., None, :], Minv)
        cache["slow"] = it > 6
        return Z, it

    def step(t: Any, z: Any) -> Any:
        Phi, A, b, phi0, c = coef(t)
        s = len(b)
        tt = (t + c * h)[:, None]
        if not implicit:
            Zp = Phi[:, None] * z[..., None, :]
            Z = np.array(Zp)
            K = np.zeros_like(Zp)
            for i in range(s):
                Z[..., i, :] = Zp[..., i, :] + h * np.einsum("j,...jd->...d", A[i, :i], K[..., :i, :])
                K[..., i, :] = G(tt[i], Z[..., i, :])
            return phi0 * z + h * np.einsum("i,...id->...d", b, K), 0
        try:
            Z, it = stages(t, z)
        except SolveFailed:
            cache["slow"] = True
            return full_newton_fallback(G, coef, h, t, z)
        return phi0 * z + h * np.einsum("i,...id->...d", b, G(tt, Z)), it
    if implicit:   # for step Jacobians (xrun.step_jacobian), see complex_step_polished
        setattr(step, "complex_step", lambda t, z: complex_step_polished(G, coef, h, t, z, stages))
    return step


def simplified_newton(G: Any, A: Any, h: Any, tt: Any, Zp: Any, Z: Any, Minv: Any) -> Any:
    """Z = Zp + h (A (x) I) G(tt, Z) for a batch (..., s, d) by simplified Newton from Z with the
    inverse matrix Minv, to the round-off test: (Z, iterations); SolveFailed on a non-finite
    iterate or after 100 iterations."""
    s, d = Z.shape[-2:]
    last, it = math.inf, 0
    while True:
        it += 1
        R = Z - Zp - h * np.einsum("ij,...jd->...id", A, G(tt, Z))
        dZ = (R.reshape(-1, s * d) @ Minv.T).reshape(R.shape)
        Z = Z - dZ
        if not np.all(np.isfinite(Z)):
            raise SolveFailed("non-finite Newton iterate")
        done, last = _converged(dZ, Z, last, it)
        if done:
            return Z, it
        if it > 100:
            raise SolveFailed("Newton did not converge")


def complex_step_polished(G: Any, coef: Any, h: Any, t: Any, z: Any, stages: Any) -> Any:
    """A step of a complex-step batch (a real state + i eps e_k: every member has the same real
    part) whose stages are then polished by two full Newton updates, the Jacobian at their real
    part: the simplified iteration's round-off test stops a slowly contracting iteration (a large
    step) with the real part up to ~1e-11 off, and the derivatives inherit it; the first update
    makes the real part exact (quadratic convergence), the second the imaginary parts (exact for
    the Jacobian they are updated with).  Cost: 2 s Jacobians and two solves for the batch."""
    Phi, A, b, phi0, c = coef(t)
    s, d = len(b), z.shape[-1]
    tt = (t + c * h)[:, None]
    Zp = Phi[:, None] * z[..., None, :]
    try:
        Z = stages(t, z)[0]
    except SolveFailed:
        return full_newton_fallback(G, coef, h, t, z)
    for _ in range(2):
        x = Z.reshape(-1, s, d)[0].real
        M = np.eye(s * d) - h * np.block([[A[i, j] * jac_cs(G, tt[j, 0], x[j]) for j in range(s)]
                                          for i in range(s)])
        R = Z - Zp - h * np.einsum("ij,...jd->...id", A, G(tt, Z))
        Z = Z - np.linalg.solve(M, R.reshape(-1, s * d).T).T.reshape(Z.shape)
    if not np.all(np.isfinite(Z)):
        raise SolveFailed("non-finite Newton iterate (polish)")
    return phi0 * z + h * np.einsum("i,...id->...d", b, G(tt, Z)), 0


def full_newton_step(G: Any, coef: Any, h: Any, t: Any, z: Any) -> Any:
    """One step of the RK family (rk_family_step's stage equations, predictor and round-off
    test) by full Newton: the stage Jacobians at every iterate.  The fallback where the
    simplified iteration fails (a large step, a stale matrix; dampsym's one-stage kernels iterate
    full Newton): both converge to round-off, so a step either takes is the same step.  Returns
    (z1, iterations); SolveFailed when full Newton fails too."""
    Phi, A, b, phi0, c = coef(t)
    s, d = len(b), z.shape[-1]
    tt = t + c * h
    Zp = Phi[:, None] * z[None, :]
    Z = Zp + h * c[:, None] * G(t, z)[None, :]

    def newton_update(Z: Any) -> Any:
        K = np.stack([G(tt[j], Z[j]) for j in range(s)])
        R = Z - Zp - h * (A @ K)
        Zr = Z.real if np.iscomplexobj(Z) else Z     # a complex step: the real part's Jacobian
        Jb = np.eye(s * d) - h * np.block([[A[i, j] * jac_cs(G, tt[j], Zr[j]) for j in range(s)]
                                           for i in range(s)])
        return np.linalg.solve(Jb, R.reshape(-1)).reshape(s, d)

    last, it = math.inf, 0
    while True:
        it += 1
        dZ = newton_update(Z)
        Z = Z - dZ
        if not np.all(np.isfinite(Z)):
            raise SolveFailed("Newton did not converge")
        done, last = _converged(dZ, Z, last, it)
        if done:
            break
        if it > 100:
            raise SolveFailed("Newton did not converge")
    if np.iscomplexobj(Z):
        # the imaginary part (a derivative) is exact for the Jacobian at the iterate it was
        # updated from: once more, from the converged real part (else it keeps that iterate's
        # error, up to the 1e-11 the round-off test allows)
        Z = Z - newton_update(Z)
    K = np.stack([G(tt[j], Z[j]) for j in range(s)])
    return phi0 * z + h * (b @ K), it


def full_newton_fallback(G: Any, coef: Any, h: Any, t: Any, z: Any) -> Any:
    """full_newton_step for each state of a batch (the complex-step directions of a step
    Jacobian too: their real parts converge by full Newton, their imaginary parts, linear in the
    real part's Jacobian, with them): (z1, the most iterations)."""
    flat = np.asarray(z).reshape(-1, z.shape[-1])
    done = [full_newton_step(G, coef, h, t, zz) for zz in flat]
    return np.stack([x for x, _ in done]).reshape(np.shape(z)), max(it for _, it in done)


def plain_coef(A: Any, b: Any, c: Any) -> Any:
    A, b, c = np.array(A, float), np.array(b, float), np.array(c, float)
    one = np.ones(len(b))
    return lambda t: (one, A, b, 1.0, c)


def ifrk_coef(prob: Any, alpha: Any, beta: Any, c: Any, h: Any) -> Any:
    """B (2.5): Phi_i = e^{-x(c_i h)}, A_ij = alpha_ij e^{x(c_j h) - x(c_i h)},
    b_i = beta_i e^{x(c_i h) - x(h)}, phi0 = e^{-x(h)}, x(tau) = Gamma(t+tau) - Gamma(t)."""
    def coef(t: Any) -> Any:
        xc = np.array([dGamma(prob, t, ci * h) for ci in c])
        xh = dGamma(prob, t, h)
        return (np.exp(-xc), alpha * np.exp(xc[None, :] - xc[:, None]),
                beta * np.exp(xc - xh), math.exp(-xh), c)
    return coef


def dGamma(prob: Any, t: Any, tau: Any) -> Any:
    """Gamma(t + tau) - Gamma(t) without cancellation: gamma tau for constant gamma; for
    gamma = eps cos(2t)/2, (eps/4)(sin 2(t+tau) - sin 2t) = (eps/2) cos(2t + tau) sin(tau)."""
    if getattr(prob, "t_dependent_gamma", False):
        return 0.5 * prob.eps * math.cos(2 * t + tau) * math.sin(tau)
    return prob.g * tau


def _sinhc(x: Any) -> Any:      # sinh(x/2)/x  -> 1/2
    return 0.5 if x == 0 else math.sinh(0.5 * x) / x


def _phi1(x: Any) -> Any:       # (1 - e^{-x})/x -> 1
    return 1.0 if x == 0 else -math.expm1(-x) / x


# ----------------------------------------------------------------------------------------
# partitioned exponential RK (B (2.14)) on q' = dT(p), p' = force(q) (damping in the phi's);
# explicit tableau pairs evaluated by repeated sweeps (the dependency graph is acyclic, so
# 2s+1 sweeps give exactly the direct evaluation).
# ----------------------------------------------------------------------------------------
def perk_step(prob: Any, coef: Any, h: Any, chat: Any) -> Any:
    nq = prob.nq

    def step(t: Any, z: Any) -> Any:
        ph, Ah, bh, ph0, pt, At, bt, pt0 = coef(t)
        s = len(bh)
        q, p = z[..., :nq], z[..., nq:]
        Q = ph[:, None] * q[..., None, :]
        P = pt[:, None] * p[..., None, :]
        tt = (t + np.asarray(chat) * h)[:, None]
        for _ in range(2 * s + 1):
            Gv = prob.force(tt, Q)
            P = pt[:, None] * p[..., None, :] + h * np.einsum("ij,...jd->...id", At, Gv)
            Fv = prob.dT(P)
            Q = ph[:, None] * q[..., None, :] + h * np.einsum("ij,...jd->...id", Ah, Fv)
        Gv = prob.force(tt, Q)
        Fv = prob.dT(P)
        q1 = ph0 * q + h * np.einsum("i,...id->...d", bh, Fv)
        p1 = pt0 * p + h * np.einsum("i,...id->...d", bt, Gv)
        return np.concatenate([q1, p1], axis=-1), 0
    return step


def csv1_perk_coef(prob: Any, h: Any) -> Any:
    """B (2.20) with B's gamma h = 2x (x = our Gamma increment over the step)."""
    def coef(t: Any) -> Any:
        x = dGamma(prob, t, h)
        e = math.exp(-x)           # e^{-gamma_B h / 2}
        Ah = np.array([[0, 0], [0.5, 0.5]])
        At = np.array([[0.5, 0], [0.5, 0]])
        return (np.ones(2), Ah, np.array([0.5, 0.5]), 1.0,
                np.array([e, e]), At, np.array([0.5 * e, 0.5 * e]), e * e)
    return coef


def csv2_perk_coef(prob: Any, h: Any) -> Any:
    """B (2.21) with B's gamma h = 2x and A^_21 = A^_22 = b^_1 = b^_2 = 2 e^{-gB h/4}/(4 - gB h)
    (the factor docs/conventions.md §6 restores)."""
    def coef(t: Any) -> Any:
        X = 2.0 * dGamma(prob, t, h)            # B's gamma h
        e4, e2 = math.exp(-X / 4), math.exp(-X / 2)
        a = 2.0 / (4.0 - X) * e4
        Ah = np.array([[0, 0], [a, a]])
        ph = np.array([1.0, (4 + X) / (4 - X) * e2])
        At = np.array([[2 / (4 + X), 0], [2 / (4 + X), 0]])
        pt = np.array([4 / (4 + X) * e4] * 2)
        bt = np.array([(4 - X) / (4 + X) * e4 / 2, e4 / 2])
        return (ph, Ah, np.array([a, a]), (4 + X) / (4 - X) * e2, pt, At, bt, (4 - X) / (4 + X) * e2)
    return coef


def etdprk2_coef(prob: Any, h: Any) -> Any:
    """B (2.22) with B's gamma h = 2x: q by Lobatto IIIA, p by the ETD tableau."""
    def coef(t: Any) -> Any:
        X = 2.0 * dGamma(prob, t, h)
        e2 = math.exp(-X / 2)
        a = 0.5 if X == 0 else -math.expm1(-X / 2) / X
        Ah = np.array([[0, 0], [0.5, 0.5]])
        At = np.array([[a, 0], [a, 0]])
        return (np.ones(2), Ah, np.array([0.5, 0.5]), 1.0,
                np.array([e2, e2]), At, np.array([0.5 * e2, 0.5 * e2]), math.exp(-X))
    return coef


# ----------------------------------------------------------------------------------------
# hand-written schemes
# ----------------------------------------------------------------------------------------
def csv1_step(prob: Any, h: Any) -> Any:
    """F (2.12): p_half = e^{-x} p - (h/2) grad V(q); q1 = q + h grad T(p_half);
    p1 = e^{-x} (p_half - (h/2) grad V(q1)); x = gamma h (Gamma increment for time-dependent gamma)."""
    nq = prob.nq

    def step(t: Any, z: Any) -> Any:
        # Strang splitting: damping flow over each half step, e^{-2 (Gamma(t+h/2) - Gamma(t))}
        # before and e^{-2 (Gamma(t+h) - Gamma(t+h/2))} after (= e^{-gamma h} for constant gamma)
        e1 = math.exp(-2.0 * dGamma(prob, t, 0.5 * h))
        e2 = math.exp(-2.0 * dGamma(prob, t + 0.5 * h, 0.5 * h))
        q, p = z[..., :nq], z[..., nq:]
        ph = e1 * p + 0.5 * h * prob.force(t, q)
        q1 = q + h * prob.dT(ph)
        p1 = e2 * (ph + 0.5 * h * prob.force(t + h, q1))
        return np.concatenate([q1, p1], axis=-1), 0
    return step


def csv2_step(prob: Any, h: Any) -> Any:
    """F (2.16): (1 + x/2) p_half = e^{-x/2} p - (h/2) grad V(q);
    (1 - x/2) q1 = e^{-x/2} [ (1 + x/2) e^{-x/2} q + h grad T(p_half) ];
    p1 = e^{-x/2} [ (1 - x/2) p_half - (h/2) grad V(q1) ];  defined for x != 2 (F (3.22): the
    stable region reversed for x > 2); at x = 2 the q-update is inf (the run diverges, as
    dampsym's csv2.hpp)."""
    nq = prob.nq

    def step(t: Any, z: Any) -> Any:
        x = dGamma(prob, t, h)
        a, b, e = 1 + 0.5 * x, 1 - 0.5 * x, math.exp(-0.5 * x)
        q, p = z[..., :nq], z[..., nq:]
        ph = (e * p + 0.5 * h * prob.force(t, q)) / a
        with np.errstate(divide="ignore", invalid="ignore"):
            q1 = e * (a * e * q + h * prob.dT(ph)) / np.float64(b)
        p1 = e * (b * ph + 0.5 * h * prob.force(t + h, q1))
        return np.concatenate([q1, p1], axis=-1), 0
    return step


def cse_step(prob: Any, h: Any, etd: bool) -> Any:
    """B (2.18) (IF) / (2.19) (ETD) with B's gamma h = 2x:
    p1 = e^{-2x} p - h c grad V(q), c = 1 (IF) or -expm1(-2x)/(2x) (ETD); q1 = q + h grad T(p1)."""
    nq = prob.nq

    def step(t: Any, z: Any) -> Any:
        X = 2.0 * dGamma(prob, t, h)
        c = (1.0 if X == 0 else -math.expm1(-X) / X) if etd else 1.0
        q, p = z[..., :nq], z[..., nq:]
        p1 = math.exp(-X) * p + h * c * prob.force(t, q)
        q1 = q + h * prob.dT(p1)
        return np.concatenate([q1, p1], axis=-1), 0
    return step


def symplectic_euler_step(prob: Any, h: Any, adjoint: bool) -> Any:
    """HLW (1.8) with u = p (implicit Euler), v = q (explicit Euler) on q' = dT(p),
    p' = force(t, q) - 2 gamma p: p1 = p + h (force(q) - 2 gamma p1) (linear in p1, solved in
    closed form), q1 = q + h dT(p1).  The adjoint swaps the roles:
    q1 = q + h dT(p), p1 = p + h (force(q1) - 2 gamma p)."""
    nq = prob.nq

    def step(t: Any, z: Any) -> Any:
        q, p = z[..., :nq], z[..., nq:]
        g = prob.gamma(t)
        if not adjoint:
            p1 = (p + h * prob.force(t, q)) / (1 + 2 * g * h)
            q1 = q + h * prob.dT(p1)
        else:
            q1 = q + h * prob.dT(p)
            # p's explicit Euler at the q stage's time t + h (implicit Euler's c = 1)
            p1 = p + h * (prob.force(t + h, q1) - 2 * prob.gamma(t + h) * p)
        return np.concatenate([q1, p1], axis=-1), 0
    return step


def symplectic_euler_partitioned_step(prob: Any, h: Any) -> Any:
    """HLW (1.8) on a partitioned system (1.7) z = (u, v) (the halves of the state) in the plain
    form: u1 = u + h a(t + h, u1, v) by Newton with the complex-step Jacobian of a in u, then
    v1 = v + h b(t + h, u1, v)."""
    if not getattr(prob, "partitioned_halves", False):
        raise NotApplicable("symplectic-euler-partitioned needs a problem declared as halves (u, v)")

    def step(t: Any, z: Any) -> Any:
        z = np.asarray(z, float)
        m = z.shape[-1] // 2
        u, v = z[:m], z[m:]
        U, last = u.copy(), np.inf
        for it in range(1, 60):
            zz = np.concatenate([U, v])
            R = U - u - h * prob.f(t + h, zz)[:m]
            J = np.eye(m) - h * jac_cs(prob.f, t + h, zz)[:m, :m]
            dU = np.linalg.solve(J, -R)
            U = U + dU
            if not np.all(np.isfinite(U)):
                raise SolveFailed("non-finite Newton iterate")
            done, last = _converged(dU, U, last, it)
            if done:
                return np.concatenate([U, v + h * prob.f(t + h, np.concatenate([U, v]))[m:]]), it
        raise SolveFailed("Newton did not converge")
    return step


def stormer_verlet_step(prob: Any, h: Any) -> Any:
    """HLW (3.7): Psi^{ie}_{h/2} o Psi^{ei}_{h/2} on the full field b(q, p) = force - 2 gamma p:
    p_half = p + h/2 b(q, p_half) (linear in p_half), q1 = q + h dT(p_half),
    p1 = p_half + h/2 b(q1, p_half)."""
    nq = prob.nq

    def step(t: Any, z: Any) -> Any:
        q, p = z[..., :nq], z[..., nq:]
        g = prob.gamma(t)
        ph = (p + 0.5 * h * prob.force(t, q)) / (1 + g * h)
        q1 = q + h * prob.dT(ph)
        # the second half's field at t + h, its damping too (Lobatto IIIA's c = (0, 1))
        p1 = ph + 0.5 * h * (prob.force(t + h, q1) - 2 * prob.gamma(t + h) * ph)
        return np.concatenate([q1, p1], axis=-1), 0
    return step


# Butcher's G-symplectic GLM (BS; docs/conventions.md §3)
R3 = math.sqrt(3.0)
GLM_A = np.array([[(3 + R3) / 6, 0], [-R3 / 3, (3 + R3) / 6]])
GLM_U = np.array([[1, -(3 + 2 * R3) / 3], [1, (3 + 2 * R3) / 3]])
GLM_B = np.array([[0.5, 0.5], [0.5, -0.5]])
GLM_V = np.array([[1, 0], [0, -1.0]])
GLM_A0 = np.array([[(3 + R3) / 6, 0], [-(3 + R3) / 3, (3 + R3) / 6]])
GLM_S = np.array([(R3 - 1) / 8, (1 - R3) / 8])


# glm4 as coefficients (BS): [A U; B V], stage times c = A e, and the starting method, whose
# stages take y_0 (U0 = e) and give y^[0] = (y_0, h S F) (V0 = (1, 0), B0 = (0; S))
GLM4: Dict[str, Any] = dict(A=GLM_A, U=GLM_U, B=GLM_B, V=GLM_V, c=GLM_A.sum(axis=1), A0=GLM_A0,
                            U0=np.ones(2), B0=np.array([[0.0, 0.0], GLM_S]), V0=np.array([1.0, 0.0]),
                            c0=GLM_A0.sum(axis=1))
# General linear methods of the user's method files (verify/xmethodfile.py): id -> coefficients
# as GLM4 (keys A, U, B, V, c, A0, U0, B0, V0, c0; s0 = 0 starting stages: A0 empty)
FILE_GLM: Dict[str, Dict[str, Any]] = {}


def glm_coefficients(method: str) -> Dict[str, Any]:
    return FILE_GLM.get(method, GLM4)


def lower_triangular(A: Any) -> bool:
    """Stages that can be solved one after the other (A_ij = 0 for j > i)."""
    return bool(np.all(np.triu(np.asarray(A, float), 1) == 0.0))


class GLM:
    """A general linear method (BD (2.3), BS): Y = h (A (x) I) F + (U (x) I) y^[n-1],
    y^[n] = h (B (x) I) F + (V (x) I) y^[n-1], F_i = f(t + c_i h, Y_i).  State: the r values
    y^[n] (r, d); start() applies the starting method.  Lower-triangular A (glm4): the stages one
    after the other, each by simplified Newton (matrix I - h a_ii J refreshed every 8 steps), an
    explicit stage (a_ii = 0) by one evaluation; a full A by simplified Newton on all stages
    (matrix at the predictor), as rk_family_step."""

    def __init__(self, prob: Any, h: Any, coefs: Optional[Dict[str, Any]] = None) -> None:
        self.prob, self.h = prob, h
        self.k = coefs if coefs is not None else GLM4
        self.main = self._stages(self.k["A"], self.k["c"])
        self.start0 = self._stages(self.k["A0"], self.k["c0"]) if len(self.k["c0"]) else None

    def _stages(self, A: Any, c: Any) -> Any:
        if not lower_triangular(A):
            return self._coupled(A, c)
        prob, h, s = self.prob, self.h, len(c)
        cache: Dict[str, Any] = {"age": 99}
        first = next((i for i in range(s) if A[i, i] != 0.0), s)   # the first implicit stage

        def inverses(t: Any, y: Any) -> List[Any]:
            d = y.shape[-1]
            zr = (y.real if np.iscomplexobj(y) else y).reshape(-1, d)[0]
            J = jac_cs(prob.f, t, zr)
            return [np.linalg.inv(np.eye(d) - h * A[k, k] * J) for k in range(s)]

        def solve(t: Any, Yp: Any) -> Any:   # Y = Yp + h A f(t + c h, Y), stage by stage
            Y = np.array(Yp)
            K = np.zeros_like(Yp)
            its = 0
            for i in range(s):
                base = Yp[..., i, :] + h * np.einsum("j,...jd->...d", A[i, :i], K[..., :i, :])
                if A[i, i] == 0.0:
                    Y[..., i, :] = base
                    K[..., i, :] = prob.f(t + c[i] * h, base)
                    continue
                if i == first:             # simplified Newton matrices refreshed every 8 steps
                    if cache["age"] >= 8:
                        cache.update(age=0, Minv=inverses(t + c[i] * h, base))
                    cache["age"] += 1
                y, it = self._newton_stage(t, c, i, A[i, i], base, cache, inverses)
                its += it
                Y[..., i, :] = y
                K[..., i, :] = prob.f(t + c[i] * h, y)
            return Y, K, its
        return solve

    def _newton_stage(self, t: Any, c: Any, i: int, aii: Any, base: Any, cache: Dict[str, Any],
                      inverses: Any) -> Any:
        """Stage i: y = base + h a_ii f(t + c_i h, y) by simplified Newton from y = base; a
        matrix from an earlier step that no longer contracts (a time-dependent field at a large
        step) is refreshed at this stage and the iteration restarted."""
        prob, h = self.prob, self.h
        y, Minv = base.copy(), cache["Minv"][i]
        last, it, its, fresh = math.inf, 0, 0, cache["age"] == 1
        while True:
            it += 1
            R = y - base - h * aii * prob.f(t + c[i] * h, y)
            dy = R @ Minv.T
            y = y - dy
            done, last = _converged(dy, y, last, it)
            if done:
                return y, its + it
            if (it > 30 or not np.all(np.isfinite(y))) and not fresh:
                cache.update(age=1, Minv=inverses(t + c[i] * h, base))
                Minv, y, last, fresh = cache["Minv"][i], base.copy(), math.inf, True
                its += it
                it = 0
                continue
            if it > 100:
                raise SolveFailed("GLM stage did not converge")

    def _coupled(self, A: Any, c: Any) -> Any:
        """All stages at once: Z = Yp + h (A (x) I) F(Z) by simplified Newton, the matrix
        I - h A (x) J at the predictor of each step."""
        prob, h, s = self.prob, self.h, len(c)

        def solve(t: Any, Yp: Any) -> Any:
            d = Yp.shape[-1]
            tt = (t + c * h)[:, None]
            zr = (Yp.real if np.iscomplexobj(Yp) else Yp).reshape(-1, s, d)[0, 0]
            Minv = np.linalg.inv(np.eye(s * d) - h * np.kron(A, jac_cs(prob.f, t, zr)))
            Z, it = simplified_newton(prob.f, A, h, tt, Yp, np.array(Yp), Minv)
            return Z, prob.f(tt, Z), it
        return solve

    def start(self, t: Any, y0: Any) -> Any:
        """y^[0]_k = V0_k y_0 + h sum_j B0_kj F_j of the starting method's stages from y_0."""
        k = self.k
        r = len(k["V0"])
        if self.start0 is None:
            return np.stack([k["V0"][j] * y0 for j in range(r)], axis=-2)
        Yp = np.stack([u * y0 for u in k["U0"]], axis=-2)
        _, K, _ = self.start0(t, Yp)
        return np.stack([self.h * np.einsum("i,...id->...d", k["B0"][j], K) + k["V0"][j] * y0
                         for j in range(r)], axis=-2)

    def step(self, t: Any, yv: Any) -> Any:
        k = self.k
        Yp = np.einsum("ij,...jd->...id", k["U"], yv)
        Y, K, its = self.main(t, Yp)
        return (self.h * np.einsum("ij,...jd->...id", k["B"], K)
                + np.einsum("ij,...jd->...id", k["V"], yv)), its


# right-hand-side (force or field) evaluations per step as the formulas are written (FSAL not
# assumed): s stages for explicit RK; two force evaluations for F (2.12), F (2.16), B (2.20)-
# (2.22) and HLW (3.6); one for B (2.18), (2.19) and HLW (1.8)
EXPLICIT_EVALS = {"euler": 1, "heun": 2, "rk3": 3, "rk4": 4, "csv1": 2, "csv2": 2, "csv1-perk": 2,
                  "csv2-perk": 2, "etdprk2": 2, "cse-if": 1, "cse-etd": 1, "symplectic-euler": 1,
                  "symplectic-euler-adjoint": 1, "stormer-verlet": 2,
                  "burgers-csv": 2, "burgers-nsfd": 1, "kg-box": 1}

IMPLICIT = {"implicit-euler", "implicit-midpoint", "gauss1", "gauss2", "gauss3", "glifrk1",
            "glifrk2", "glifrk3", "cimp", "etdrk2", "glm4", "symplectic-euler-partitioned"}
NEEDS_SEPARABLE = {"csv1", "csv2", "csv1-perk", "csv2-perk", "etdprk2", "cse-if", "cse-etd",
                   "symplectic-euler", "symplectic-euler-adjoint", "stormer-verlet"}
NEEDS_CONFORMAL = {"cimp", "glifrk1", "glifrk2", "glifrk3", "etdrk2"}
# Tableaux of the user's method files (verify/xmethodfile.py registers them) other than explicit
# plain ones (those join EXPLICIT_RK): id -> (form "plain" | "if", A, b, c)
FILE_RK: Dict[str, Any] = {}
# Partitioned pairs of the user's method files: id -> (q tableau (A, b, c), p tableau (A, b, c))
FILE_PRK: Dict[str, Any] = {}
# Exponential tableaux of the user's method files (B (2.7), (2.10)): id -> (c, A, phi, b, phi0),
# every coefficient a function of the damping argument (xmethodfile.phi_terms: sums of
# coef * NAME(arg * x)); partitioned pairs (B (2.14)): id -> (q tableau, p tableau)
FILE_ERK: Dict[str, Any] = {}
FILE_PERK: Dict[str, Any] = {}
# the claims a method file declares (its linear-momentum factor, B Table 3.1, follows from them)
FILE_CLAIMS: Dict[str, Any] = {}
# every method file's definition as registered (id -> its family and coefficients, repr): part of
# the key of our cached results (xcache), so that a file edited between runs is recomputed
FILE_DEFS: Dict[str, str] = {}
# General linear methods (BS): a step maps r values y^[n] (here r = 2), not the state alone, so a
# run from a mid-run state needs y^[n], the one-step map of the state has no Jacobian to test for
# conformal symplecticity, and the Newton counts follow the GLM's own stages.
MULTIVALUE = {"glm4"}
# B's Burgers schemes (5.10), (5.12), (4.18), each on its own semi-discretisation (docs/pde.md)
BURGERS_B = {"burgers-csv": "burgers", "burgers-box": "burgers-box", "burgers-nsfd": "burgers-upwind"}
# B's NLS schemes IF (4.15), ETD (5.27), IMP (5.28) on the NLS family (docs/pde.md)
NLS_B = {"nls-if", "nls-etd", "nls-imp"}
NLS_FAMILY = {"schrodinger", "nls", "nls-driven"}
# B's Klein-Gordon box scheme (5.5) on its own semi-discretisation klein-gordon-box: a scheme on
# two levels (u^i, u^{i+1}) whose stepper keeps the earlier level, so a run restarted from a
# mid-run state (u, v) is another computation, not a round-off kick of this one (docs/pde.md)
TWO_LEVEL = {"kg-box"}
METHODS = set(EXPLICIT_RK) | IMPLICIT | NEEDS_SEPARABLE | set(BURGERS_B) | NLS_B | TWO_LEVEL


def nls_b_step(method: str, prob: Any, h: Any) -> Any:
    """B's NLS schemes written from B (4.15), (5.27), (5.28) (gamma = B's gamma = prob.gB), with
    X = e^{g h} psi^{i+1}, Y = e^{-g h} psi^i (IMP: X = psi^{i+1}, Y = psi^i), Phi = (X + Y)/2:
        IF  (4.15): i (X - Y)/h + d2 Phi + V'(|Phi|^2) Phi = F(t + h/2)
        ETD (5.27): the same with i (X - Y)/h multiplied by kappa = g h / sinh(g h)
        IMP (5.28): i (X - Y)/h + d2 Phi + V'(|Phi|^2) Phi + 2 i g Phi = F(t + h/2)
    With X = 2 Phi - Y: (2 i kappa/h + d2 [+ 2 i g]) Phi = 2 i kappa Y/h - V'(|Phi|^2) Phi + F, the
    linear operator inverted by FFT (d2's symbol -4 sin^2(pi j/M)/dx^2), the nonlinear term by
    fixed-point iteration to round-off; psi^{i+1} = e^{-g h}(2 Phi - Y) (IMP: 2 Phi - Y).
    F = Gamma e^{i(omega0 t + alpha)} for nls-driven, else 0.  Batch axes allowed."""
    if prob.pid not in NLS_FAMILY:
        raise NotApplicable("%s applies to the NLS problems only" % method)
    g, M, dx = prob.gB, prob.M, prob.dx
    imp = method == "nls-imp"
    kappa = g * h / math.sinh(g * h) if (method == "nls-etd" and g != 0.0) else 1.0
    ey = 1.0 if imp else math.exp(-g * h)
    c2 = 2j * kappa / h
    d2 = -4.0 * np.sin(math.pi * np.arange(M) / M) ** 2 / dx ** 2
    sym = c2 + (2j * g if imp else 0.0) + d2
    driven = prob.pid == "nls-driven"

    def step(t: Any, z: Any) -> Any:
        z = np.asarray(z, float)
        Y = ey * (z[..., :M] + 1j * z[..., M:])
        F = prob.G * np.exp(1j * (prob.w0 * (t + 0.5 * h) + prob.al)) if driven else 0.0
        Phi = Y.copy()
        last = np.inf
        for it in range(1, 201):
            r = c2 * Y - prob.Vp(np.abs(Phi) ** 2) * Phi + F
            new = np.fft.ifft(np.fft.fft(r, axis=-1) / sym, axis=-1)
            m = np.max(np.abs(new - Phi)) / max(np.max(np.abs(new)), 1e-300)
            Phi = new
            if m <= 2 * EPS or (it >= 3 and m >= 0.5 * last and m <= 1e-11):
                psi = ey * (2.0 * Phi - Y) if not imp else 2.0 * Phi - Y
                return np.concatenate([psi.real, psi.imag], axis=-1), it
            last = m
        raise SolveFailed("%s: fixed-point iteration did not converge" % method)
    return step


def burgers_b_step(method: str, prob: Any, h: Any) -> Any:
    """B's Burgers schemes written from B (5.10), (5.12), (4.18) (gamma = B's gamma = prob.gB):
    (5.10) on the even/odd split (v = even, w = odd grid points, flux = delta_x(u^2/2)):
        w^{i+1/2} = e^{-g h} w^i - (h/2) f_w(u),  v^{i+1} = e^{-g h}(e^{-g h} v^i - h f_v(u)),
        w^{i+1} = e^{-g h}(w^{i+1/2} - (h/2) f_w(u));
    (5.12) D_t^g A_x u + (1/2) D_x (A_t^g u)^2 = 0 in X = e^{g h} u^{i+1}, Y = e^{-g h} u^i, dense
        Newton;
    (4.18) (u^{i+1} - u^i)/phi + u^i (u^{i+1}_n - u^{i+1}_{n-1})/dx = -2 g u^i,
        phi = (1 - e^{-2 g h})/(2 g), dense linear solve.
    (5.10) takes batch axes and complex steps; (5.12) and (4.18) one real state."""
    if prob.pid != BURGERS_B[method]:
        raise NotApplicable("%s applies to problem %s only" % (method, BURGERS_B[method]))
    g, dx, M = prob.gB, prob.dx, prob.M
    e = math.exp(-g * h)
    if method == "burgers-csv":
        ev, od = np.arange(0, M, 2), np.arange(1, M, 2)

        def flux(u: Any) -> Any:
            return (np.roll(u, -1, axis=-1) ** 2 - np.roll(u, 1, axis=-1) ** 2) / (4.0 * dx)

        def step_csv(t: Any, z: Any) -> Any:
            u = np.array(z)                       # batch axes and complex steps allowed
            u[..., od] = e * u[..., od] - 0.5 * h * flux(u)[..., od]
            u[..., ev] = e * (e * u[..., ev] - h * flux(u)[..., ev])
            u[..., od] = e * (u[..., od] - 0.5 * h * flux(u)[..., od])
            return u, 0
        return step_csv
    if method == "burgers-nsfd":
        phi = -math.expm1(-2.0 * g * h) / (2.0 * g) if g != 0.0 else h
        back = np.roll(np.eye(M), -1, axis=1)    # row n picks X_{n-1}

        def step_nsfd(t: Any, z: Any) -> Any:
            u = np.asarray(z, float)
            A = np.diag(1.0 / phi + u / dx) - np.diag(u / dx) @ back
            return np.linalg.solve(A, u * (1.0 / phi - 2.0 * g)), 1
        return step_nsfd
    S = np.roll(np.eye(M), 1, axis=1)              # (S x)_n = x_{n+1}

    def step(t: Any, z: Any) -> Any:
        Y = e * np.asarray(z, float)
        X = Y.copy()
        last = np.inf
        for it in range(1, 60):
            W = 0.5 * (X + Y)
            F = (X + S @ X - Y - S @ Y) / (2.0 * h) + (S @ (W * W) - W * W) / (2.0 * dx)
            J = (np.eye(M) + S) / (2.0 * h) + (S * W[None, :] - np.diag(W)) / (2.0 * dx)
            dX = np.linalg.solve(J, -F)
            X = X + dX
            done, last = _converged(dX, X, last, it)
            if done:
                return e * X, it
        raise SolveFailed("burgers-box: Newton did not converge")
    return step


def kg_box_step(prob: Any, h: Any) -> Any:
    """B's box scheme (5.5) written from B's u-form (B section 5.1.2; docs/pde.md), gamma = B's:
        (D_t^{g/2})^2 A_x^2 u - D_x^2 (A_t^{g/2})^2 u = (g^2 - c) A_x^2 (A_t^{g/2})^2 u,
    D_t^a u^i = (e^{a h} u^{i+1} - e^{-a h} u^i)/h, A_t^a u^i = (e^{a h} u^{i+1} + e^{-a h} u^i)/2, and
    B (1.14)'s forward A_x, D_x applied by their Fourier symbols (1 + e^{i theta})/2 and
    (e^{i theta} - 1)/dx, so each step solves for u^{i+2} mode by mode (E = e^{g h}):
        E [ax2/h^2 - S/4] X = ax2 (2 u^{i+1} - u^i/E)/h^2 + S (2 u^{i+1} + u^i/E)/4,  S = dx2 + (g^2 - c) ax2.
    Start (docs/pde.md): the same equation at i = -1 with the central value y^{-1} = y^1 - 2h y'(0)
    in y = e^{g t} u, y'(0) = v0 + g u0:  E [ax2/h^2 - S/4] u^1 = ax2 (u0 + h y'0)/h^2 + S (u0 - h y'0)/4.
    The state returned is (u^{i+1}, v^{i+1}) with v from docs/pde.md's second-order formulas in y:
    first step v^1 = (2 (E u^1 - u^0)/h - y'(0))/E - g u^1 (trapezoidal rule), later steps
    v^{i+1} = (3 u^{i+1} - 4 u^i/E + u^{i-1}/E^2)/(2h) - g u^{i+1} (one-sided three-level difference).
    The stepper keeps the previous level: on the first call it starts from z = (u0, v0), on later
    calls the incoming u is u^{i+1} (dampsym's convention for kg-box).  One real state (no batch)."""
    if prob.pid != "klein-gordon-box":
        raise NotApplicable("kg-box applies to problem klein-gordon-box only")
    M, dx, g, c = prob.M, prob.dx, prob.g, prob.c
    ei = np.exp(2j * math.pi * np.arange(M) / M)
    ax2 = (0.5 * (1.0 + ei)) ** 2
    S = ((ei - 1.0) / dx) ** 2 + (g * g - c) * ax2
    E = math.exp(g * h)
    lhs = E * (ax2 / h ** 2 - S / 4.0)
    levels: Dict[str, Any] = {}

    def solve(r: Any) -> Any:
        return np.real(np.fft.ifft(r / lhs))

    def step(t: Any, z: Any) -> Any:
        z = np.asarray(z, float)
        u, v = z[:M], z[M:]
        F = np.fft.fft
        if "prev" not in levels:
            yd = v + g * u
            u1 = solve(ax2 * F(u + h * yd) / h ** 2 + S * F(u - h * yd) / 4.0)
            v1 = (2.0 * (E * u1 - u) / h - yd) / E - g * u1
            levels["prev"] = u
            return np.concatenate([u1, v1]), 0
        up = levels["prev"]
        u2 = solve(ax2 * F(2.0 * u - up / E) / h ** 2 + S * F(2.0 * u + up / E) / 4.0)
        v2 = (3.0 * u2 - 4.0 * u / E + up / E ** 2) / (2.0 * h) - g * u2
        levels["prev"] = u
        return np.concatenate([u2, v2]), 0
    return step


def file_coef(method: str, prob: Any, h: Any) -> Any:
    """(G, coef) of a method file's tableau: the plain form, or B (2.5) on the conformal form."""
    form, A, b, c = FILE_RK[method]
    A, b, c = np.array(A, float), np.array(b, float), np.array(c, float)
    if form == "if":
        if not hasattr(prob, "N"):
            raise NotApplicable("%s (integrating factor) needs the conformal form" % method)
        return prob.N, ifrk_coef(prob, A, b, c, h)
    return prob.f, plain_coef(A, b, c)


def prk_schedule(Aq: Any, Ap: Any, damped: bool = True) -> Any:
    """An order in which the stages of a partitioned pair can be computed one after the other
    (docs/method-files.md "explicit"): Q_i once every P_j with a_ij != 0 is known; P_i once
    every Q_j with a^_ij != 0 (F_j = F(Q_j)) and every other P_j with a^_ij != 0 is known (its
    own damping term a^_ii 2 gamma_i P_i is linear: solved in closed form; `damped` False: an
    exponential pair, whose damping is in its factors, has no P_j terms).  [("q"|"p", i)], or
    None when the stages are coupled (then solved together by Newton)."""
    s = len(Aq)
    known: Dict[Any, bool] = {}
    order: List[Any] = []
    while len(order) < 2 * s:
        ready = [(k, i) for k in ("q", "p") for i in range(s) if (k, i) not in known and all(
            known.get(dep, False) for dep in
            ([("p", j) for j in range(s) if Aq[i][j] != 0] if k == "q" else
             [("q", j) for j in range(s) if Ap[i][j] != 0] + [("p", j) for j in range(s)
                                                              if damped and Ap[i][j] != 0 and j != i]))]
        if not ready:
            return None
        known[ready[0]] = True
        order.append(ready[0])
    return order


def prk_file_step(prob: Any, h: Any, method: str) -> Any:
    """A partitioned pair on the separable form q' = dT(p), p' = F(t, q) - 2 gamma p (docs/
    method-files.md "partitioned-rk": stage times from the q tableau's c):
        Q_i = q + h sum_j a_ij dT(P_j),   P_i = p + h sum_j a^_ij (F(t_j, Q_j) - 2 gamma_j P_j),
        q1 = q + h sum_i b_i dT(P_i),     p1 = p + h sum_i b^_i (F(t_i, Q_i) - 2 gamma_i P_i),
    stage by stage when prk_schedule finds an order, else by Newton on all stages at once."""
    if not getattr(prob, "separable", False):
        raise NotApplicable("%s needs a separable q/p problem" % method)
    (Aq, bq, cq), (Ap, bp, _) = FILE_PRK[method]
    Aq, bq, cq, Ap, bp = (np.array(x, float) for x in (Aq, bq, cq, Ap, bp))
    order, nq, s = prk_schedule(Aq, Ap), prob.nq, len(bq)

    def finish(t: Any, q: Any, p: Any, Q: Any, P: Any) -> Any:
        F = [prob.force(t + cq[i] * h, Q[i]) - 2 * prob.gamma(t + cq[i] * h) * P[i] for i in range(s)]
        q1 = q + h * sum(bq[i] * prob.dT(P[i]) for i in range(s) if bq[i] != 0)
        p1 = p + h * sum(bp[i] * F[i] for i in range(s) if bp[i] != 0)
        return np.concatenate([q1, p1], axis=-1)

    def staged(t: Any, z: Any) -> Any:
        q, p = z[..., :nq], z[..., nq:]
        Q, P, F = [q] * s, [p] * s, [q] * s
        g = [prob.gamma(t + cq[i] * h) for i in range(s)]
        for kind, i in order:
            if kind == "q":
                Q[i] = q + h * sum(Aq[i, j] * prob.dT(P[j]) for j in range(s) if Aq[i, j] != 0)
                F[i] = prob.force(t + cq[i] * h, Q[i])
                continue
            acc = p + h * sum(Ap[i, j] * (F[j] - (2 * g[j] * P[j] if j != i else 0))
                              for j in range(s) if Ap[i, j] != 0)
            P[i] = acc / (1 + 2 * h * Ap[i, i] * g[i])
        return finish(t, q, p, Q, P), 0

    def residual(t: Any, q: Any, p: Any, Q: Any, P: Any) -> Any:
        rq = [Q[i] - q - h * sum(Aq[i, j] * prob.dT(P[j]) for j in range(s) if Aq[i, j] != 0) for i in range(s)]
        rp = [P[i] - p - h * sum(Ap[i, j] * (prob.force(t + cq[j] * h, Q[j]) - 2 * prob.gamma(t + cq[j] * h) * P[j])
                                 for j in range(s) if Ap[i, j] != 0) for i in range(s)]
        return np.concatenate(rq + rp)

    def coupled(t: Any, z: Any) -> Any:
        """Simplified Newton: the stage Jacobian I - h [[0, A (x) T''], [A^ (x) F', -A^ (x) 2 gamma]]
        with T'' and F' at the step's start (the field's complex-step Jacobian), iterated to
        round-off (xmethods._converged)."""
        q, p = z[:nq], z[nq:]
        Jf = jac_cs(prob.f, t, np.asarray(z.real, float))
        Tpp, Fq = Jf[:nq, nq:], Jf[nq:, :nq] + 0.0
        g = np.array([prob.gamma(t + cq[j] * h) for j in range(s)])
        M = np.eye(2 * s * nq)
        M[:s * nq, s * nq:] -= h * np.kron(Aq, Tpp)
        M[s * nq:, :s * nq] -= h * np.kron(Ap, Fq)
        M[s * nq:, s * nq:] += h * np.kron(Ap * 2 * g[None, :], np.eye(nq))
        Minv = np.linalg.inv(M)
        Q, P, last = [q] * s, [p] * s, np.inf
        for it in range(1, 101):
            dX = -(Minv @ residual(t, q, p, Q, P))
            Q = [Q[i] + dX[i * nq:(i + 1) * nq] for i in range(s)]
            P = [P[i] + dX[(s + i) * nq:(s + i + 1) * nq] for i in range(s)]
            X = np.concatenate(Q + P)
            if not np.all(np.isfinite(X)):
                raise SolveFailed("non-finite Newton iterate")
            done, last = _converged(dX, X, last, it)
            if done:
                return finish(t, q, p, Q, P), it
        raise SolveFailed("Newton did not converge")

    def batched(t: Any, z: Any) -> Any:
        z = np.asarray(z)
        if z.ndim == 1:
            return coupled(t, z)
        flat = z.reshape(-1, z.shape[-1])
        outs = [coupled(t, zz) for zz in flat]
        return np.stack([o[0] for o in outs]).reshape(z.shape), max(o[1] for o in outs)
    return staged if order is not None else batched


def _phi_k(z: float, k: int) -> float:
    """phi_k(z) = (e^z - sum_{m<k} z^m/m!)/z^k by its series for |z| < 1 (no cancellation)."""
    if abs(z) < 1.0:
        term, total = 1.0 / math.factorial(k), 0.0
        for m in range(30):
            total += term
            term *= z / (m + k + 1)
        return total
    return (math.expm1(z) - sum(z ** m / math.factorial(m) for m in range(1, k))) / z ** k


PHI = {"exp": math.exp, "phi0": math.exp, "phi1": lambda z: _phi_k(z, 1), "phi2": lambda z: _phi_k(z, 2),
       "phi3": lambda z: _phi_k(z, 3), "sinhc": lambda z: math.sinh(z) / z if z != 0.0 else 1.0}


def phi_value(terms: Any, x: float) -> float:
    """A coefficient of an exponential tableau at the damping argument x: sum coef * NAME(arg x)
    (NAME None: the constant coef)."""
    return float(sum(c if name is None else c * PHI[name](a * x) for c, name, a in terms))


def exp_tableau_at(tab: Any, x: float) -> Any:
    """(Phi, A, b, phi0, c) of an exponential tableau (c, A, phi, b, phi0) at x."""
    c, A, phi, b, phi0 = tab
    return (np.array([phi_value(e, x) for e in phi]), np.array([[phi_value(e, x) for e in row] for row in A]),
            np.array([phi_value(e, x) for e in b]), phi_value(phi0, x), np.array(c, float))


def file_erk_coef(method: str, prob: Any, h: Any) -> Any:
    """(G, coef) of an exponential-rk file: on the conformal form N, at x = Gamma(t + h) - Gamma(t)
    (docs/method-files.md: our gamma; re-evaluated every step for a time-dependent gamma)."""
    if not hasattr(prob, "N"):
        raise NotApplicable("%s (exponential) needs the conformal form" % method)
    tab = FILE_ERK[method]
    memo: Dict[float, Any] = {}

    def coef(t: Any) -> Any:
        x = dGamma(prob, t, h)
        if x not in memo:
            memo.clear()
            memo[x] = exp_tableau_at(tab, x)
        return memo[x]
    return prob.N, coef


def file_perk_coef(method: str, prob: Any, h: Any) -> Any:
    """perk_step's coefficients of a partitioned-exponential-rk file at B's argument
    x_B = 2 (Gamma(t + h) - Gamma(t)) (B's gamma is twice ours: docs/method-files.md)."""
    qt, pt = FILE_PERK[method]

    def coef(t: Any) -> Any:
        x = 2.0 * dGamma(prob, t, h)
        ph, Ah, bh, ph0, _ = exp_tableau_at(qt, x)
        pp, At, bt, pt0, _ = exp_tableau_at(pt, x)
        return ph, Ah, bh, ph0, pp, At, bt, pt0
    return coef


def make_stepper(method: str, prob: Any, h: Any) -> Any:
    if method in FILE_ERK:
        G, coef = file_erk_coef(method, prob, h)
        return rk_family_step(G, coef, h, implicit=method in IMPLICIT)
    if method in FILE_PERK:
        if not getattr(prob, "separable", False):
            raise NotApplicable("%s needs a separable q/p problem" % method)
        return perk_step(prob, file_perk_coef(method, prob, h), h, np.array(FILE_PERK[method][0][0], float))
    if method in FILE_PRK:
        return prk_file_step(prob, h, method)
    if method in FILE_RK:
        G, coef = file_coef(method, prob, h)
        return rk_family_step(G, coef, h, implicit=method in IMPLICIT)
    if method == "kg-box":
        return kg_box_step(prob, h)
    if method in BURGERS_B:
        return burgers_b_step(method, prob, h)
    if method in NLS_B:
        return nls_b_step(method, prob, h)
    if method in NEEDS_SEPARABLE and not prob.separable:
        raise NotApplicable("%s needs a separable q/p problem" % method)
    if method in EXPLICIT_RK:
        A, b, c = EXPLICIT_RK[method]
        return rk_family_step(prob.f, plain_coef(A, b, c), h, implicit=False)
    if method == "implicit-euler":
        return rk_family_step(prob.f, plain_coef([[1.0]], [1.0], [1.0]), h, implicit=True)
    if method in ("implicit-midpoint", "gauss1", "gauss2", "gauss3"):
        A, b, c = GAUSS[1 if method == "implicit-midpoint" else int(method[-1])]
        return rk_family_step(prob.f, plain_coef(A, b, c), h, implicit=True)
    if method in ("cimp", "glifrk1", "glifrk2", "glifrk3"):
        A, b, c = GAUSS[1 if method == "cimp" else int(method[-1])]
        return rk_family_step(prob.N, ifrk_coef(prob, A, b, c, h), h, implicit=True)
    if method == "etdrk2":
        def coef(t: Any) -> Any:
            x = dGamma(prob, t, h)
            return (np.array([math.exp(-0.5 * x)]), np.array([[_sinhc(x)]]),
                    np.array([_phi1(x)]), math.exp(-x), np.array([0.5]))
        return rk_family_step(prob.N, coef, h, implicit=True)
    if method == "csv1":
        return csv1_step(prob, h)
    if method == "csv2":
        return csv2_step(prob, h)
    if method in ("cse-if", "cse-etd"):
        return cse_step(prob, h, etd=method == "cse-etd")
    if method == "csv1-perk":
        return perk_step(prob, csv1_perk_coef(prob, h), h, (0.0, 1.0))
    if method == "csv2-perk":
        return perk_step(prob, csv2_perk_coef(prob, h), h, (0.0, 1.0))
    if method == "etdprk2":
        return perk_step(prob, etdprk2_coef(prob, h), h, (0.0, 1.0))
    if method in ("symplectic-euler", "symplectic-euler-adjoint"):
        return symplectic_euler_step(prob, h, adjoint=method.endswith("adjoint"))
    if method == "stormer-verlet":
        return stormer_verlet_step(prob, h)
    if method == "symplectic-euler-partitioned":
        return symplectic_euler_partitioned_step(prob, h)
    raise KeyError(method)
