#!/usr/bin/python3
"""Writes the stability-threshold cases of the stress suite (verify/cases/stress-threshold-*.json).

A case file cannot say "dt = 0.99 h*", so this script solves each analytic threshold h* of the
damped oscillator q'' + 2 gamma q' + omega^2 q = 0 (our gamma: the momentum decays like
e^{-2 gamma t}) and writes dt_ladder = [0.99 h*, 1.01 h*] with 17 significant digits, plus the
expectations the analysis gives at both step sizes:

  * F's condition |tr M/2| < e^{-gamma h} (F(3.17) for csv1, F(3.22) for csv2) and
    power-boundedness of the one-step matrix M (spectral radius <= 1);
  * the spectral radius of M, from the closed-form M below;
  * for a step size where M is not power-bounded, the step at which the run must be reported
    "diverged" (|z_i| > 1e100, src/core/integrate.hpp), found by iterating the closed-form M;
  * for a power-bounded step size, a bound on the error over the output grid (and, for the
    conformal methods, on e^{2 gamma t} H_gamma(z_n) / H_gamma(z_0) - 1), from the same iteration.

tests/test_stress_thresholds.cpp recomputes every h* independently in C++ (bisection on the
catalog's F_condition, the stability polynomial, or the closed form) and checks that the dt_ladder
of each file is 0.99 and 1.01 times it, so the numbers cannot go stale silently. Run from the
repository root:  /usr/bin/python3 -m verify.stress_thresholds
"""
from typing import Any, Dict

import json
import math
import os

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
CASES = os.path.join(HERE, "cases")


def r17(x: Any) -> float:
    """x rounded to 17 significant digits (what the JSON holds)."""
    return float("%.17g" % x)


# ---- closed-form one-step matrices on the oscillator (columns: images of (1,0) and (0,1)) ----

def m_csv1(w: Any, g: Any, h: Any) -> Any:
    # F(2.12): p_half = e^{-gh} p - (h/2) w^2 q; q1 = q + h p_half; p1 = e^{-gh}(p_half - (h/2) w^2 q1)
    d = math.exp(-g * h)

    def step(q: Any, p: Any) -> Any:
        ph = d * p - 0.5 * h * w * w * q
        q1 = q + h * ph
        return q1, d * (ph - 0.5 * h * w * w * q1)
    return np.array([step(1.0, 0.0), step(0.0, 1.0)]).T


def m_csv2(w: Any, g: Any, h: Any) -> Any:
    # F(2.16) in conventions §3's form
    e = math.exp(-0.5 * g * h)
    pl, mi = 1.0 + 0.5 * g * h, 1.0 - 0.5 * g * h

    def step(q: Any, p: Any) -> Any:
        ph = (e * p - 0.5 * h * w * w * q) / pl
        q1 = e * (pl * e * q + h * ph) / mi
        return q1, e * (mi * ph - 0.5 * h * w * w * q1)
    return np.array([step(1.0, 0.0), step(0.0, 1.0)]).T


TABLEAUX = {  # explicit RK: (A, b)
    "euler": ([[0.0]], [1.0]),
    "heun": ([[0.0, 0.0], [1.0, 0.0]], [0.5, 0.5]),
    "rk3": ([[0, 0, 0], [0.5, 0, 0], [-1.0, 2.0, 0]], [1 / 6, 2 / 3, 1 / 6]),
    "rk4": ([[0, 0, 0, 0], [0.5, 0, 0, 0], [0, 0.5, 0, 0], [0, 0, 1.0, 0]],
            [1 / 6, 1 / 3, 1 / 3, 1 / 6]),
}


def m_rk(name: Any, w: Any, g: Any, h: Any) -> Any:
    """M = R(hA) = sum_k (hA)^k b^T A_rk^{k-1} 1 for an explicit RK method (a polynomial)."""
    A_rk, b = (np.array(x, dtype=float) for x in TABLEAUX[name])
    s = len(b)
    A = np.array([[0.0, 1.0], [-w * w, -2.0 * g]])
    M = np.eye(2)
    v = np.ones(s)
    P = np.eye(2)
    for _ in range(s):
        P = P @ (h * A)
        M = M + (b @ v) * P
        v = A_rk @ v
    return M


def m_stormer_verlet(w: Any, g: Any, h: Any) -> Any:
    assert g == 0.0  # velocity Verlet (Lobatto IIIA-IIIB) on the undamped oscillator
    return m_csv1(w, 0.0, h)


