"""Stability sweep and h^4 trace coefficient of the oscillator's one-step matrix, recomputed
independently for the cross-check (docs/conventions.md §5; F (3.10)-(3.23)).

The one-step matrix M(gamma, h) is OUR step map applied to the basis vectors (xmethods'
steppers, or refmath's plain-float ones where it has the method; both ours).  Over the grid
gamma_k = from + k step, h_j = from + j step (both ends included) of the case's
`stability_sweep`, per method:

  F_emp(g, h)    F's condition |1/2 tr M| < e^{-g h} (F calls this stability; §5);
  F_formula      the same condition from F's closed forms (cimp: omega > gamma, F (3.12);
                 csv1(-perk): 1 - sech gh < h^2 w^2/2 < 1 + sech gh, F (3.17); csv2(-perk):
                 g^2 sech(gh/2) < w^2 < 4 sech(gh/2)/h^2 for gh < 2, reversed for gh > 2, F (3.22));
  PB             power-bounded: rho(M) < 1 - 8 eps, or rho <= 1 + 8 eps with two distinct
                 eigenvalues (|l1 - l2| > 1e-7), the rule of the per-run stability metric;
  PB_R           (explicit RK) the same from the stability polynomial R(z) = sum_k z^k b^T A^{k-1} 1;
                 (implicit RK on the plain form: implicit Euler, the Gauss methods) from
                 R(z) = 1 + z b^T (I - z A)^{-1} 1
                 of OUR tableau at the eigenvalues h lambda of the oscillator's matrix.

Metrics: F_violations = #not F_emp; mismatch_points = #(F_emp != F_formula);
violations_omega_gt_gamma = #not F_emp where omega > gamma; power_bounded_violations = #not PB;
power_mismatch_points = #(PB != PB_R); per gamma row: h_F_empirical, h_F_formula,
h_power_unbounded = the first h of the row where the condition fails (none: null),
max_half_trace_err = max_h |1/2 tr M - e^{-gh} cos(beta h)| (cosh for beta^2 < 0);
max_boundary_mismatch_cells = max over rows of |j(h_F_empirical) - j(h_F_formula)| (a row
without failure counts as j = number of h points); max_power_boundary_mismatch_cells the same
for PB against PB_R; first_row = the first gamma row's gamma, h_F_empirical, h_power_unbounded.

Where M does not exist (csv2 at gamma h = 2: F (2.16) divides by 1 - gamma h/2) F's condition
counts as not satisfied (as F (3.22), which excludes gamma h = 2) and PB is not evaluated.

Round-off ties: a point whose |1/2 tr M| lies within 16 eps e^{-gh} of e^{-gh} (or whose rho
lies within 16 eps of 1) is decided by the last bits of M, which differ between two correct
implementations.  Each count is returned with the number of such tie points (a reported count
agrees within it), each first-failure step with its range when ties are flipped either way.
"""
from typing import Any, Dict, List, Tuple
import math

import numpy as np

from . import refmath
from . import xcache
from . import xmethods as xm
from . import xproblems as xp

EPS = np.finfo(float).eps
FORMULA = {"cimp": "cimp", "csv1": "csv1", "csv1-perk": "csv1", "csv2": "csv2", "csv2-perk": "csv2"}


def axis(spec: Dict[str, Any]) -> Any:
    a, b, s = (float(x) for x in spec)
    n = int(math.floor((b - a) / s * (1 + 1e-12) + 1e-9)) + 1
    return a + s * np.arange(n)


def one_step_matrix(method: str, w: Any, g: Any, h: Any) -> Any:
    if method in ("csv2", "csv2-perk") and g * h > 2:
        # F (2.16) beyond gamma h = 2 (F (3.22) "reversed")
        prob = xp.make_problem("oscillator", {"omega": w, "gamma": g, "q0": 1.0, "p0": 0.0})
        step = xm.csv2_step(prob, h) if method == "csv2" else \
            xm.perk_step(prob, xm.csv2_perk_coef(prob, h), h, (0.0, 1.0))
        return step(0.0, np.eye(2))[0].T
    if method in refmath.METHODS:
        return refmath.one_step_matrix(method, refmath.Oscillator(w, g, 1.0, 0.0), h)
    prob = xp.make_problem("oscillator", {"omega": w, "gamma": g, "q0": 1.0, "p0": 0.0})
    step = xm.make_stepper(method, prob, h)
    Z1, _ = step(0.0, np.eye(2))
    return Z1.T


PERK = {"csv1-perk": xm.csv1_perk_coef, "csv2-perk": xm.csv2_perk_coef, "etdprk2": xm.etdprk2_coef}


