"""Closed-form values of the oscillator's error metrics for methods whose step is a known matrix.

On the linear oscillator z' = A z, A = [[0, 1], [-w^2, -2g]] (q'' + 2g q' + w^2 q = 0, p = q'), a
step of every method named in STEP_MATRIX is z_{n+1} = M(h) z_n with M a closed form: an s-stage
explicit Runge-Kutta method of order s (s <= 4) has the Taylor polynomial sum_{k<=s} (hA)^k/k!
(HLW II.1; euler, heun, rk3, rk4), and cimp is e^{-gh} times the Cayley transform of (h/2)N with
N = A + gI, the conformal form (F (2.3)). The exact flow is e^{At} = e^{-gt}[cos(bt) I + sin(bt)/b
(A + gI)], b = sqrt(w^2 - g^2) (g < w). So every error metric and measure of dampsym's error
diagnostic (docs/case-keys.md) over the output grid has a value computed here in 40-digit
arithmetic, independently of dampsym's step loop, its error accumulator and its measures: the
case verify/cases/osc-closed-form.json checks them with `near` (osc-order-window: a local-order
fit), and verify/tests/test_closed_form.py checks that the cases' numbers are these and that their
tolerances see a 1e-7 relative change.

    python3 -m verify.closed_form verify/cases/osc-closed-form.json   # print the expect block
"""
from __future__ import annotations

import json
import sys
from typing import Any, Callable, Dict, List, Sequence

import mpmath

Matrix = List[List[mpmath.mpf]]
Vector = List[mpmath.mpf]

mpmath.mp.dps = 40

# The relative tolerance of every closed-form check: 1e-9 of the value (dampsym's round-off in
# these metrics is below 1e-12 relative; a 1e-7 relative defect is 100x the tolerance).
REL_TOL = 1e-9

# The metrics checked against their closed form (with every measure.* of the case).
METRICS = ["error.final_abs", "error.max_abs", "error.mean_abs", "error.final_rel"]


def _mul(a: Matrix, b: Matrix) -> Matrix:
    return [[a[i][0] * b[0][j] + a[i][1] * b[1][j] for j in range(2)] for i in range(2)]


def _add(a: Matrix, b: Matrix, s: mpmath.mpf) -> Matrix:
    return [[a[i][j] + s * b[i][j] for j in range(2)] for i in range(2)]


def _eye() -> Matrix:
    return [[mpmath.mpf(1), mpmath.mpf(0)], [mpmath.mpf(0), mpmath.mpf(1)]]


def _apply(m: Matrix, z: Vector) -> Vector:
    return [m[0][0] * z[0] + m[0][1] * z[1], m[1][0] * z[0] + m[1][1] * z[1]]


def _taylor(a: Matrix, h: mpmath.mpf, order: int) -> Matrix:
    """sum_{k <= order} (hA)^k / k!: the step matrix of an explicit RK method of order = stages."""
    out, term = _eye(), _eye()
    for k in range(1, order + 1):
        term = [[x * h / k for x in row] for row in _mul(term, a)]
        out = _add(out, term, mpmath.mpf(1))
    return out


def _cimp(a: Matrix, g: mpmath.mpf, h: mpmath.mpf) -> Matrix:
    """e^{-gh} (I - (h/2)N)^{-1} (I + (h/2)N), N = A + gI (cimp.hpp: the midpoint's Cayley map)."""
    n = _add(a, _eye(), g)
    lhs = mpmath.matrix(_add(_eye(), n, -h / 2))
    rhs = mpmath.matrix(_add(_eye(), n, h / 2))
    m = mpmath.exp(-g * h) * (lhs ** -1) * rhs
    return [[m[i, j] for j in range(2)] for i in range(2)]


STEP_MATRIX: Dict[str, Callable[[Matrix, mpmath.mpf, mpmath.mpf], Matrix]] = {
    "euler": lambda a, g, h: _taylor(a, h, 1),
    "heun": lambda a, g, h: _taylor(a, h, 2),
    "rk3": lambda a, g, h: _taylor(a, h, 3),
    "rk4": lambda a, g, h: _taylor(a, h, 4),
    "cimp": _cimp,
}


def exact(w: mpmath.mpf, g: mpmath.mpf, t: mpmath.mpf, z0: Vector) -> Vector:
    b = mpmath.sqrt(w * w - g * g)
    a = [[mpmath.mpf(0), mpmath.mpf(1)], [-w * w, -2 * g]]
    flow = _add([[mpmath.cos(b * t), mpmath.mpf(0)], [mpmath.mpf(0), mpmath.cos(b * t)]],
                _add(a, _eye(), g), mpmath.sin(b * t) / b)
    return [mpmath.exp(-g * t) * x for x in _apply(flow, z0)]


def _norm(v: Sequence[mpmath.mpf]) -> mpmath.mpf:
    return mpmath.sqrt(sum(x * x for x in v))