def m_symplectic_euler(w: Any, g: Any, h: Any) -> Any:
    # q tableau explicit Euler, p tableau implicit Euler (HLW(1.8)): p1 = p - h w^2 q, q1 = q + h p1
    assert g == 0.0
    return np.array([[1.0 - h * h * w * w, h], [-h * w * w, 1.0]])


def one_step(method: str, w: Any, g: Any, h: Any) -> Any:
    if method == "csv1":
        return m_csv1(w, g, h)
    if method == "csv2":
        return m_csv2(w, g, h)
    if method == "stormer-verlet":
        return m_stormer_verlet(w, g, h)
    if method == "symplectic-euler":
        return m_symplectic_euler(w, g, h)
    return m_rk(method, w, g, h)


def spectral_radius(M: Any) -> float:
    return float(max(abs(np.linalg.eigvals(M))))


def f_condition(M: Any, g: Any, h: Any) -> bool:
    return abs(0.5 * np.trace(M)) < math.exp(-g * h)


# ---- the thresholds (each solved case-independently from its formula) ----

def bisect(f: Any, a: Any, b: Any, iters: Any = 200) -> Any:
    """Root of f in [a, b] (f(a), f(b) of opposite sign), to the last bit."""
    fa = f(a)
    assert fa * f(b) < 0, (a, b, fa, f(b))
    for _ in range(iters):
        m = 0.5 * (a + b)
        if m in (a, b):
            break
        if (f(m) < 0) == (fa < 0):
            a, fa = m, f(m)
        else:
            b = m
    return 0.5 * (a + b)


def h_csv1_upper(w: Any, g: Any) -> Any:  # F(3.17): h^2 w^2 / 2 = 1 + sech(g h)
    return bisect(lambda h: 0.5 * h * h * w * w - 1.0 - 1.0 / math.cosh(g * h), 1e-6, 10.0 / w)


def h_csv1_lower(w: Any, g: Any) -> Any:  # F(3.17): h^2 w^2 / 2 = 1 - sech(g h) (exists for w < g)
    return bisect(lambda h: 0.5 * h * h * w * w - 1.0 + 1.0 / math.cosh(g * h), 1e-3, 10.0 / w)


def h_csv2_upper(w: Any, g: Any) -> Any:  # F(3.22): w^2 = 4 sech(g h / 2) / h^2 (g h < 2)
    return bisect(lambda h: w * w * h * h - 4.0 / math.cosh(0.5 * g * h), 1e-6, 2.0 / g if g else 10.0 / w)


def h_csv2_lower(w: Any, g: Any) -> Any:  # F(3.22): w^2 = g^2 sech(g h / 2)  ->  h = (2/g) arccosh(g^2/w^2)
    return 2.0 / g * math.acosh(g * g / (w * w))


def h_rk_power(name: Any, w: Any, g: Any) -> Any:
    """First h where max |R(h lambda)| = 1, lambda = -g +- sqrt(g^2 - w^2) (closed forms at g = 0:
    euler, heun never stable; rk3 h w = sqrt 3; rk4 h w = 2 sqrt 2; euler at g < w: h = 2g/w^2)."""
    A_rk, b = (np.array(x, dtype=float) for x in TABLEAUX[name])
    lam = -g + np.sqrt(complex(g * g - w * w))

    def R(z: Any) -> Any:
        v, zk = np.ones(len(b)), 1.0 + 0j
        out: Any = 1.0 + 0j
        for _ in range(len(b)):
            zk = zk * z
            out += (b @ v) * zk
            v = A_rk @ v
        return out
    return bisect(lambda h: abs(R(h * lam)) - 1.0, 0.1 / w, 4.0 / w)


# ---- predictions by iterating the closed-form M ----

def exact(w: Any, g: Any, q0: Any, p0: Any, t: Any) -> Any:
    b2 = (w - g) * (w + g)
    if b2 > 0:
        b = math.sqrt(b2)
        C, S = math.cos(b * t), math.sin(b * t) / b
    elif b2 < 0:
        k = math.sqrt(-b2)
        C, S = math.cosh(k * t), math.sinh(k * t) / k
    else:
        C, S = 1.0, t
    e = math.exp(-g * t)
    return np.array([e * (q0 * C + (p0 + g * q0) * S), e * (p0 * C - (g * p0 + w * w * q0) * S)])