def row_matrices(method: str, w: Any, g: Any, H: Any) -> Any:
    """One-step matrices of a whole gamma row at once (nh, 2, 2), or None (then point by point):
    the symplectic Euler pair and Stormer-Verlet are xmethods' own steppers called with an array
    of step sizes (their formulas only multiply and divide by h); the partitioned exponential
    methods are xmethods.perk_step's sweeps written over a batch of step sizes, with xmethods'
    coefficient functions evaluated at each h."""
    prob = xp.make_problem("oscillator", {"omega": w, "gamma": g, "q0": 1.0, "p0": 0.0})
    hb = np.asarray(H, float)[:, None, None]
    Z = np.broadcast_to(np.eye(2), (len(H), 2, 2))
    with np.errstate(all="ignore"):
        if method in ("symplectic-euler", "symplectic-euler-adjoint", "stormer-verlet"):
            step = (xm.stormer_verlet_step(prob, hb) if method == "stormer-verlet" else
                    xm.symplectic_euler_step(prob, hb, adjoint=method.endswith("adjoint")))
            return np.swapaxes(step(0.0, Z)[0], -1, -2)
        if method in PERK:
            co: List[Any] = []
            for h in H:
                if method == "csv2-perk" and abs(2 * g * h - 4.0) == 0.0:
                    co.append(None)
                    continue
                co.append(PERK[method](prob, h)(0.0))
            good = np.array([c is not None for c in co])
            tmpl = next(c for c in co if c is not None)
            C = [np.stack([np.asarray(c[k] if c is not None else np.full_like(np.asarray(tmpl[k], float), np.nan),
                                      float) for c in co]) for k in range(8)]
            ph, Ah, bh, ph0, pt, At, bt, pt0 = C
            s = bh.shape[1]
            h = np.asarray(H, float)
            q, p = Z[..., :1], Z[..., 1:]                         # (nh, basis, 1)
            Q = ph[:, None, :, None] * q[:, :, None, :]
            P = pt[:, None, :, None] * p[:, :, None, :]
            for _ in range(2 * s + 1):
                Gv = prob.force(0.0, Q)
                P = pt[:, None, :, None] * p[:, :, None, :] + h[:, None, None, None] * np.einsum("nij,nbjd->nbid", At, Gv)
                Fv = prob.dT(P)
                Q = ph[:, None, :, None] * q[:, :, None, :] + h[:, None, None, None] * np.einsum("nij,nbjd->nbid", Ah, Fv)
            Gv, Fv = prob.force(0.0, Q), prob.dT(P)
            q1 = ph0[:, None, None] * q + h[:, None, None] * np.einsum("ni,nbid->nbd", bh, Fv)
            p1 = pt0[:, None, None] * p + h[:, None, None] * np.einsum("ni,nbid->nbd", bt, Gv)
            M = np.swapaxes(np.concatenate([q1, p1], axis=-1), -1, -2)
            M[~good] = np.nan
            return M
    return None


def eig2(M: Any) -> Any:
    """Eigenvalues of a batch of real 2x2 matrices (..., 2, 2): (..., 2) complex."""
    tr = M[..., 0, 0] + M[..., 1, 1]
    det = M[..., 0, 0] * M[..., 1, 1] - M[..., 0, 1] * M[..., 1, 0]
    disc = np.sqrt((0.25 * tr * tr - det).astype(complex))
    return np.stack([0.5 * tr + disc, 0.5 * tr - disc], axis=-1)


def f_formula(kind: str, w: Any, g: Any, h: Any) -> Any:
    if kind == "cimp":
        return w > g
    if kind == "csv1":
        sech = 1.0 / math.cosh(g * h)
        x = h * h * w * w / 2
        return 1 - sech < x < 1 + sech
    if kind == "csv2":
        sech = 1.0 / math.cosh(g * h / 2)
        lo, hi = g * g * sech, 4 * sech / (h * h)
        if g * h < 2:
            return lo < w * w < hi
        if g * h > 2:
            return hi < w * w < lo
        return False
    return None


def _pb(ev: Any) -> Any:
    rho = float(np.max(np.abs(ev)))
    pb = rho < 1.0 - 8 * EPS or (rho <= 1.0 + 8 * EPS and abs(ev[0] - ev[-1]) > 1e-7)
    return pb, abs(rho - 1.0) <= 16 * EPS


