"""Independent mathematics for the dampsym cross-check (numpy + scipy only).

Everything here is written from docs/conventions.md and the source papers
(F = Floyd 2014 thesis, B = Bhatt 2016).  Nothing is taken from the C++ code
base: no shared code, no shared coefficients, no shared intermediate numbers.

Convention (conventions §1, "our gamma"):  q' = dT/dp,  p' = -dV/dq - 2*gamma*p, T = p^2/2.
Equivalently z' = N(z) - gamma*z with N = J^{-1} grad H_gamma, H_gamma = T + V + gamma*q*p
(F(1.4), B(3.3)).  Only one-degree-of-freedom problems with constant gamma are
implemented (oscillator, pendulum), so states are plain Python floats (q, p):
this keeps the long step loops fast without numpy call overhead.
"""
from typing import Any, Dict
import math

import numpy as np
from scipy.integrate import solve_ivp

EPS = np.finfo(float).eps


class NotApplicable(Exception):
    """The method cannot be applied with these parameters (e.g. csv2 with gamma*h >= 2)."""


class SolveFailed(Exception):
    """The implicit stage equation could not be solved."""


# ----------------------------------------------------------------------------------------
# Problems (conventions §2).  Each gives V'(q), V''(q) and the constant gamma.
# ----------------------------------------------------------------------------------------
class Oscillator:
    """q'' + 2 gamma q' + omega^2 q = 0 (F(2.5)); V = omega^2 q^2 / 2."""
    name = "oscillator"
    param_names = ("omega", "gamma", "q0", "p0")

    def __init__(self, omega: Any, gamma: Any, q0: Any, p0: Any) -> None:
        self.omega, self.gamma, self.q0, self.p0 = float(omega), float(gamma), float(q0), float(p0)
        w2 = self.omega ** 2
        self.dV = lambda q: w2 * q
        self.ddV = lambda q: w2

    def exact(self, t: Any) -> Any:
        """Exact state at time t after the initial one, valid in every regime.

        z' = A z with A = [[0, 1], [-w^2, -2g]].  With B = A + g I one has B^2 = -beta^2 I,
        beta^2 = w^2 - g^2, so  z(t) = e^{-g t} [ c(t) I + s(t) B ] z0  with
        c = cos(beta t), s = sin(beta t)/beta for beta^2 > 0, cosh/sinh forms for beta^2 < 0,
        and a power series (continuous through beta = 0, no 0/0) when |beta^2 t^2| <= 1.
        Below C = e^{-g t} c and S = e^{-g t} s.
        """
        g, w = self.gamma, self.omega
        b2 = (w - g) * (w + g)          # beta^2 without cancellation near critical damping
        x = b2 * t * t
        if abs(x) <= 1.0:
            # C = sum (-x)^k/(2k)!, S = t sum (-x)^k/(2k+1)!; 12 terms reach round-off for |x| <= 1
            C, S, term_c, term_s = 0.0, 0.0, 1.0, t
            for k in range(12):
                C += term_c
                S += term_s
                term_c *= -x / ((2 * k + 1) * (2 * k + 2))
                term_s *= -x / ((2 * k + 2) * (2 * k + 3))
            e = math.exp(-g * t)
            C, S = e * C, e * S
        elif b2 > 0:                    # under-damped
            beta = math.sqrt(b2)
            e = math.exp(-g * t)
            C, S = e * math.cos(beta * t), e * math.sin(beta * t) / beta
        else:                           # over-damped: e^{-gt} cosh, e^{-gt} sinh without overflow,
            kappa = math.sqrt(-b2)      # kappa - g = -w^2/(kappa + g) avoids cancellation
            slow, fast = math.exp(-w * w / (kappa + g) * t), math.exp(-(kappa + g) * t)
            C, S = 0.5 * (slow + fast), 0.5 * (slow - fast) / kappa
        q0, p0 = self.q0, self.p0
        # B z0 = (g q0 + p0, -w^2 q0 - g p0)
        return np.array([C * q0 + S * (g * q0 + p0), C * p0 + S * (-w * w * q0 - g * p0)])

    def H_gamma(self, q: Any, p: Any) -> Any:
        """Conformal invariant H_gamma = (w^2 q^2 + p^2)/2 + g q p (B Ex. 1.2); works on arrays."""
        return 0.5 * (self.omega ** 2 * q * q + p * p) + self.gamma * q * p