def iterate(M: Any, w: Any, g: Any, h: Any, n: Any, every: Any, z0: Any = (1.0, 0.0)) -> Any:
    """Runs z <- M z for n steps like src/core/integrate.hpp. Returns the diverged step (or None),
    the max error against the exact solution on the output grid (every `every` steps) and the max
    of |e^{2 g t} H_gamma(z_k)/H_gamma(z_0) - 1| over all steps."""
    z = np.array(z0, dtype=float)

    def hg(v: Any) -> Any:
        return 0.5 * (w * w * v[0] ** 2 + v[1] ** 2) + g * v[0] * v[1]
    h0 = hg(z)
    max_err, max_inv = 0.0, 0.0
    for k in range(1, n + 1):
        z = M @ z
        if not np.all(np.abs(z) <= 1e100):
            return k, max_err, max_inv
        # as src/diagnostics/recorder.hpp: the ratio in log form; 0 when H_gamma underflows
        ratio = 0.0
        if hg(z) != 0.0:
            x = math.log(abs(hg(z))) - math.log(abs(h0)) + 2 * g * k * h
            ratio = math.copysign(math.exp(x) if x < 709 else math.inf, hg(z) * h0)
        max_inv = max(max_inv, abs(ratio - 1.0))
        if k % every == 0:
            max_err = max(max_err, float(np.linalg.norm(z - exact(w, g, z0[0], z0[1], k * h))))
    return None, max_err, max_inv


# ---- the cases ----

# (id suffix, method, omega, gamma, threshold solver, formula text, m = output points, side)
# side "upper": inside the region below h*; "lower": inside above h*.
THRESHOLDS = [
    ("csv1-upper", "csv1", 1.0, 0.005, lambda w, g: h_csv1_upper(w, g),
     "F(3.17) upper boundary h^2 w^2/2 = 1 + sech(gamma h), by bisection", 200, "upper"),
    ("csv2-upper", "csv2", 1.0, 0.005, lambda w, g: h_csv2_upper(w, g),
     "F(3.22) upper boundary w^2 = 4 sech(gamma h/2)/h^2, by bisection", 200, "upper"),
    ("csv1-upper-strong", "csv1", 3.51, 1.0, lambda w, g: h_csv1_upper(w, g),
     "F(3.17) upper boundary h^2 w^2/2 = 1 + sech(gamma h), by bisection", 3, "upper"),
    ("csv2-upper-strong", "csv2", 3.51, 1.0, lambda w, g: h_csv2_upper(w, g),
     "F(3.22) upper boundary w^2 = 4 sech(gamma h/2)/h^2, by bisection", 3, "upper"),
    ("csv1-lower", "csv1", 1.0, 2.0, lambda w, g: h_csv1_lower(w, g),
     "F(3.17) lower boundary h^2 w^2/2 = 1 - sech(gamma h) (over-damped w < gamma), by bisection",
     1, "lower"),
    ("csv2-lower", "csv2", 1.0, 1.2, lambda w, g: h_csv2_lower(w, g),
     "F(3.22) lower boundary w^2 = gamma^2 sech(gamma h/2), closed form h = (2/gamma) arccosh(gamma^2/w^2)"
     " (gamma h < 2)", 1, "lower"),
    ("stormer-verlet", "stormer-verlet", 1.0, 0.0, lambda w, g: 2.0 / w,
     "absolute stability of Stormer-Verlet on the undamped oscillator, closed form h w = 2", 500, "upper"),
    ("symplectic-euler", "symplectic-euler", 1.0, 0.0, lambda w, g: 2.0 / w,
     "absolute stability of symplectic Euler on the undamped oscillator, closed form h w = 2", 500, "upper"),
    ("rk3", "rk3", 1.0, 0.0, lambda w, g: math.sqrt(3.0) / w,
     "imaginary-axis stability limit of rk3, |R(iy)|^2 = 1 - y^4/12 + y^6/36 = 1 at h w = sqrt(3)", 500, "upper"),
    ("rk4", "rk4", 1.0, 0.0, lambda w, g: 2.0 * math.sqrt(2.0) / w,
     "imaginary-axis stability limit of rk4, |R(iy)|^2 = 1 - y^6/72 + y^8/576 = 1 at h w = 2 sqrt(2)", 500, "upper"),
    ("euler", "euler", 1.0, 0.5, lambda w, g: 2.0 * g / (w * w),
     "absolute stability of explicit Euler at lambda = -gamma +- i beta: |1 + h lambda| = 1 at h = 2 gamma/w^2",
     500, "upper"),
    ("heun", "heun", 1.0, 0.3, lambda w, g: h_rk_power("heun", w, g),
     "absolute stability of Heun at lambda = -gamma +- i beta: |1 + z + z^2/2| = 1 at z = h lambda, by bisection",
     500, "upper"),
]

CONFORMAL = {"csv1", "csv2"}


def g17(x: Any) -> float:
    return float("%.17g" % x)


def fmt(x: Any) -> str:
    return "%.6g" % x


