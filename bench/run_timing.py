#!/usr/bin/python3
"""Kernel speed through `dampsym run`: each method alone (one `dampsym run` per method, --jobs 1),
10^7 pendulum steps (gamma = 0.1), no diagnostic, timed by the run's own wall_seconds in
report.json. Prints ns per step and per force evaluation and the acceptance ratios of the data
kernels against the hand-written and implicit references (same limits as the bench_report.py
rows); with --out-json writes them. Exit status 1 if a ratio fails, 2 on a usage or input error.

Usage: bench/run_timing.py DAMPSYM_BINARY [--repeats N] [--out-json FILE]
Each method is run --repeats times (default 3) and its minimum wall time is used (shared machine).
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
CASE = os.path.join(HERE, "cases", "run-pendulum-1e7.json")
METHODS = ["csv1", "stormer-verlet", "csv1-perk", "cse-if", "cse-etd", "rk4", "gauss1", "gauss2",
           "gauss3", "glifrk1", "glifrk2", "glifrk3", "etdrk2"]
# (name, numerator, denominator, per, limit): per = "step" or "force" (rhs evaluation).
ROWS = [
    ("stormer-verlet / csv1 (ns per step)", "stormer-verlet", "csv1", "step", 1.15),
    ("csv1-perk / csv1 (ns per step)", "csv1-perk", "csv1", "step", 1.15),
    ("cse-if / csv1 (ns per force evaluation)", "cse-if", "csv1", "force", 1.15),
    ("cse-etd / csv1 (ns per force evaluation)", "cse-etd", "csv1", "force", 1.15),
    ("glifrk1 / gauss1 (ns per step)", "glifrk1", "gauss1", "step", 1.15),
    ("glifrk2 / gauss2 (ns per step)", "glifrk2", "gauss2", "step", 1.15),
    ("glifrk3 / gauss3 (ns per step)", "glifrk3", "gauss3", "step", 1.15),
    ("etdrk2 / gauss1 (ns per step)", "etdrk2", "gauss1", "step", 1.15),
]


def run_once(binary, method, out_dir):
    cmd = [binary, "run", CASE, "--jobs", "1", "--time-budget", "0", "--out", out_dir,
           "--set", f'methods=["{method}"]']
    p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if p.returncode == 2:
        sys.exit(f"run_timing.py: {' '.join(cmd)}: bad input: {p.stderr.strip()}")
    with open(os.path.join(out_dir, "report.json")) as f:
        run = json.load(f)["cases"][0]["runs"][0]
    if run["status"] != "ok" or not run["observed"]["bare_loop"]:
        sys.exit(f"run_timing.py: {method}: status {run['status']}, bare loop "
                 f"{run['observed']['bare_loop']}")
    return run


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("binary")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out-json")
    a = ap.parse_args()
    if a.repeats < 1:
        sys.exit(2)
    timing = {}
    with tempfile.TemporaryDirectory() as tmp:
        for m in METHODS:
            best = None
            for r in range(a.repeats):
                run = run_once(a.binary, m, os.path.join(tmp, f"{m}-{r}"))
                if best is None or run["wall_seconds"] < best["wall_seconds"]:
                    best = run
            timing[m] = {"wall_seconds": best["wall_seconds"], "steps": best["steps"],
                         "rhs_evals": best["rhs_evals"],
                         "ns_per_step": 1e9 * best["wall_seconds"] / best["steps"],
                         "ns_per_force_eval": 1e9 * best["wall_seconds"] / best["rhs_evals"]}
    print(f"{'method':16} {'wall s':>8} {'ns/step':>9} {'ns/force':>9}")
    for m, t in timing.items():
        print(f"{m:16} {t['wall_seconds']:8.3f} {t['ns_per_step']:9.2f} "
              f"{t['ns_per_force_eval']:9.2f}")
    acc = []
    for name, num, den, per, limit in ROWS:
        key = "ns_per_step" if per == "step" else "ns_per_force_eval"
        r = timing[num][key] / timing[den][key]
        acc.append({"name": name, "ratio": r, "limit": limit, "passed": r <= limit})
    w = max(len(r["name"]) for r in acc)
    print(f"\n{'dampsym run acceptance'.ljust(w)}  {'ratio':>7}  limit  result")
    for r in acc:
        print(f"{r['name'].ljust(w)}  {r['ratio']:7.3f}  {r['limit']:5.2f}  "
              f"{'PASS' if r['passed'] else 'FAIL'}")
    if a.out_json:
        with open(a.out_json, "w") as f:
            json.dump({"case": CASE, "timing": timing, "acceptance": acc}, f, indent=2)
    return 0 if all(r["passed"] for r in acc) else 1


if __name__ == "__main__":
    sys.exit(main())
