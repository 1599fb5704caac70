#!/usr/bin/python3
"""Explicit Klein-Gordon scheme (B (5.3) = csv1) against scipy's solve_ivp(RK45) on the same
semi-discrete system: a work-precision comparison (docs/benchmarks.md, docs/pde.md).

    /usr/bin/python3 bench/pde_scipy.py BENCH_RAW_JSON      (prints JSON; called by ci/bench.sh)

System: B (5.2), u' = v, v' = (delta_x^2 - c) u - 2 gamma v on M points of [-pi, pi) (gamma = 0.375,
c = 1), over t in [0, 10], from two initial states: B (5.1)'s plane wave (K = 1, one Fourier mode)
and a pulse u = exp(-4 x^2), v = 0 (every mode, so that the stiff modes of the grid are present).
The yardstick is the exact solution of the semi-discrete system, mode by mode (verify/xpde.py).

- csv1 at h = 0.8, 0.4, 0.2, 0.1 Delta x (its stability limit is h < Delta x): the error is that
  of the scheme (the numpy replica of verify/xpde.py, which the cross-check holds to dampsym's own
  runs); its CPU time is dampsym's, steps x ns per step of the benchmark pde/kg-csv1/M (the cost per
  step does not depend on h or on the state); 2 force evaluations per step.
- RK45 at rtol = 1e-3, 1e-4, ..., 1e-10 (atol = 1e-3 rtol): error, function evaluations, CPU
  time (one solve; minimum of 4 for the matched runs).
- Matched rows: for each csv1 step, the RK45 run with the fewest function evaluations whose error
  is at most csv1's, and the ratios of function evaluations (independent of the language) and of
  CPU time (scipy's steps are interpreted Python: this ratio includes that overhead).
On these grids RK45 is held by stability, not accuracy: its evaluations hardly change with rtol.
"""
import json
import math
import os
import sys
import time
from typing import Any, Callable, Dict, List, Tuple

import numpy as np
from scipy.integrate import solve_ivp

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "verify"))
from bench_report import load_benchmarks, value  # noqa: E402
from xpde import KG  # type: ignore[import]  # noqa: E402

GAMMA, C, T_END = 0.375, 1.0, 10.0
H_FRACTIONS = (0.8, 0.4, 0.2, 0.1)
RTOLS = [10.0 ** (-k) for k in range(3, 11)]


def initial(kg: Any, kind: str) -> Tuple[np.ndarray, np.ndarray]:
    if kind == "plane-wave":
        u, v = kg.initial()
        return u, v
    return np.exp(-4.0 * kg.x ** 2), np.zeros(kg.M)


def error(kg: Any, exact: Tuple[np.ndarray, np.ndarray], u: np.ndarray,
          v: np.ndarray) -> float:
    return float(max(np.max(np.abs(u - exact[0])), np.max(np.abs(v - exact[1]))))


def csv1_points(kg: Any, u0: np.ndarray, v0: np.ndarray, exact: Tuple[np.ndarray, np.ndarray],
                ns_per_step: float) -> List[Dict[str, Any]]:
    out: List[Dict[str, Any]] = []
    for frac in H_FRACTIONS:
        steps = math.ceil(T_END / (frac * kg.dx))
        h = T_END / steps
        u, v = u0.copy(), v0.copy()
        for _ in range(steps):
            u, v = kg.step("csv1", h, u, v)
        out.append({"h": h, "h_over_dx": h / kg.dx, "steps": steps, "rhs_evals": 2 * steps,
                    "error": error(kg, exact, u, v), "cpu_seconds": ns_per_step * steps * 1e-9})
    return out


def rk45_points(kg: Any, u0: np.ndarray, v0: np.ndarray,
                exact: Tuple[np.ndarray, np.ndarray]) -> List[Dict[str, Any]]:
    M = kg.M

    def f(_t: float, z: np.ndarray) -> np.ndarray:
        u, v = z[:M], z[M:]
        return np.concatenate([v, kg.force(u) - 2.0 * GAMMA * v])

    z0 = np.concatenate([u0, v0])
    out: List[Dict[str, Any]] = []
    for rtol in RTOLS:
        c0 = time.process_time()
        sol = solve_ivp(f, (0.0, T_END), z0, method="RK45", rtol=rtol, atol=1e-3 * rtol)
        cpu = time.process_time() - c0
        if sol.success:
            out.append({"rtol": rtol, "atol": 1e-3 * rtol, "rhs_evals": int(sol.nfev),
                        "error": error(kg, exact, sol.y[:M, -1], sol.y[M:, -1]),
                        "cpu_seconds": cpu, "retime": lambda r=rtol: retime(f, z0, r)})
    return out


def retime(f: Callable[[float, np.ndarray], np.ndarray], z0: np.ndarray,
           rtol: float) -> float:
    """Minimum CPU time of 3 more solves (for the matched rows)."""
    cpu = []
    for _ in range(3):
        c0 = time.process_time()
        solve_ivp(f, (0.0, T_END), z0, method="RK45", rtol=rtol, atol=1e-3 * rtol)
        cpu.append(time.process_time() - c0)
    return min(cpu)


def matched(csv1: List[Dict[str, Any]], rk45: List[Dict[str, Any]]) -> List[Dict[str, Any]]:
    rows: List[Dict[str, Any]] = []
    for p in csv1:
        ok = [r for r in rk45 if r["error"] <= p["error"]]
        best = min(ok, key=lambda r: r["rhs_evals"]) if ok else None
        row: Dict[str, Any] = {"csv1_h_over_dx": p["h_over_dx"], "error": p["error"], "rk45": None}
        if best:
            if "retimed" not in best:
                best["retimed"] = min(best["cpu_seconds"], best.pop("retime")())
            row["rk45"] = {"rtol": best["rtol"], "error": best["error"],
                           "rhs_evals": best["rhs_evals"], "cpu_seconds": best["retimed"],
                           "rhs_ratio_rk45_over_csv1": best["rhs_evals"] / p["rhs_evals"],
                           "cpu_ratio_rk45_over_csv1": best["retimed"] / p["cpu_seconds"]}
        rows.append(row)
    for r in rk45:
        r.pop("retime", None)
        if "retimed" in r:
            r["cpu_seconds"] = r.pop("retimed")
    return rows


def main() -> int:
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    _, runs = load_benchmarks(sys.argv[1])
    out: List[Dict[str, Any]] = []
    for M in (256, 1024):
        ns = value(runs, f"pde/kg-csv1/{M}", "ns_per_step")
        if ns is None:
            continue
        kg = KG(M, C, GAMMA, 1)
        for kind in ("plane-wave", "pulse"):
            u0, v0 = initial(kg, kind)
            exact = kg.exact_semidiscrete(u0, v0, T_END)
            csv1 = csv1_points(kg, u0, v0, exact, ns)
            rk45 = rk45_points(kg, u0, v0, exact)
            out.append({"M": M, "initial": kind, "t_end": T_END, "gamma": GAMMA, "c": C,
                        "csv1_ns_per_step": ns, "csv1": csv1, "rk45": rk45,
                        "matched": matched(csv1, rk45)})
    json.dump(out, sys.stdout, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