def metrics(case: Dict[str, object], method: str) -> Dict[str, float]:
    """error.* and measure.* of `method` on the oscillator case (one dt, output grid t_1..t_end)."""
    prob = case["problem"]
    assert isinstance(prob, dict) and prob["id"] == "oscillator"
    w, g = mpmath.mpf(prob.get("omega", 1.0)), mpmath.mpf(prob.get("gamma", 0.0))
    z0 = [mpmath.mpf(prob.get("q0", 1.0)), mpmath.mpf(prob.get("p0", 0.0))]
    t0, t_end = mpmath.mpf(case.get("t0", 0.0)), mpmath.mpf(case["t_end"])
    h = mpmath.mpf(case["dt"])
    out_dt = mpmath.mpf(case.get("output_dt", t_end - t0))
    steps_per_point = int(mpmath.nint(out_dt / h))
    points = int(mpmath.nint((t_end - t0) / out_dt))
    a = [[mpmath.mpf(0), mpmath.mpf(1)], [-w * w, -2 * g]]
    m = STEP_MATRIX[method](a, g, h)
    big = _eye()
    for _ in range(steps_per_point):
        big = _mul(m, big)
    energy = lambda v: (v[1] * v[1] + w * w * v[0] * v[0]) / 2  # noqa: E731 (oscillator.hpp)
    z, rows = z0, []
    for k in range(1, points + 1):
        z = _apply(big, z)
        x = exact(w, g, k * out_dt, z0)
        e, de = _norm([z[0] - x[0], z[1] - x[1]]), abs(energy(z) - energy(x))
        rows.append({"state.abs": e, "state.rel": e / _norm(x), "p.abs": abs(z[1] - x[1]),
                     "energy-error.abs": de, "energy-error.rel": de / energy(x)})
    return _reduce(rows, case)


def _reduce(rows: List[Dict[str, mpmath.mpf]], case: Dict[str, object]) -> Dict[str, float]:
    """The error diagnostic's metrics and the case's measures (mean over t_1..t_end)."""
    n = len(rows)
    e = [r["state.abs"] for r in rows]
    out = {"error.final_abs": e[-1], "error.max_abs": max(e), "error.mean_abs": sum(e) / n,
           "error.final_rel": rows[-1]["state.rel"],
           "error.max_rel": max(r["state.rel"] for r in rows)}
    measures = case.get("measures", {})
    assert isinstance(measures, dict)
    for name, spec in measures.items():
        what = spec.get("component", "state")
        if spec.get("quantity", "error") == "energy-error":
            what = "energy-error"
        v = [r[what + "." + spec.get("norm", "abs")] for r in rows]
        out["measure." + name] = {"final": v[-1], "max": max(v), "mean": sum(v) / n,
                                  "rms": mpmath.sqrt(sum(x * x for x in v) / n)}[spec["over"]]
    return {k: float(x) for k, x in out.items()}


def local_order_fit(case: Dict[str, object], method: str) -> Dict[str, Any]:
    """The local-order fit (docs/conventions.md §5, verify/refmath.py fit_order) of `method`'s
    one-step errors from the initial state over the case's ladder, in closed form."""
    from verify.refmath import fit_order
    prob = case["problem"]
    assert isinstance(prob, dict) and prob["id"] == "oscillator"
    w, g = mpmath.mpf(prob.get("omega", 1.0)), mpmath.mpf(prob.get("gamma", 0.0))
    z0 = [mpmath.mpf(prob.get("q0", 1.0)), mpmath.mpf(prob.get("p0", 0.0))]
    a = [[mpmath.mpf(0), mpmath.mpf(1)], [-w * w, -2 * g]]
    dts = case["dt_ladder"]
    assert isinstance(dts, list)
    errs = []
    for h in dts:
        z, x = _apply(STEP_MATRIX[method](a, g, mpmath.mpf(h)), z0), exact(w, g, mpmath.mpf(h), z0)
        errs.append(float(_norm([z[0] - x[0], z[1] - x[1]])))
    fit: Dict[str, Any] = fit_order(dts, errs, floor=0.0)
    return fit


def expect_block(case: Dict[str, object]) -> Dict[str, Dict[str, object]]:
    """One `near` check per method of the case and metric of METRICS (its measures included)."""
    out: Dict[str, Dict[str, object]] = {}
    methods = case["methods"]
    assert isinstance(methods, list)
    for method in methods:
        vals = metrics(case, method)
        for metric in METRICS + sorted(k for k in vals if k.startswith("measure.")):
            v = vals[metric]
            out["%s %s closed form" % (method, metric)] = {
                "metric": metric, "methods": [method], "near": float("%.15e" % v),
                "tol": float("%.2e" % (REL_TOL * abs(v)))}
    return out


def main(argv: List[str]) -> int:
    with open(argv[0], encoding="utf-8") as f:
        case = json.load(f)
    print(json.dumps(expect_block(case), indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
