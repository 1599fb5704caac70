#!/usr/bin/python3
"""The Python API's overhead (docs/python.md "Cost"): the same case, 10^7 pendulum steps of the
built-in csv1 (bench/cases/run-pendulum-1e7.json, no diagnostic, --time-budget 0), run by the
command line (`dampsym run`, a whole process: start, run, report files) and by dampsym.run in
this process (run and report parsed into a dict), in alternating rounds; the ratio Python / CLI
of the wall times is the median over the rounds, accepted at <= 1.05 (and, for information, the
same ratio of the step loop alone, each run's wall time in its report). Then a step given as a
Python callable (csv1 written with numpy, the plugin kernel calling it) on the same problem:
its cost per step from the run's own wall time (report timings), against the built-in's.

Usage: PYTHONPATH=build/python bench/python_api.py DAMPSYM_BINARY [--repeats N] [--out-json F]
Exit status 1 if the ratio exceeds 1.05, 2 on a usage or input error.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from typing import Any

import numpy as np
from numpy.typing import NDArray

import dampsym  # type: ignore[import]  # the built module (python/), found at run time

HERE = os.path.dirname(os.path.abspath(__file__))
CASE = os.path.join(HERE, "cases", "run-pendulum-1e7.json")
LIMIT = 1.05


def run_wall(report: dict[str, Any]) -> float:
    """The run's own wall time (report timings): the step loop alone."""
    return float(report["timings"]["cases"][0]["runs"][0]["wall_seconds"])


def cli_seconds(binary: str, out: str) -> tuple[float, float]:
    start = time.perf_counter()
    p = subprocess.run([binary, "run", CASE, "--jobs", "1", "--time-budget", "0", "--out", out,
                        "--quiet"], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    seconds = time.perf_counter() - start
    if p.returncode != 0:
        sys.exit(f"python_api.py: dampsym run {CASE}: exit {p.returncode}: {p.stderr.strip()}")
    with open(os.path.join(out, "report.json")) as f:
        return seconds, run_wall(json.load(f))


def api_seconds() -> tuple[float, float]:
    start = time.perf_counter()
    report = dampsym.run(CASE, time_budget=0)
    seconds = time.perf_counter() - start
    assert report["cases"][0]["runs"][0]["status"] == "ok"
    return seconds, run_wall(report)


def py_csv1(t: float, z: NDArray[np.float64], h: float, problem: Any) -> NDArray[np.float64]:
    n = z.size // 2
    q, p = z[:n], z[n:]
    hh = 0.5 * h
    p1 = problem.damping_factor(t, hh) * p + hh * problem.force(t, q)
    q1 = q + h * problem.grad_T(p1)
    p1 = problem.damping_factor(t + hh, hh) * (p1 + hh * problem.force(t + h, q1))
    return np.concatenate([q1, p1])


def per_step_ns(method: str, steps: int) -> float:
    case = {"id": "bench-python-step", "title": "cost per step", "source": "bench",
            "problem": {"id": "pendulum", "gamma": 0.1}, "methods": [method],
            "t_end": steps * 0.01, "dt": 0.01, "diagnostics": [],
            "no_checks_because": "a timing case"}
    report = dampsym.run(case, time_budget=0)
    return 1e9 * float(report["timings"]["cases"][0]["runs"][0]["wall_seconds"]) / steps


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("binary")
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--out-json")
    a = ap.parse_args()
    api_seconds()  # warm: the first run pays the page faults of the library
    ratios, loop_ratios, cli, api = [], [], [], []
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(a.repeats):
            (c, c_loop), (p, p_loop) = cli_seconds(a.binary, tmp), api_seconds()
            cli.append(c)
            api.append(p)
            ratios.append(p / c)
            loop_ratios.append(p_loop / c_loop)
    dampsym.Step(py_csv1, id="bench-py-csv1", order=2, claims=["conformal-symplectic"])
    py_ns = min(per_step_ns("bench-py-csv1", 20000) for _ in range(3))
    builtin_ns = min(per_step_ns("csv1", 10**6) for _ in range(3))
    ratio = statistics.median(ratios)
    result: dict[str, Any] = {"ratio_api_over_cli": ratio, "limit": LIMIT,
              "ratio_step_loop_api_over_cli": statistics.median(loop_ratios),
              "cli_seconds": cli, "api_seconds": api,
              "python_step_ns_per_step": py_ns, "builtin_csv1_ns_per_step": builtin_ns}
    ok = ratio <= LIMIT
    print(f"Python API / CLI, 10^7 csv1 pendulum steps: {result['ratio_api_over_cli']:.3f} "
          f"(limit {LIMIT}; CLI median {statistics.median(cli):.3f} s) {'ok' if ok else 'FAIL'}; "
          f"the step loop alone (the run's wall time in the report): "
          f"{result['ratio_step_loop_api_over_cli']:.3f}")
    print(f"a Python callable's step (csv1 with numpy, pendulum): {py_ns / 1000:.1f} us per step "
          f"(built-in csv1: {builtin_ns:.1f} ns per step)")
    if a.out_json:
        with open(a.out_json, "w") as f:
            json.dump(result, f, indent=2)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