class Pendulum:
    """q'' + 2 gamma q' + sin q = 0 (F(4.5) with the typo 2*gamma*q fixed, conventions §6); V = -cos q."""
    name = "pendulum"
    param_names = ("gamma", "q0", "p0")

    def __init__(self, gamma: Any, q0: Any, p0: Any) -> None:
        self.gamma, self.q0, self.p0 = float(gamma), float(q0), float(p0)
        self.dV = math.sin
        self.ddV = math.cos
        self._cache: Dict[float, Any] = {}

    def reference(self, t: Any) -> Any:
        """Numerical reference at time t after the initial one (conventions §4, certified).

        DOP853 with rtol 1e-13, atol 1e-15, recomputed with a ten times tighter tolerance;
        the difference is returned as the reference's own error estimate.  scipy refuses
        rtol < 100*eps (it would silently raise it), so the tighter solve uses
        rtol = max(1e-14, 100*eps) and atol = 1e-16.
        Returns (state, error_estimate, note).
        """
        if t not in self._cache:
            g = self.gamma

            def f(_t: Any, z: Any) -> Any:
                return [z[1], -math.sin(z[0]) - 2.0 * g * z[1]]

            z0 = [self.q0, self.p0]
            a = solve_ivp(f, (0.0, t), z0, method="DOP853", rtol=1e-13, atol=1e-15)
            rtol2 = max(1e-14, 100 * float(EPS))
            b = solve_ivp(f, (0.0, t), z0, method="DOP853", rtol=rtol2, atol=1e-16)
            if not (a.success and b.success):
                raise SolveFailed("reference solve failed: %s / %s" % (a.message, b.message))
            za, zb = a.y[:, -1], b.y[:, -1]
            note = "DOP853 rtol 1e-13 atol 1e-15, checked with rtol %.3g atol 1e-16" % rtol2
            self._cache[t] = (za, float(np.linalg.norm(za - zb)), note)
        return self._cache[t]


PROBLEMS = {"oscillator": Oscillator, "pendulum": Pendulum}


# ----------------------------------------------------------------------------------------
# One-step maps.  make_step(method, prob, h) returns step(q, p) -> (q1, p1) with all
# h-dependent constants precomputed.  IMPLICIT names the implicit ones (looser tolerance).
# ----------------------------------------------------------------------------------------
IMPLICIT = {"cimp"}


def _full_field(prob: Any) -> Any:
    """Full vector field f(q, p) = (p, -V'(q) - 2 gamma p) (conventions §1, F(1.1))."""
    dV, g2 = prob.dV, 2.0 * prob.gamma
    return lambda q, p: (p, -dV(q) - g2 * p)


def _euler(prob: Any, h: Any) -> Any:
    """Explicit Euler, HLW(1.4)."""
    f = _full_field(prob)

    def step(q: Any, p: Any) -> Any:
        kq, kp = f(q, p)
        return q + h * kq, p + h * kp
    return step


def _heun(prob: Any, h: Any) -> Any:
    """Heun = explicit trapezoid, B(3.8): predictor z + h f(z), then average the slopes."""
    f = _full_field(prob)

    def step(q: Any, p: Any) -> Any:
        k1q, k1p = f(q, p)
        k2q, k2p = f(q + h * k1q, p + h * k1p)
        return q + 0.5 * h * (k1q + k2q), p + 0.5 * h * (k1p + k2p)
    return step


def _rk3(prob: Any, h: Any) -> Any:
    """Kutta's third-order RK (F ch.4): c = (0, 1/2, 1), A = [[0], [1/2], [-1, 2]], b = (1/6, 2/3, 1/6)."""
    f = _full_field(prob)

    def step(q: Any, p: Any) -> Any:
        k1q, k1p = f(q, p)
        k2q, k2p = f(q + 0.5 * h * k1q, p + 0.5 * h * k1p)
        k3q, k3p = f(q + h * (-k1q + 2.0 * k2q), p + h * (-k1p + 2.0 * k2p))
        return (q + h * (k1q + 4.0 * k2q + k3q) / 6.0,
                p + h * (k1p + 4.0 * k2p + k3p) / 6.0)
    return step


def _rk4(prob: Any, h: Any) -> Any:
    """Classical fourth-order Runge-Kutta on the full vector field."""
    f = _full_field(prob)

    def step(q: Any, p: Any) -> Any:
        k1q, k1p = f(q, p)
        k2q, k2p = f(q + 0.5 * h * k1q, p + 0.5 * h * k1p)
        k3q, k3p = f(q + 0.5 * h * k2q, p + 0.5 * h * k2p)
        k4q, k4p = f(q + h * k3q, p + h * k3p)
        return (q + h * (k1q + 2.0 * k2q + 2.0 * k3q + k4q) / 6.0,
                p + h * (k1p + 2.0 * k2p + 2.0 * k3p + k4p) / 6.0)
    return step


