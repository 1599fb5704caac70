#!/usr/bin/python3
"""Kernel speed through `dampsym run`: each method alone (one `dampsym run` per method, --jobs 1),
10^7 pendulum steps (gamma = 0.1), no diagnostic, timed by the run's own wall time in report.json
(timings.cases[0].runs[0].wall_seconds). Prints ns per step and per force evaluation and the
acceptance ratios of the data kernels against the hand-written and implicit references (same
limits as the bench_report.py rows); with --out-json writes them. Exit status 1 if a ratio fails,
2 on a usage or input error.

Usage: bench/run_timing.py DAMPSYM_BINARY [--repeats N] [--bench-json RAW.json] [--out-json FILE]
The methods are run in --repeats rounds (default 5), every method once per round, so that a change
of the machine's load falls on all of them; each ratio is the median over the rounds of the ratio
measured within the round (shared machine). With --bench-json (dampsym_bench's raw output of the
same ci/bench.sh invocation) the rows of PEER_ROWS divide a method's ns per step through
`dampsym run` (median over the rounds) by a peer's (the minimum CPU time of its repetitions):
Boost.Odeint runge_kutta4 for rk4, and the hand-written loops of their own arithmetic for the
partitioned data kernels; neither can be run through `dampsym run`.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from typing import Any, Dict, List

HERE = os.path.dirname(os.path.abspath(__file__))
CASE = os.path.join(HERE, "cases", "run-pendulum-1e7.json")
METHODS = ["csv1", "stormer-verlet", "csv1-perk", "cse-if", "cse-etd", "rk4", "gauss1", "gauss2",
           "gauss3", "glifrk1", "glifrk2", "glifrk3", "etdrk2", "rk4-file", "stormer-verlet-file"]
# Methods loaded from method files (docs/method-files.md): id -> file.
METHOD_FILES = {m: os.path.join(HERE, "..", "examples", "methods", m[:-len("-file")] + ".json")
                for m in ("rk4-file", "stormer-verlet-file")}
# (name, numerator, denominator, per, limit): per = "step" or "force" (rhs evaluation).
ROWS = [
    ("glifrk1 / gauss1 (ns per step)", "glifrk1", "gauss1", "step", 1.15),
    ("glifrk2 / gauss2 (ns per step)", "glifrk2", "gauss2", "step", 1.15),
    ("glifrk3 / gauss3 (ns per step)", "glifrk3", "gauss3", "step", 1.15),
    ("etdrk2 / gauss1 (ns per step)", "etdrk2", "gauss1", "step", 1.15),
    ("rk4 from a method file / built-in rk4 (ns per step)", "rk4-file", "rk4", "step", 1.10),
    ("stormer-verlet from a method file / built-in (ns per step)", "stormer-verlet-file",
     "stormer-verlet", "step", 1.10),
]


def run_once(binary: str, method: str, out_dir: str) -> Dict[str, float]:
    cmd = [binary, "run", CASE, "--jobs", "1", "--time-budget", "0", "--out", out_dir,
           "--set", f'methods=["{method}"]']
    if method in METHOD_FILES:
        cmd += ["--methods", METHOD_FILES[method]]
    p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if p.returncode == 2:
        sys.exit(f"run_timing.py: {' '.join(cmd)}: bad input: {p.stderr.strip()}")
    with open(os.path.join(out_dir, "report.json")) as f:
        report = json.load(f)
    run = report["cases"][0]["runs"][0]
    if run["status"] != "ok" or not run["observed"]["bare_loop"]:
        sys.exit(f"run_timing.py: {method}: status {run['status']}, bare loop "
                 f"{run['observed']['bare_loop']}")
    wall = report["timings"]["cases"][0]["runs"][0]["wall_seconds"]
    return {"wall_seconds": wall, "steps": run["steps"], "rhs_evals": run["rhs_evals"],
            "ns_per_step": 1e9 * wall / run["steps"],
            "ns_per_force_eval": 1e9 * wall / run["rhs_evals"]}


def peer_ns_per_step(path: str, peer: str) -> float:
    """Minimum over repetitions of peer/pendulum/PEER's ns_per_step in dampsym_bench's JSON."""
    try:
        with open(path) as f:
            data = json.load(f)
    except (OSError, json.JSONDecodeError) as e:
        sys.exit(f"run_timing.py: cannot read {path}: {e}")
    vals = [b["ns_per_step"] for b in data.get("benchmarks", [])
            if b.get("run_type", "iteration") == "iteration" and "ns_per_step" in b
            and b.get("run_name", b["name"]).split("/")[:3] == ["peer", "pendulum", peer]]
    if not vals:
        sys.exit(f"run_timing.py: {path}: no peer/pendulum/{peer} benchmark")
    return min(vals)


# (method through `dampsym run`, dampsym_bench peer, limit): against a peer of the same
# ci/bench.sh invocation (--bench-json). The bare-* peers are the hand-written loops of the
# methods' own arithmetic (bench_peers.cpp; they end at the kernel's final state bit for bit).
PEER_ROWS = [
    ("rk4", "odeint-rk4", 1.10, "odeint runge_kutta4"),
    ("stormer-verlet", "bare-stormer-verlet", 1.15, "its hand-written loop"),
    ("csv1-perk", "bare-csv1-perk", 1.15, "its hand-written loop"),
    ("cse-if", "bare-cse-if", 1.15, "its hand-written loop"),
    ("cse-etd", "bare-cse-if", 1.15, "cse-if's hand-written loop (same operations)"),
]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("binary")
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--bench-json")
    ap.add_argument("--out-json")
    ap.add_argument("--only", nargs="+", metavar="METHOD",
                    help="time only these methods (and only the rows between them)")
    a = ap.parse_args()
    if a.only:
        unknown = [m for m in a.only if m not in METHODS]
        if unknown:
            sys.exit(f"run_timing.py: --only: unknown method(s) {unknown} (known: {METHODS})")
        METHODS[:] = [m for m in METHODS if m in a.only]
        ROWS[:] = [r for r in ROWS if r[1] in METHODS and r[2] in METHODS]
    if a.repeats < 1:
        sys.exit(2)
    rounds: List[Dict[str, Dict[str, float]]] = []
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(a.repeats):
            rounds.append({m: run_once(a.binary, m, os.path.join(tmp, f"{m}-{k}"))
                           for m in METHODS})
    timing: Dict[str, Dict[str, Any]] = {m: {k: statistics.median(rd[m][k] for rd in rounds)
                  for k in ("wall_seconds", "ns_per_step", "ns_per_force_eval")}
              | {"steps": rounds[0][m]["steps"], "rhs_evals": rounds[0][m]["rhs_evals"],
                 "wall_seconds_all": [rd[m]["wall_seconds"] for rd in rounds]}
              for m in METHODS}
    print(f"{'method':16} {'wall s':>8} {'ns/step':>9} {'ns/force':>9}   (medians of {a.repeats} rounds)")
    for m, t in timing.items():
        print(f"{m:16} {t['wall_seconds']:8.3f} {t['ns_per_step']:9.2f} "
              f"{t['ns_per_force_eval']:9.2f}")
    acc: List[Dict[str, Any]] = []
    for name, num, den, per, limit in ROWS:
        key = "ns_per_step" if per == "step" else "ns_per_force_eval"
        per_round = [rd[num][key] / rd[den][key] for rd in rounds]
        ratio = statistics.median(per_round)
        acc.append({"name": name, "ratio": ratio, "limit": limit, "passed": ratio <= limit,
                    "ratio_per_round": per_round})
    for method, peer, limit, label in PEER_ROWS if a.bench_json else []:
        if method not in METHODS:
            continue
        peer_ns = peer_ns_per_step(a.bench_json, peer)
        peer_ratio = timing[method]["ns_per_step"] / peer_ns
        acc.append({"name": f"{method} through dampsym run / {label} in dampsym_bench "
                            "(ns per step)", "ratio": peer_ratio, "limit": limit,
                    "passed": peer_ratio <= limit,
                    "peer": f"peer/pendulum/{peer}", "peer_ns_per_step": peer_ns})
    w = max(len(row["name"]) for row in acc)
    print(f"\n{'dampsym run acceptance'.ljust(w)}  {'ratio':>7}  limit  result")
    for row in acc:
        print(f"{row['name'].ljust(w)}  {row['ratio']:7.3f}  {row['limit']:5.2f}  "
              f"{'PASS' if row['passed'] else 'FAIL'}")
    if a.out_json:
        with open(a.out_json, "w") as f:
            json.dump({"case": CASE, "rounds": a.repeats, "statistic": "median over rounds",
                       "timing": timing, "acceptance": acc}, f, indent=2)
    return 0 if all(row["passed"] for row in acc) else 1


if __name__ == "__main__":
    sys.exit(main())
