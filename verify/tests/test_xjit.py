#!/usr/bin/python3
"""The compiled step loops (verify/xjit.py, python3-numba) against the cross-check's plain-Python
loops (verify/xscalar.py, verify/xmethods.py): bit-identical final states, trajectories, GLM
states, step counts, statuses and Newton iteration counts on Kepler, the rigid body, the driven
pendulum and the outer solar system; on argon (Lennard-Jones powers: numpy's vectorised pow
against libm's) within 1e-12 relative over 500 steps.  Negative control: a compiled run with
h one ulp larger must be reported as different.

    /usr/bin/python3 -m pytest verify/tests/test_xjit.py      (skipped without numba)
"""
from __future__ import annotations

import math
from typing import Any, Dict, List, Tuple

import numpy as np
import pytest

from verify import xjit
from verify import xproblems as xp
from verify import xrun

CASES = [   # problem, parameters, methods, h, steps, t0
    ("kepler", {"e": 0.6}, ["euler", "rk4", "symplectic-euler", "stormer-verlet", "implicit-midpoint",
                            "gauss2"], 0.01, 2000, 0.0),
    ("rigid-body", {"I1": 4.0, "I2": 3.0, "I3": 2.0, "epsilon": 0.3, "z1": 4.0, "z2": 3.0, "z3": 0.5},
     ["rk4", "heun", "glm4", "gauss1", "gauss3", "implicit-midpoint"], 0.05, 1500, 0.7),
    ("driven-pendulum", {"f": 3.375, "gamma": 0.375, "lambda": 1.5, "p0": 0.0, "q0": 0.0},
     ["heun", "rk3", "csv1", "csv2", "cimp", "glifrk2", "glifrk3", "gauss2"], 0.05, 2000, 0.0),
    ("outer-solar-system", {"gamma": 0.0}, ["euler", "symplectic-euler", "stormer-verlet",
                                            "implicit-midpoint"], 10.0, 1000, 0.0),
    ("outer-solar-system", {"gamma": 0.001}, ["implicit-midpoint"], 10.0, 300, 0.0),  # solve fails
    ("pendulum", {"gamma": 0.05, "q0": 2.5, "p0": 0.0}, ["euler", "heun", "rk3", "rk4", "csv1", "csv2",
                                                          "cimp"], 0.1, 3000, 0.0),
    ("oscillator", {"omega": 1.0, "gamma": 0.1, "q0": 1.0, "p0": 0.0}, ["euler", "heun", "rk3", "rk4",
                                                                         "csv1", "csv2", "cimp"], 0.3, 2000, 0.0),
    ("pendulum", {"gamma": 0.0, "q0": 1.0, "p0": 0.5}, ["euler"], 1.9, 400, 0.0),     # diverges
    ("argon", {"gamma": 0.0}, ["euler", "symplectic-euler", "stormer-verlet", "implicit-midpoint"],
     1e-5, 500, 0.0),
]
KEYS = ("steps", "status", "message", "newton", "newton_max")


Out = Dict[str, Any]


def run(method: str, prob: Any, h: float, n: int, t0: float, compiled: bool) -> Out:
    xjit.HAVE_NUMBA = compiled
    try:
        return xrun.integrate(method, prob, h, n, t0, record=True)
    finally:
        xjit.HAVE_NUMBA = True


def differs(a: Out, b: Out, rel: float) -> str:
    """'' when a and b agree (bit for bit when rel is 0), else what differs."""
    if not a.get("compiled"):
        return "the compiled loop was not used"
    for k in KEYS:
        if a[k] != b[k] and not (rel and k == "newton"):
            return "%s %r != %r" % (k, a[k], b[k])
    for k in ("z", "traj", "glm_y"):
        if (k in a) != (k in b):
            return "%s present on one side only" % k
        if k not in a or a[k] is None:
            continue
        x, y = np.asarray(a[k]), np.asarray(b[k])
        if k == "traj" and a["status"] == "solve-failed":
            # xrun returns rows 0..n for a failure at step n; row n was never written (both sides)
            x, y = x[:a["steps"]], y[:b["steps"]]
        if x.shape != y.shape:
            return "%s shape %s != %s" % (k, x.shape, y.shape)
        if rel == 0.0:
            if not np.array_equal(x, y, equal_nan=True):
                return "%s not bit-identical (max |diff| %.3g)" % (k, float(np.nanmax(np.abs(x - y))))
        elif np.max(np.abs(x - y)) > rel * np.max(np.abs(y)):
            return "%s differs by %.3g relative" % (k, float(np.max(np.abs(x - y)) / np.max(np.abs(y))))
    return ""


needs_numba = pytest.mark.skipif(not xjit.HAVE_NUMBA, reason="python3-numba not available")
RUNS: List[Tuple[str, Dict[str, float], str, float, int, float]] = [
    (pid, par, m, h, n, t0) for pid, par, methods, h, n, t0 in CASES for m in methods]


@needs_numba
@pytest.mark.parametrize("pid,par,method,h,n,t0", RUNS, ids=["%s-%s-%d" % (r[0], r[2], i) for i, r in enumerate(RUNS)])
def test_compiled_equals_plain(pid: str, par: Dict[str, float], method: str, h: float, n: int, t0: float) -> None:
    """Bit for bit (argon: 1e-12 relative, numpy's vectorised pow against libm's)."""
    prob = xp.make_problem(pid, par)
    rel = 1e-12 if pid == "argon" else 0.0
    why = differs(run(method, prob, h, n, t0, True), run(method, prob, h, n, t0, False), rel)
    assert why == ""


@needs_numba
def test_one_ulp_is_seen() -> None:
    """Negative control: a compiled run with h one ulp larger differs from the plain one."""
    prob = xp.make_problem("kepler", {"e": 0.6})
    a = run("stormer-verlet", prob, math.nextafter(0.01, 1.0), 2000, 0.0, True)
    b = run("stormer-verlet", prob, 0.01, 2000, 0.0, False)
    assert differs(a, b, 0.0) != ""