def _csv1(prob: Any, h: Any) -> Any:
    """CSV1, F(2.12) (Modin-Soderlind), T = p^2/2:
         p_half = e^{-g h} p - (h/2) V'(q)
         q1     = q + h p_half
         p1     = e^{-g h} (p_half - (h/2) V'(q1))"""
    dV, e = prob.dV, math.exp(-prob.gamma * h)

    def step(q: Any, p: Any) -> Any:
        ph = e * p - 0.5 * h * dV(q)
        q1 = q + h * ph
        return q1, e * (ph - 0.5 * h * dV(q1))
    return step


def _csv2(prob: Any, h: Any) -> Any:
    """CSV2, F(2.16) exactly as printed, T = p^2/2:
         (1 + g h/2) p_half = e^{-g h/2} p - (h/2) V'(q)
         (1 - g h/2) q1     = e^{-g h/2} [ (1 + g h/2) e^{-g h/2} q + h p_half ]
         p1                 = e^{-g h/2} [ (1 - g h/2) p_half - (h/2) V'(q1) ]
       Defined for g h != 2 (F (3.22): the stable region reversed for g h > 2); at g h = 2 the
       q-update divides by zero in IEEE arithmetic (inf: the run diverges, as dampsym's csv2.hpp)."""
    g, dV = prob.gamma, prob.dV
    a, b, e = 1.0 + 0.5 * g * h, 1.0 - 0.5 * g * h, math.exp(-0.5 * g * h)

    def step(q: Any, p: Any) -> Any:
        ph = (e * p - 0.5 * h * dV(q)) / a
        q1 = ieee_div(e * (a * e * q + h * ph), b)
        return q1, e * (b * ph - 0.5 * h * dV(q1))
    return step


def ieee_div(x: float, y: float) -> float:
    """x / y as IEEE doubles divide (+-inf or nan for y = 0, where Python raises)."""
    if y != 0.0:
        return x / y
    with np.errstate(divide="ignore", invalid="ignore"):
        return float(np.float64(x) / np.float64(y))


def _cimp(prob: Any, h: Any) -> Any:
    """CIMP, F(2.3):  (e^{gh/2} z1 - e^{-gh/2} z0)/h = N((e^{gh/2} z1 + e^{-gh/2} z0)/2),
    N = J^{-1} grad H_gamma = (p + g q, -V'(q) - g p).

    Unknown w = e^{gh/2} z1, a = e^{-gh/2} z0:  G(w) = w - a - h N((w + a)/2) = 0, solved by
    Newton with the exact Jacobian  G' = I - (h/2) [[g, 1], [-V''(q_m), -g]]  until the
    update is at round-off; then z1 = e^{-gh/2} w."""
    g, dV, ddV = prob.gamma, prob.dV, prob.ddV
    em = math.exp(-0.5 * g * h)
    hh = 0.5 * h

    def step(q: Any, p: Any) -> Any:
        aq, ap = em * q, em * p
        wq, wp = aq + h * (ap + g * aq), ap + h * (-dV(aq) - g * ap)   # Euler predictor
        last = math.inf
        for _ in range(60):
            mq, mp = 0.5 * (wq + aq), 0.5 * (wp + ap)
            rq = wq - aq - h * (mp + g * mq)
            rp = wp - ap - h * (-dV(mq) - g * mp)
            j11, j12 = 1.0 - hh * g, -hh
            j21, j22 = hh * ddV(mq), 1.0 + hh * g
            det = j11 * j22 - j12 * j21
            dq = (rq * j22 - rp * j12) / det
            dp = (rp * j11 - rq * j21) / det
            wq, wp = wq - dq, wp - dp
            size = abs(dq) + abs(dp)
            scale = abs(wq) + abs(wp)
            if size <= 4.0 * EPS * scale or size == 0.0:
                break
            if size >= last and size <= 1e-10 * scale:   # stagnating at round-off
                break
            last = size
        else:
            raise SolveFailed("Newton did not converge")
        if not (math.isfinite(wq) and math.isfinite(wp)):
            raise SolveFailed("Newton produced a non-finite iterate")
        return em * wq, em * wp
    return step


METHODS = {"euler": _euler, "heun": _heun, "rk3": _rk3, "rk4": _rk4,
           "csv1": _csv1, "csv2": _csv2, "cimp": _cimp}


def make_step(method: str, prob: Any, h: Any) -> Any:
    return METHODS[method](prob, h)


def one_step_matrix(method: str, prob: Any, h: Any) -> Any:
    """One-step matrix M of a method on a linear problem: columns = one step from e1 and e2."""
    step = make_step(method, prob, h)
    c1, c2 = step(1.0, 0.0), step(0.0, 1.0)
    return np.array([[c1[0], c2[0]], [c1[1], c2[1]]])


