#!/usr/bin/python3
"""Explicit Klein-Gordon scheme (B (5.3) = csv1, bench/bench_pde.cpp) against scipy's
solve_ivp(RK45) on the same semi-discrete system, side by side (issue 15 item 7, docs/benchmarks.md).

    /usr/bin/python3 bench/pde_scipy.py BENCH_RAW_JSON      (prints JSON; called by bench_report.py)

For each M of pde/kg-csv1/M in the benchmark output: the semi-discrete damped Klein-Gordon system
u' = v, v' = (delta_x^2 - c) u - 2 gamma v (B (5.2)) from B (5.1)'s plane wave (gamma = 0.375,
c = 1, K = 1, verify/xproblems.KleinGordon, whose exact solution mode by mode is the yardstick) is
solved by RK45 over the same [0, t_end] at rtol = 1e-3, 1e-4, ..., 1e-12 (atol = 1e-3 rtol); the
loosest rtol whose max-norm final error is <= csv1's error (counter `error`) is "matching
accuracy", and its CPU time (minimum of 3) is set against csv1's (ns_per_step x steps).
"""
import json
import math
import os
import sys
import time

import numpy as np
from scipy.integrate import solve_ivp

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "verify"))
from bench_report import load_benchmarks, value  # noqa: E402
import xproblems as xp  # noqa: E402


def main():
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    _, runs = load_benchmarks(sys.argv[1])
    out = []
    for M in (256, 512, 1024, 2048):
        name = f"pde/kg-csv1/{M}"
        err = value(runs, name, "error")
        if err is None:
            continue
        t_end, h = value(runs, name, "t_end"), value(runs, name, "h")
        steps = round(t_end / h)
        csv1_cpu = value(runs, name, "ns_per_step") * steps * 1e-9
        prob = xp.KleinGordon(M, 1.0, 0.375, 1)
        exact = np.asarray(prob.exact(0.0, t_end)).reshape(-1)
        chosen = None
        for k in range(3, 13):
            rtol = 10.0 ** (-k)
            sol = solve_ivp(lambda t, z: prob.f(t, z), (0.0, t_end), prob.z0, method="RK45",
                            rtol=rtol, atol=1e-3 * rtol)
            e = float(np.max(np.abs(sol.y[:, -1] - exact)))
            if sol.success and e <= err:
                chosen = (rtol, e, int(sol.nfev))
                break
        row = {"M": M, "t_end": t_end, "csv1_h": h, "csv1_steps": steps, "csv1_error": err,
               "csv1_cpu_seconds": csv1_cpu, "rk45": None}
        if chosen:
            rtol, e, nfev = chosen
            cpu = []
            for _ in range(3):
                c0 = time.process_time()
                solve_ivp(lambda t, z: prob.f(t, z), (0.0, t_end), prob.z0, method="RK45",
                          rtol=rtol, atol=1e-3 * rtol)
                cpu.append(time.process_time() - c0)
            row["rk45"] = {"rtol": rtol, "atol": 1e-3 * rtol, "error": e, "nfev": nfev,
                           "cpu_seconds": min(cpu), "cpu_ratio_rk45_over_csv1": min(cpu) / csv1_cpu}
        out.append(row)
    json.dump(out, sys.stdout, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
