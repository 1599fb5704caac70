"""Verify your own method from Python (docs/python.md), as in a notebook: a tableau and a step
given as a Python function, through dampsym's matrix battery, with the verdicts printed.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/verify_my_method.py
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

import dampsym

# 1. A tableau: the 1-stage Gauss method (implicit midpoint) under the integrating factor, which
#    makes it conformal symplectic (B Thm 2.6). Exact strings or numbers, as in a method file.
midpoint = dampsym.Tableau([["1/2"]], [1], ["1/2"], id="my-if-midpoint", order=2,
                           integrating_factor=True, claims=["conformal-symplectic"])


# 2. A step as a function: conformal Stormer-Verlet (F (2.12), B (2.20)) on the separable form
#    q' = grad T(p), p' = F(q, t) - 2 gamma(t) p, using the problem's callbacks.
def my_csv1(t: float, z: NDArray[np.float64], h: float, problem: Any) -> NDArray[np.float64]:
    n = z.size // 2
    q, p = z[:n], z[n:]
    hh = 0.5 * h
    p1 = problem.damping_factor(t, hh) * p + hh * problem.force(t, q)
    q1 = q + h * problem.grad_T(p1)
    p1 = problem.damping_factor(t + hh, hh) * (p1 + hh * problem.force(t + h, q1))
    return np.concatenate([q1, p1])


step = dampsym.Step(my_csv1, id="my-csv1", order=2, claims=["conformal-symplectic"])

# 3. The coefficient checks of the tableau, then the matrix of both beside the built-in csv1.
for c in midpoint.checks():
    print(f"{midpoint.id}: {c['name']}: {'agrees' if c['agrees'] else 'DISAGREES'}")
m = dampsym.matrix(methods=[midpoint, step, "csv1"])
for row in m["methods"]:
    cells = row["cells"]
    verdicts = ", ".join(f"{p} {cells[p]['verdict']}" for p in ("order", "en-pendulum", "en-hill")
                         if p in cells)
    print(f"{row['id']:>16}: {verdicts}")
print("every claim holds" if m.exit_status == 0 else "a claimed property FAILS")
raise SystemExit(m.exit_status)