def expect_bounded(ex: Dict[str, Any], method: str, dt: Any, label: str, p: Dict[str, Any], conformal: bool) -> None:
    """The checks of a run predicted bounded at `label` h* (p: the prediction from M)."""
    ex["bounded run at %s h*: completes every step" % label] = {
        "metric": "run.ok", "methods": [method], "dt": dt, "ge": 1,
        "note": "%d steps, rho(M) = %s <= 1" % (p["n"], fmt(p["rho"]))}
    ex["bounded run at %s h*: power-bounded M" % label] = {
        "metric": "stability.power_bounded", "methods": [method], "dt": dt, "ge": 1}
    bound = g17(1.01 * p["err"] + 1e-300)
    ex["bounded run at %s h*: error over the output grid as predicted" % label] = {
        "metric": "error.max_abs", "methods": [method], "dt": dt, "le": bound,
        "note": "iterating the closed-form M over the %d steps gives max error %s on the output "
                "grid against the exact solution; 1%% margin (a growing mode, e.g. rho = 1 + 1e-4, "
                "would exceed it)" % (p["n"], fmt(p["err"]))}
    if conformal and p["F"]:
        ex["bounded run at %s h*: e^{2 gamma t} H_gamma stays bounded" % label] = {
            "metric": "invariants.H_gamma.max_global_ratio_dev", "methods": [method], "dt": dt,
            "le": g17(1.01 * p["inv"]),
            "note": "inside F's region both eigenvalues have modulus e^{-gamma h}: the conformal "
                    "energy oscillates on the modified ellipse, max |e^{2 gamma t}H_gamma/H_gamma(0) - 1| "
                    "= %s by iterating M (1%% margin)" % fmt(p["inv"])}
    elif conformal:
        ex["bounded run at %s h*, outside F's region: e^{2 gamma t} H_gamma grows" % label] = {
            "metric": "invariants.H_gamma.max_global_ratio_dev", "methods": [method], "dt": dt,
            "ge": 1e6, "negative_control": True,
            "note": "outside F's region the eigenvalues are real, one of modulus > e^{-gamma h}: the "
                    "run stays bounded (rho(M) = %s < 1) but e^{2 gamma t} H_gamma grows; iterating M "
                    "gives max %s" % (fmt(p["rho"]), fmt(p["inv"]))}


def expect_unbounded(ex: Dict[str, Any], method: str, dt: Any, label: str, p: Dict[str, Any], suffix: Any) -> None:
    """The checks of a run predicted unbounded at `label` h*: diverged at the predicted step."""
    if p["F"]:
        ex["unbounded at %s h* although F's condition holds" % label] = {
            "metric": "stability.F_condition", "methods": [method], "dt": dt, "ge": 1,
            "note": "|tr M/2| < e^{-gamma h} but det M = %s != e^{-2 gamma h}: for a method that is "
                    "not conformal symplectic F's condition is not boundedness (conventions §6)"
                    % fmt(np.linalg.det(p["M"]))}
    ex["unbounded at %s h*: M not power-bounded" % label] = {
        "metric": "stability.power_bounded", "methods": [method], "dt": dt, "le": 0,
        "negative_control": True,
        "note": "rho(M) = %s > 1" % fmt(p["rho"])}
    assert p["div"] is not None, (suffix, label, "predicted no divergence within the run")
    ex["unbounded at %s h*: the run is reported diverged" % label] = {
        "metric": "run.diverged", "methods": [method], "dt": dt, "ge": 1,
        "negative_control": True,
        "note": "status 'diverged' is a reported result, not a crash"}
    tol = max(2, math.ceil(0.002 * p["div"]))
    ex["unbounded at %s h*: diverges at the predicted step" % label] = {
        "metric": "run.failed_at_step", "methods": [method], "dt": dt,
        "near": p["div"], "tol": tol,
        "note": "iterating the closed-form M from (1, 0), |z_i| first exceeds 1e100 at step %d "
                "(~ ln(1e100)/ln(rho) = %d); tolerance %d steps" % (
                    p["div"], round(math.log(1e100) / math.log(p["rho"])), tol)}