def integrate(method: str, prob: Any, h: Any, nsteps: int, keep: Any = False, blowup: Any = None) -> Any:
    """Take nsteps steps of size h from (q0, p0).

    Returns dict(status, steps, q, p, traj, message) with status 'ok', 'diverged' (state
    non-finite, or, when blowup is given, larger than blowup * max(1, |z0|)),
    'solve-failed' or 'not-applicable'.  traj holds the arrays (q_n), (p_n), n = 0..steps,
    when keep is true.
    """
    q, p = prob.q0, prob.p0
    limit = math.inf if blowup is None else blowup * max(1.0, abs(q) + abs(p))
    try:
        step = make_step(method, prob, h)
    except NotApplicable as exc:
        return dict(status="not-applicable", steps=0, q=q, p=p, traj=None, message=str(exc))
    qs: Any = [q] if keep else None
    ps: Any = [p] if keep else None
    status, msg, n = "ok", "", 0
    try:
        for n in range(1, nsteps + 1):
            q, p = step(q, p)
            if keep:
                qs.append(q)
                ps.append(p)
            if not abs(q) + abs(p) < limit:        # also catches inf and NaN
                status, msg = "diverged", "|z| passed %g at step %d" % (limit, n)
                break
    except SolveFailed as exc:
        status, msg = "solve-failed", "%s at step %d" % (exc, n)
    except OverflowError:
        status, msg = "diverged", "overflow at step %d" % n
    traj = (np.array(qs), np.array(ps)) if keep else None
    return dict(status=status, steps=n, q=q, p=p, traj=traj, message=msg)


# ----------------------------------------------------------------------------------------
# Order fit (conventions §5 "order") with the asymptotic-window rule.
# ----------------------------------------------------------------------------------------
def _window_at_finest(local: Any) -> Any:
    """First index i of the longest window of local orders local[i:] (>= 2 of them) that ends at
    the finest step and agrees within max(0.1 |mean|, 0.05) with a mean >= 0.5, or None."""
    first = None
    for i in range(len(local) - 2, -1, -1):
        lo = local[i:]
        m = lo.mean()
        if m >= 0.5 and np.all(np.abs(lo - m) <= max(0.1 * abs(m), 0.05)):
            first = i
    return first


def fit_order(dts: Any, errors: Any, floor: Any, solution_scale: Any = math.inf) -> Any:
    """Least-squares slope of log(error) against log(dt) over the asymptotic window
    (docs/conventions.md §5 "order").

    1. drop points whose error is not finite, not positive, <= floor, or >= 0.1 solution_scale
       (not small against the solution);
    2. sort by dt descending; local orders p_i = log(e_i / e_{i+1}) / log(dt_i / dt_{i+1});
    3. the window ENDS at the finest remaining point and reaches as far coarser as the local
       orders in it agree within max(0.1 |mean|, 0.05) of their mean, mean >= 0.5, >= 3 points;
       none: the fit fails with status "no convergence at the finest steps" (finest local order
       < 0.5), "order drops at small h" (below the one before) or "order rises at small h";
    4. slope and R^2 of the least-squares line over the window.
    """
    pts = sorted(((float(d), float(e)) for d, e in zip(dts, errors)
                  if e is not None and math.isfinite(e) and 0.0 < e and e > floor
                  and e < 0.1 * solution_scale),
                 key=lambda x: -x[0])
    out = dict(ok=False, status="too few points", points=len(pts), slope=None, r2=None,
               window_dt=[], local_orders=[])
    if len(pts) < 3:
        out["reason"] = "fewer than 3 usable points (%d)" % len(pts)
        return out
    ld = np.log([d for d, _ in pts])
    le = np.log([e for _, e in pts])
    local = np.diff(le) / np.diff(ld)
    out["local_orders"] = local.tolist()
    out["finest_local_order"] = float(local[-1])
    i = _window_at_finest(local)
    if i is None:
        fin, before = local[-1], local[-2]
        out["status"] = ("no convergence at the finest steps" if fin < 0.5 else
                         "order drops at small h" if fin < before else "order rises at small h")
        out["reason"] = "the finest steps' local orders disagree"
        return out
    x, y = ld[i:], le[i:]
    slope, icept = np.polyfit(x, y, 1)
    ss_res = float(np.sum((y - (slope * x + icept)) ** 2))
    ss_tot = float(np.sum((y - y.mean()) ** 2))
    out.update(ok=True, status="ok", slope=float(slope),
               r2=1.0 - ss_res / ss_tot if ss_tot > 0 else 1.0, window_dt=[d for d, _ in pts[i:]])
    return out