def stab_poly(method: str) -> Any:
    A, b, _ = xm.EXPLICIT_RK[method]
    A, b = np.array(A, float), np.array(b, float)
    s = len(b)
    coef = [1.0]
    v = np.ones(s)
    for _ in range(s):
        coef.append(float(b @ v))
        v = A @ v
    return coef       # R(z) = sum_k coef[k] z^k (A nilpotent: exact for explicit RK)


def grid_matrices(method: str, w: float, G: np.ndarray, H: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """The one-step matrices over the (gamma, h) grid, and where none exists (not applicable
    or not finite)."""
    Ms = np.full((len(G), len(H), 2, 2), np.nan)
    na = np.zeros((len(G), len(H)), bool)
    for i, g in enumerate(G):
        row = row_matrices(method, w, g, H)
        if row is not None:
            Ms[i] = row
            continue
        for j, h in enumerate(H):
            try:
                Ms[i, j] = one_step_matrix(method, w, g, h)
            except (xm.NotApplicable, refmath.NotApplicable):
                na[i, j] = True
    na |= ~np.all(np.isfinite(Ms), axis=(-2, -1))
    return Ms, na


# implicit Runge-Kutta methods on the plain form (dampsym: their Butcher tableau, a power-boundary
# formula as for the explicit ones)
PLAIN_IMPLICIT = {"implicit-euler": ([[1.0]], [1.0]), "implicit-midpoint": xm.GAUSS[1][:2],
                  "gauss1": xm.GAUSS[1][:2], "gauss2": xm.GAUSS[2][:2], "gauss3": xm.GAUSS[3][:2]}


def rational_r(A: Any, b: Any, z: np.ndarray) -> np.ndarray:
    """R(z) = 1 + z b^T (I - z A)^{-1} 1 of a Runge-Kutta tableau, at every z of an array."""
    A, b = np.asarray(A, float), np.asarray(b, float)
    s = len(b)
    zz = np.asarray(z, complex)[..., None, None]
    k = np.linalg.solve(np.eye(s) - zz * A, np.ones(zz.shape[:-2] + (s, 1), complex))
    return 1.0 + np.asarray(z, complex) * (k[..., 0] @ b)


def power_bounded_by_r(poly: Any, w: float, Gg: np.ndarray, Hh: np.ndarray) -> np.ndarray:
    """Power-boundedness from the stability function R(h lambda) of an explicit RK method at the
    oscillator's eigenvalues lambda = -g +- sqrt(g^2 - w^2)."""
    disc = np.sqrt(((Gg - w) * (Gg + w)).astype(complex))
    lam = np.stack([-Gg + disc, -Gg - disc], axis=-1) * Hh[..., None]
    R = rational_r(poly[1], poly[2], lam) if poly[0] == "tableau" else sum(c * lam ** k for k, c in enumerate(poly))
    rR = np.max(np.abs(R), axis=-1)
    return (rR < 1.0 - 8 * EPS) | ((rR <= 1.0 + 8 * EPS) & (np.abs(R[..., 0] - R[..., 1]) > 1e-7))


@xcache.memo
def sweep(method: str, spec: Dict[str, Any]) -> Any:
    w = float(spec.get("omega", 1.0))
    G, H = axis(spec["gamma"]), axis(spec["h"])
    nh = len(H)
    kind = FORMULA.get(method)
    poly = (stab_poly(method) if method in xm.EXPLICIT_RK else
            ["tableau", *PLAIN_IMPLICIT[method]] if method in PLAIN_IMPLICIT else
            ["tableau", *xm.FILE_RK[method][1:3]] if xm.FILE_RK.get(method, ("",))[0] == "plain" else None)
    Ms, na = grid_matrices(method, w, G, H)
    Gg, Hh = G[:, None], H[None, :]
    e = np.exp(-Gg * Hh)
    ht = 0.5 * (Ms[..., 0, 0] + Ms[..., 1, 1])
    with np.errstate(invalid="ignore"):
        Femp = np.abs(ht) < e          # False where M does not exist (csv2 at gamma h = 2)
        Ftie = np.abs(np.abs(ht) - e) <= 16 * EPS * e
    Ffor = np.zeros_like(Femp)
    if kind:
        for i, g in enumerate(G):
            for j, h in enumerate(H):
                Ffor[i, j] = f_formula(kind, w, g, h)
    ev = eig2(np.nan_to_num(Ms))
    rho = np.max(np.abs(ev), axis=-1)
    dist = np.abs(ev[..., 0] - ev[..., 1])
    PB = (rho < 1.0 - 8 * EPS) | ((rho <= 1.0 + 8 * EPS) & (dist > 1e-7))
    PBtie = np.abs(rho - 1.0) <= 16 * EPS
    PBR = np.zeros_like(PB) if poly is None else power_bounded_by_r(poly, w, Gg, Hh)
    b2 = (w - Gg) * (w + Gg)
    with np.errstate(invalid="ignore"):
        hx = e * np.where(b2 >= 0, np.cos(np.sqrt(np.abs(b2)) * Hh), np.cosh(np.sqrt(np.abs(b2)) * Hh))
    hterr = np.abs(ht - hx)
    ok = ~na

    def cnt(mask: Any, tie: Any, where: Any = ok) -> Any:
        return int(np.sum(mask & where)), int(np.sum(tie & ok))

    def first(fail: bool, tie: Any) -> Any:
        """first failing index (nh if none), and its range with ties flipped"""
        def f(m: Any) -> Any:
            idx = np.nonzero(m)[0]
            return int(idx[0]) if len(idx) else nh
        return f(fail), f(fail & ~tie), f(fail | tie)

    def hval(j: Any) -> Any:
        return None if j >= nh else float(H[j])

    allp = np.ones_like(ok)
    out = {"F_violations": cnt(~Femp, Ftie, allp), "power_bounded_violations": cnt(~PB, PBtie),
           "violations_omega_gt_gamma": cnt((~Femp) & (w > G)[:, None], Ftie & (w > G)[:, None], allp)}
    rows, bmis, pmis = [], [0, 0, 0], [0, 0, 0]
    for i, g in enumerate(G):
        fe = first(~Femp[i], Ftie[i])
        pu = first(~PB[i] & ok[i], PBtie[i])
        row = {"gamma": float(g), "h_F_empirical": [hval(x) for x in fe],
               "h_power_unbounded": [hval(x) for x in pu],
               "max_half_trace_err": float(np.max(hterr[i][ok[i]])) if ok[i].any() else None}
        if kind:
            ff = first(~Ffor[i] & ok[i], np.zeros(nh, bool))[0]
            row["h_F_formula"] = [hval(ff)] * 3
            d = [abs(x - ff) for x in fe]
            bmis = [max(bmis[0], d[0]), max(bmis[1], min(d)), max(bmis[2], max(d))]
        if poly is not None:
            fr = first(~PBR[i] & ok[i], np.zeros(nh, bool))[0]
            d = [abs(x - fr) for x in pu]
            pmis = [max(pmis[0], d[0]), max(pmis[1], min(d)), max(pmis[2], max(d))]
        rows.append(row)
    if kind:
        m = Femp != Ffor
        out["mismatch_points"] = cnt(m, Ftie)
        out["max_boundary_mismatch_cells"] = (bmis[0], bmis[2] - bmis[1])
    if poly is not None:
        out["power_mismatch_points"] = cnt(PB != PBR, PBtie)
        out["max_power_boundary_mismatch_cells"] = (pmis[0], pmis[2] - pmis[1])
    out["rows"] = rows
    out["first_row"] = {"gamma": rows[0]["gamma"], "h_F_empirical": rows[0]["h_F_empirical"],
                        "h_power_unbounded": rows[0]["h_power_unbounded"]}
    out["grid"] = {"gamma": len(G), "h": nh}
    return out


def trace_taylor(method: str, w: Any, g: Any, h: Any) -> Any:
    """c of 1/2 tr M - e^{-gh} cos(beta h) = c h^4 + O(h^5), in magnitude, from OUR M: the
    estimator D(h)/h^4 at h, h/2, h/4 extrapolated with c + c1 h + c2 h^2 (Richardson).  Returns
    (c, band): band bounds how far any estimate from step sizes <= h can lie from c = the plain
    estimator's truncation |D(h)/h^4 - c| plus the extrapolation's round-off
    (eps / (h/4)^4 amplified by the extrapolation weights, < 8)."""
    b2 = (w - g) * (w + g)
    hs = np.array([h, h / 2, h / 4])
    est = []
    for hk in hs:
        M = one_step_matrix(method, w, g, hk)
        e = math.exp(-g * hk)
        hx = e * (math.cos(math.sqrt(b2) * hk) if b2 >= 0 else math.cosh(math.sqrt(-b2) * hk))
        est.append((0.5 * (M[0, 0] + M[1, 1]) - hx) / hk ** 4)
    V = np.vander(hs, 3, increasing=True)
    c = float(np.linalg.solve(V, np.array(est))[0])
    ro = 8 * 4 * EPS / (h / 4) ** 4
    band = abs(est[0] - c) + ro
    return abs(c), band