def make_case(suffix: Any, method: str, w: Any, g: Any, solve: Any, how: Any, m: Any, side: Any) -> Any:
    hstar = solve(w, g)
    if method == "euler":  # cross-check the closed form with the stability polynomial
        assert abs(hstar - h_rk_power("euler", w, g)) < 1e-12 * hstar
    if method in ("rk3", "rk4"):
        assert abs(hstar - h_rk_power(method, w, g)) < 1e-9 * hstar
    dts = [r17(0.99 * hstar), r17(1.01 * hstar)]
    t_end = r17(101 * m * dts[0])
    output_dt = r17(t_end / m)
    steps = [round(t_end / dt) for dt in dts]
    assert all(abs(n * dt - t_end) <= 1e-12 * t_end for n, dt in zip(steps, dts))
    inside = dts[0] if side == "upper" else dts[1]
    outside = dts[1] if side == "upper" else dts[0]
    pred = {}
    for dt, n in zip(dts, steps):
        M = one_step(method, w, g, dt)
        every = round(output_dt / dt)
        div, err, inv = iterate(M, w, g, dt, n, every)
        pred[dt] = dict(M=M, n=n, rho=spectral_radius(M), F=f_condition(M, g, dt),
                        pb=spectral_radius(M) <= 1.0 + 1e-12, div=div, err=err, inv=inv)
    conformal = method in CONFORMAL
    ex: Dict[str, Any] = {}
    which = "0.99" if inside == dts[0] else "1.01"
    other = "1.01" if which == "0.99" else "0.99"
    # F's condition: the statement of F(3.17)/(3.22) for csv1/csv2; for the others it is reported
    # (conventions §6: F's condition is not boundedness for a method that is not conformal symplectic).
    if conformal:
        ex["F's condition holds at %s h* (inside F's region)" % which] = {
            "metric": "stability.F_condition", "methods": [method], "dt": inside, "ge": 1,
            "note": "h* = %.17g: %s" % (hstar, how)}
        ex["F's condition fails at %s h* (outside F's region)" % other] = {
            "metric": "stability.F_condition", "methods": [method], "dt": outside, "le": 0,
            "negative_control": True,
            "note": "the one-step matrix leaves F's region as (3.17)/(3.22) predict"}
    for dt, label in ((dts[0], "0.99"), (dts[1], "1.01")):
        p = pred[dt]
        ex["spectral radius at %s h* as M's closed form" % label] = {
            "metric": "stability.spectral_radius", "methods": [method], "dt": dt,
            "near": g17(p["rho"]), "tol": g17(1e-9 * p["rho"]),
            "note": "rho(M) = %s from the closed-form one-step matrix (verify/stress_thresholds.py); "
                    "h* = %.17g: %s" % (fmt(p["rho"]), hstar, how)}
        if p["pb"]:
            expect_bounded(ex, method, dt, label, p, conformal)
        else:
            expect_unbounded(ex, method, dt, label, p, suffix)
    region = "F's region" if conformal else "its absolute-stability region"
    case = {
        "id": "stress-threshold-" + suffix,
        "title": "%s at 0.99 h* and 1.01 h* of %s (omega = %g, gamma = %g)" % (method, region, w, g),
        "source": "F(3.15)-(3.22), conventions §5; verify/stress_thresholds.py",
        "suites": ["stress"],
        "notes": ("h* = %.17g (%s). dt_ladder = [0.99 h*, 1.01 h*] rounded to 17 significant digits; "
                  "t_end = 101*%d*(0.99 h*) = 99*%d*(1.01 h*), output every 101 resp. 99 steps. Written by "
                  "verify/stress_thresholds.py; tests/test_stress_thresholds.cpp recomputes h* and checks "
                  "these numbers." % (hstar, how, m, m)),
        "problem": {"id": "oscillator", "omega": w, "gamma": g, "q0": 1.0, "p0": 0.0},
        "methods": [method],
        "t_end": t_end,
        "dt_ladder": dts,
        "output_dt": output_dt,
        "diagnostics": ["stability", "error"] + (["invariants"] if conformal else []),
        "expect": ex,
    }
    summary = {dt: {k: v for k, v in pred[dt].items() if k != "M"} for dt in dts}
    for dt in dts:
        summary[dt]["det"] = float(np.linalg.det(pred[dt]["M"]))
    return case, hstar, summary


def main() -> None:
    for row in THRESHOLDS:
        case, hstar, summary = make_case(*row)
        path = os.path.join(CASES, case["id"] + ".json")
        with open(path, "w") as f:
            json.dump(case, f, indent=2, ensure_ascii=False)
            f.write("\n")
        print("%-40s h* = %.17g" % (case["id"], hstar))
        for dt, s in summary.items():
            print("    dt = %.17g: steps %d, rho %.9g, F %s, bounded %s, diverged at %s, max err %.3g, "
                  "max H_gamma rel %.3g" % (dt, s["n"], s["rho"], s["F"], s["pb"], s["div"], s["err"],
                                             s["inv"]))


if __name__ == "__main__":
    main()
