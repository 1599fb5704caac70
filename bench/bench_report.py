#!/usr/bin/python3
"""dampsym bench report: reads dampsym_bench's Google Benchmark JSON, times scipy's DOP853 on the
certified reference's pendulum problem, and writes bench.json and bench.md with the acceptance table.

    /usr/bin/python3 bench/bench_report.py BENCH.json [--suite-jobs1 R1.json --suite-jobs2 R2.json]
                                           [--out-json reports/bench.json] [--out-md reports/bench.md]

Every number of a benchmark is the minimum over its repetitions (the least disturbed repetition on a
shared machine); times are CPU times. Exit status: 0 if every acceptance row passes, 1 if one fails,
2 on bad input.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from typing import Any, Dict, List, NoReturn, Optional, Tuple

Runs = Dict[str, Dict[str, Any]]
Record = Dict[str, Any]


def fail_input(msg: str) -> NoReturn:
    print(f"bench_report.py: {msg}", file=sys.stderr)
    sys.exit(2)


TIME_TO_NS = {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}


def load_benchmarks(path: str) -> Tuple[Record, Runs]:
    """{run_name: {"reps": [...], "min": {...}}} from the iteration entries (aggregates ignored)."""
    try:
        with open(path) as f:
            data = json.load(f)
    except (OSError, json.JSONDecodeError) as err:
        fail_input(f"cannot read {path}: {err}")
    runs: Runs = {}
    for b in data.get("benchmarks", []):
        if b.get("run_type", "iteration") != "iteration":
            continue
        # Google Benchmark appends the options to the name ("/min_time:0.200/repeats:7"): drop them.
        name = "/".join(x for x in b.get("run_name", b["name"]).split("/") if ":" not in x)
        entry = runs.setdefault(name, {"reps": [], "errors": []})
        if b.get("error_occurred"):
            entry["errors"].append(b.get("error_message", "error"))
            continue
        rep = {k: v for k, v in b.items() if isinstance(v, (int, float)) and not isinstance(v, bool)}
        rep["cpu_time_ns"] = b["cpu_time"] * TIME_TO_NS[b.get("time_unit", "ns")]
        rep["real_time_ns"] = b["real_time"] * TIME_TO_NS[b.get("time_unit", "ns")]
        if "label" in b:
            entry["label"] = b["label"]
        # Sanity of the per-iteration counters: ns_per_step must equal cpu time / steps.
        if "ns_per_step" in rep and rep.get("steps"):
            recomputed = rep["cpu_time_ns"] / rep["steps"]
            rel = abs(recomputed - rep["ns_per_step"]) / recomputed
            if rel > 1e-6:
                fail_input(f"{name}: ns_per_step {rep['ns_per_step']} != cpu_time/steps {recomputed}")
        if "ns_per_force_eval" in rep and rep.get("force_evals"):
            recomputed = rep["cpu_time_ns"] / rep["force_evals"]
            rel = abs(recomputed - rep["ns_per_force_eval"]) / recomputed
            if rel > 1e-6:
                fail_input(f"{name}: ns_per_force_eval != cpu_time/force_evals")
        entry["reps"].append(rep)
    for name, e in runs.items():
        if not e["reps"]:
            e["min"] = None
            continue
        best = min(e["reps"], key=lambda r: r["cpu_time_ns"])
        # Times and per-unit costs: minimum over repetitions; counts come from that repetition.
        m = dict(best)
        for k in ("ns_per_step", "ns_per_force_eval", "cpu_time_ns", "real_time_ns",
                  "loop_ns_per_step"):
            vals = [r[k] for r in e["reps"] if k in r]
            if vals:
                m[k] = min(vals)
        e["min"] = m
    return data.get("context", {}), runs


def value(runs: Runs, name: str, key: str) -> Any:
    e = runs.get(name)
    if not e or not e.get("min") or key not in e["min"]:
        return None
    return e["min"][key]


def time_scipy(ref: Record, repeats: int) -> Record:
    """Minimum CPU time of solve_ivp(DOP853) on the reference's pendulum, tolerance and times."""
    import numpy as np
    import scipy
    from scipy.integrate import solve_ivp

    g = ref["gamma"]

    def rhs(t: float, y: Any) -> Any:
        return np.array([y[1], -math.sin(y[0]) - 2.0 * g * y[1]])

    t0, t1 = ref["t0"], ref["t_end"]
    times = np.linspace(t0, t1, int(round(ref["points"])))
    y0 = [ref["q0"], ref["p0"]]
    # solve_ivp raises rtol to 100·eps (2.2e-14) when asked for less; report what it used.
    eff_rtol = max(ref["epsrel"], 100 * np.finfo(float).eps)
    cpu: List[float] = []
    wall: List[float] = []
    nfev, ok = None, True
    import warnings

    for _ in range(repeats):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            c0, w0 = time.process_time(), time.perf_counter()
            sol = solve_ivp(rhs, (t0, t1), y0, method="DOP853", rtol=ref["epsrel"],
                            atol=ref["epsabs"], t_eval=times)
            c1, w1 = time.process_time(), time.perf_counter()
        cpu.append(c1 - c0)
        wall.append(w1 - w0)
        nfev = int(sol.nfev)
        ok = ok and bool(sol.success)
    return {
        "scipy_version": scipy.__version__,
        "method": "DOP853",
        "rtol_requested": ref["epsrel"],
        "rtol_effective": eff_rtol,
        "atol": ref["epsabs"],
        "t0": t0,
        "t_end": t1,
        "points": len(times),
        "repeats": repeats,
        "cpu_seconds_min": min(cpu),
        "wall_seconds_min": min(wall),
        "cpu_seconds_all": cpu,
        "nfev": nfev,
        "success": ok,
        "final_state": [float(sol.y[0, -1]), float(sol.y[1, -1])],
    }


def suite_wall(path: str) -> float:
    try:
        with open(path) as f:
            report = json.load(f)
        # schema_version 2 keeps the clock values in "timings"; 1 kept them in "summary"
        section = report["timings"] if "timings" in report else report["summary"]
        return float(section["wall_seconds"])
    except (OSError, KeyError, ValueError, TypeError, json.JSONDecodeError) as e:
        fail_input(f"cannot read timings.wall_seconds from {path}: {e}")


def fmt(x: Any, digits: int = 3) -> str:
    if x is None:
        return "—"
    if isinstance(x, str):
        return x
    if x == 0 or (abs(x) >= 1e-2 and abs(x) < 1e6):
        return f"{x:.{digits}g}" if abs(x) < 1000 else f"{x:.0f}"
    return f"{x:.{digits}e}"


PROBLEMS = ["oscillator", "pendulum", "rigid-body", "nbody-3", "nbody-6", "nbody-10"]


# The peers on the damped pendulum: (table label, benchmark name), in the table's order.
PEER_ROWS = [
    ("harness csv1", "harness/pendulum/csv1"),
    ("bare csv1 loop", "peer/pendulum/bare-csv1"),
    ("odeint velocity_verlet (damping in force)", "peer/pendulum/odeint-velocity-verlet"),
    ("odeint sb3a_m4_mclachlan + exact damping half-steps", "peer/pendulum/odeint-rkn-sb3a-m4-damped"),
    ("harness stormer-verlet", "harness/pendulum/stormer-verlet"),
    ("harness rk4", "harness/pendulum/rk4"),
    ("odeint runge_kutta4", "peer/pendulum/odeint-rk4"),
    ("harness glifrk2", "harness/pendulum/glifrk2"),
    ("harness gauss2", "harness/pendulum/gauss2"),
    ("GSL rk4imp (step doubling)", "peer/pendulum/gsl-rk4imp"),
    ("harness glifrk1", "harness/pendulum/glifrk1"),
    ("harness gauss1", "harness/pendulum/gauss1"),
    ("GSL rk2imp (step doubling)", "peer/pendulum/gsl-rk2imp"),
]


def parse_args() -> argparse.Namespace:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("bench_json")
    ap.add_argument("--suite-jobs1")
    ap.add_argument("--suite-jobs2")
    ap.add_argument("--out-json", default="reports/bench.json")
    ap.add_argument("--out-md", default="reports/bench.md")
    ap.add_argument("--scipy-repeats", type=int, default=5)
    a = ap.parse_args()
    if bool(a.suite_jobs1) != bool(a.suite_jobs2):
        fail_input("give both --suite-jobs1 and --suite-jobs2, or neither")
    return a


def evals_per_step(steps: Any, evals: Any) -> Optional[float]:
    return evals / steps if steps and evals is not None else None


def method_grid(runs: Runs) -> Tuple[List[str], Dict[str, Dict[str, Record]]]:
    """The methods of the harness/PROBLEM/METHOD benchmarks (in run order) and, per method and
    problem, ns per step, ns per force evaluation and force evaluations per step."""
    methods: List[str] = []
    for name in runs:
        parts = name.split("/")
        if parts[0] == "harness" and len(parts) == 3 and parts[2] not in methods:
            methods.append(parts[2])
    grid = {
        m: {p: {"ns_per_step": value(runs, f"harness/{p}/{m}", "ns_per_step"),
                "ns_per_force_eval": value(runs, f"harness/{p}/{m}", "ns_per_force_eval"),
                "force_evals_per_step": evals_per_step(value(runs, f"harness/{p}/{m}", "steps"),
                                                       value(runs, f"harness/{p}/{m}", "force_evals"))}
            for p in PROBLEMS if f"harness/{p}/{m}" in runs}
        for m in methods
    }
    return methods, grid


def peer_table(runs: Runs) -> List[Record]:
    """The rows of PEER_ROWS with their costs."""
    peers = []
    for label, name in PEER_ROWS:
        s, e = value(runs, name, "steps"), value(runs, name, "force_evals")
        peers.append({"label": label, "benchmark": name,
                      "ns_per_step": value(runs, name, "ns_per_step"),
                      "ns_per_force_eval": value(runs, name, "ns_per_force_eval"),
                      "force_evals_per_step": evals_per_step(s, e),
                      "jac_evals_per_iteration": value(runs, name, "jac_evals")})
    return peers


def reference_and_scipy(runs: Runs, repeats: int) -> Tuple[Optional[Record], Optional[Record]]:
    """The certified reference's problem, tolerances and cost, and scipy's DOP853 timed on the same
    problem (both None without the reference/pendulum/certified benchmark)."""
    ref_name = "reference/pendulum/certified"
    ref = runs.get(ref_name, {}).get("min")
    if not ref:
        return None, None
    reference = {k: ref.get(k) for k in ("gamma", "q0", "p0", "t0", "t_end", "points", "epsrel",
                                         "epsabs", "cert_epsrel", "cert_epsabs", "rhs_evals",
                                         "error_estimate")}
    # The label ends in "<stepper> certified by <certifier>" (bench_reference.cpp).
    reference["label"] = runs[ref_name].get("label") or ""
    solvers = reference["label"].rsplit(", ", 1)[-1].split(" certified by ")
    reference["stepper"], reference["certifier"] = (solvers + ["?", "?"])[:2]
    reference["cpu_seconds"] = ref["cpu_time_ns"] * 1e-9
    reference["main_only_cpu_seconds"] = (
        value(runs, "reference/pendulum/main-only", "cpu_time_ns") or float("nan")) * 1e-9
    return reference, time_scipy(ref, repeats)


def overhead(runs: Runs) -> Record:
    """run_cases against a bare integrate() on the oscillator (bench/bench_overhead.cpp)."""
    return {
        "run_cases_final_error_ns_per_step": value(runs, "overhead/oscillator/run_cases-final-error",
                                                   "ns_per_step"),
        "bare_integrate_ns_per_step": value(runs, "overhead/oscillator/bare-integrate", "ns_per_step"),
        "run_cases_error_grid_ns_per_step": value(runs, "overhead/oscillator/run_cases-error-grid",
                                                  "ns_per_step"),
        "steps": value(runs, "overhead/oscillator/bare-integrate", "steps"),
        "final_error_reference_points": value(runs, "overhead/oscillator/run_cases-final-error",
                                              "reference_points"),
        "grid_reference_points": value(runs, "overhead/oscillator/run_cases-error-grid",
                                       "reference_points"),
    }


def ratio(x: Any, y: Any) -> Optional[float]:
    return x / y if x is not None and y not in (None, 0) else None


def add_row(acc: List[Record], name: str, r: Optional[float], op: str, limit: float,
            how: str) -> None:
    """Appends an acceptance row; it passes if the ratio r exists and satisfies `op limit`."""
    passed = r is not None and (r <= limit if op == "<=" else r >= limit)
    acc.append({"name": name, "ratio": r, "op": op, "limit": limit, "passed": passed, "how": how})


def peer_rows(acc: List[Record], runs: Runs, ov: Record, reference: Optional[Record],
              scipy_info: Optional[Record]) -> None:
    """The rows against the peers, the bare loop, run_cases' overhead and scipy."""
    add_row(acc, "csv1 pendulum: harness integrate() / bare loop (ns per step)",
            ratio(value(runs, "harness/pendulum/csv1", "ns_per_step"),
                  value(runs, "peer/pendulum/bare-csv1", "ns_per_step")), "<=", 1.15,
            "harness/pendulum/csv1 ÷ peer/pendulum/bare-csv1")
    add_row(acc, "csv1 pendulum: harness / odeint velocity_verlet (ns per force evaluation)",
            ratio(value(runs, "harness/pendulum/csv1", "ns_per_force_eval"),
                  value(runs, "peer/pendulum/odeint-velocity-verlet", "ns_per_force_eval")), "<=",
            1.05, "harness/pendulum/csv1 ÷ peer/pendulum/odeint-velocity-verlet")
    add_row(acc, "glifrk2 / GSL rk4imp (ns per step, same h)",
            ratio(value(runs, "harness/pendulum/glifrk2", "ns_per_step"),
                  value(runs, "peer/pendulum/gsl-rk4imp", "ns_per_step")), "<=", 0.5,
            "harness/pendulum/glifrk2 ÷ peer/pendulum/gsl-rk4imp")
    add_row(acc, "final-error-only case through run_cases / bare integrate() (same 10^6 steps)",
            ratio(ov["run_cases_final_error_ns_per_step"], ov["bare_integrate_ns_per_step"]), "<=",
            1.10, "overhead/oscillator/run_cases-final-error ÷ overhead/oscillator/bare-integrate")
    add_row(acc,
            "scipy DOP853 solve / certified GSL reference (CPU time, same problem, tolerance, t_end)",
            ratio(scipy_info["cpu_seconds_min"] if scipy_info else None,
                  reference["cpu_seconds"] if reference else None), ">=", 20.0,
            "bench_report.py solve_ivp ÷ reference/pendulum/certified")


def kernel_rows(acc: List[Record], runs: Runs) -> None:
    """Data-defined kernels against the hand-written and implicit references (same pendulum, h,
    gamma; bench/run_timing.py measures the same ratios through `dampsym run`)."""
    def kernel_row(name: str, num: str, den: str, key: str, limit: float, peer: bool = False) -> None:
        prefix = "peer/pendulum/" if peer else "harness/pendulum/"
        add_row(acc, name,
                ratio(value(runs, f"harness/pendulum/{num}", key), value(runs, prefix + den, key)),
                "<=", limit, f"harness/pendulum/{num} ÷ {prefix}{den} ({key})")

    # The split data kernels are held to the hand-written loop of their own arithmetic
    # (peer/pendulum/bare-*, which fail unless they end at the kernel's final state bit for bit):
    # the engine's price. Their ratios to csv1 are informational (informational_ratios): they also
    # contain the price of the methods' arithmetic — Rayleigh-form stormer-verlet divides by
    # 1 + h*gamma on the step's chain, csv1-perk evaluates F at Q2 and at q1, which B(2.14)'s sums
    # round differently, and csv1's two evaluations share one sine (F at q1 starts the next step).
    kernel_row("stormer-verlet / its hand-written loop (ns per step)", "stormer-verlet",
               "bare-stormer-verlet", "ns_per_step", 1.15, peer=True)
    kernel_row("csv1-perk / its hand-written loop (ns per step)", "csv1-perk", "bare-csv1-perk",
               "ns_per_step", 1.15, peer=True)
    kernel_row("cse-if / its hand-written loop (ns per step)", "cse-if", "bare-cse-if",
               "ns_per_step", 1.15, peer=True)
    kernel_row("cse-etd / cse-if's hand-written loop (ns per step; same operations)", "cse-etd",
               "bare-cse-if", "ns_per_step", 1.15, peer=True)
    kernel_row("rk4 / odeint runge_kutta4 (ns per step)", "rk4", "odeint-rk4", "ns_per_step", 1.10,
               peer=True)
    for s_ in (1, 2, 3):
        kernel_row(f"glifrk{s_} / gauss{s_} (ns per step)", f"glifrk{s_}", f"gauss{s_}",
                   "ns_per_step", 1.15)
    kernel_row("etdrk2 / gauss1 (ns per step)", "etdrk2", "gauss1", "ns_per_step", 1.15)
    # Methods loaded from method files (docs/method-files.md) against the built-in rows.
    kernel_row("rk4 from a method file / built-in rk4 (ns per step)", "rk4-file", "rk4",
               "ns_per_step", 1.10)
    kernel_row("stormer-verlet from a method file / built-in (ns per step)", "stormer-verlet-file",
               "stormer-verlet", "ns_per_step", 1.10)
    # A C plugin's csv1 (examples/plugins, docs/plugins.md) against the built-in csv1: the price of
    # the indirect step call, of three host callbacks per step (copies into the problem's vectors)
    # and of the two damping factors exp(-2 dGamma) the plugin asks for at every step (csv1 forms
    # them once); no limit in the issue, 6x here so that a regression shows.
    kernel_row("plugin-csv1 (C plugin) / built-in csv1 (ns per step)", "plugin-csv1", "csv1",
               "ns_per_step", 6.0)


def pde_rows(acc: List[Record], runs: Runs) -> None:
    """PDE schemes of B ch. 5 (bench/bench_pde.cpp): cost per step linear in M for the explicit KG
    scheme (5.3) and the banded box scheme (5.5) (ideal 32 for 256 -> 8192), O(M log M) for the
    FFT-based NLS IF (4.15) (ideal 32 * 13/8 = 52; limit 1.25 x that), and the box scheme at most
    10x the explicit scheme at M = 1024."""
    def pde_ns(name: str, M: int) -> Any:
        return value(runs, f"pde/{name}/{M}", "ns_per_step")

    for name, label in (("kg-csv1", "explicit KG (5.3) = csv1"), ("kg-box", "KG box scheme (5.5)")):
        add_row(acc, f"{label}: time per step M = 8192 / M = 256 (linear: 32)",
                ratio(pde_ns(name, 8192), pde_ns(name, 256)), "<=", 40.0,
                f"pde/{name}/8192 ÷ pde/{name}/256 (ns per step)")
    add_row(acc, "NLS IF (4.15), FFT: time per step M = 8192 / M = 256 (M log M: 52)",
            ratio(pde_ns("nls-if", 8192), pde_ns("nls-if", 256)), "<=", 65.0,
            "pde/nls-if/8192 ÷ pde/nls-if/256 (ns per step)")
    add_row(acc, "KG box (5.5) / explicit KG (5.3) per step at M = 1024",
            ratio(pde_ns("kg-box", 1024), pde_ns("kg-csv1", 1024)), "<=", 10.0,
            "pde/kg-box/1024 ÷ pde/kg-csv1/1024 (ns per step)")


def suite_rows(acc: List[Record], jobs1: Optional[str], jobs2: Optional[str]) -> Optional[Record]:
    """The default suite's wall times with --jobs 1 and 2 (None without the two reports)."""
    if not jobs1 or not jobs2:
        return None
    w1, w2 = suite_wall(jobs1), suite_wall(jobs2)
    add_row(acc, "default suite wall time with --jobs 2 [s]", w2, "<=", 20.0,
            "summary.wall_seconds of the --jobs 2 report")
    add_row(acc, "default suite speedup --jobs 1 / --jobs 2", w1 / w2, ">=", 1.7,
            "summary.wall_seconds, jobs 1 ÷ jobs 2")
    return {"jobs1_wall_seconds": w1, "jobs2_wall_seconds": w2, "speedup": w1 / w2}


def informational_ratios(runs: Runs, ov: Record) -> List[Tuple[str, Optional[float]]]:
    """Ratios reported without a limit: (name, ratio)."""
    def peer_ratio(num: str, den: str, key: str = "ns_per_step") -> Optional[float]:
        return ratio(value(runs, num, key), value(runs, den, key))

    bare = "peer/pendulum/bare-csv1"
    harness = "harness/pendulum/"
    return [
        ("stormer-verlet / csv1 (ns per step; held to its own hand-written loop instead)",
         peer_ratio(harness + "stormer-verlet", harness + "csv1")),
        ("csv1-perk / csv1 (ns per step; held to its own hand-written loop instead)",
         peer_ratio(harness + "csv1-perk", harness + "csv1")),
        ("cse-if / csv1 (ns per force evaluation; held to its own hand-written loop instead)",
         peer_ratio(harness + "cse-if", harness + "csv1", "ns_per_force_eval")),
        ("cse-etd / csv1 (ns per force evaluation; held to cse-if's hand-written loop instead)",
         peer_ratio(harness + "cse-etd", harness + "csv1", "ns_per_force_eval")),
        ("hand-written stormer-verlet loop / bare csv1 loop (ns per step)",
         peer_ratio("peer/pendulum/bare-stormer-verlet", bare)),
        ("hand-written csv1-perk loop / bare csv1 loop (ns per step)",
         peer_ratio("peer/pendulum/bare-csv1-perk", bare)),
        ("hand-written cse-if loop / bare csv1 loop (ns per force evaluation)",
         peer_ratio("peer/pendulum/bare-cse-if", bare, "ns_per_force_eval")),
        ("glifrk1 / GSL rk2imp (ns per step)",
         peer_ratio("harness/pendulum/glifrk1", "peer/pendulum/gsl-rk2imp")),
        ("gauss2 / GSL rk4imp (ns per step)",
         peer_ratio("harness/pendulum/gauss2", "peer/pendulum/gsl-rk4imp")),
        ("gauss1 / GSL rk2imp (ns per step)",
         peer_ratio("harness/pendulum/gauss1", "peer/pendulum/gsl-rk2imp")),
        ("csv1 harness / bare loop (ns per force evaluation)",
         peer_ratio("harness/pendulum/csv1", bare, "ns_per_force_eval")),
        ("bare csv1 loop / odeint velocity_verlet (ns per force evaluation)",
         peer_ratio(bare, "peer/pendulum/odeint-velocity-verlet", "ns_per_force_eval")),
        ("csv1 pendulum: the runner's own loop in run_cases (case shard) / bare loop (ns per step)",
         ratio(value(runs, "overhead/pendulum/run_cases-csv1", "loop_ns_per_step"),
               value(runs, bare, "ns_per_step"))),
        ("csv1 pendulum: whole run_cases call / bare loop (ns per step, 10^4 steps)",
         peer_ratio("overhead/pendulum/run_cases-csv1", bare)),
        ("error with the default output grid / final-error-only (run_cases)",
         ratio(ov["run_cases_error_grid_ns_per_step"], ov["run_cases_final_error_ns_per_step"])),
    ]


def markdown_header(context: Record) -> List[str]:
    """The title and the paragraph on the host, the build and the problems."""
    md = ["# dampsym benchmarks", ""]
    md.append(f"Host: {context.get('host_name', '?')}, {context.get('num_cpus', '?')} CPUs at "
              f"{context.get('mhz_per_cpu', '?')} MHz, load average "
              f"{', '.join(f'{x:.2f}' for x in context.get('load_avg', []))}; "
              f"dampsym_bench built {' '.join(context.get('dampsym.build', '?').split())} (Google Benchmark's "
              f"\"library build type {context.get('library_build_type', '?')}\" is the installed "
              f"package's). "
              f"Steps h = {context.get('dampsym.h', '?')}, γ = {context.get('dampsym.gamma', '?')}, "
              f"{context.get('dampsym.steps_1dof', '?')} steps (oscillator, pendulum, rigid body; "
              f"rigid body γ(t) = 0.1 cos 2t), {context.get('dampsym.steps_nbody', '?')} steps "
              f"(N-body, gravity). CPU time; each number is the minimum over the benchmark's "
              f"repetitions. Force evaluation = what the method calls (force −∇V for split methods, "
              f"N or f otherwise; one call of the full rhs for the peers).")
    md.append("")
    return md


def markdown_acceptance(acc: List[Record], info: List[Tuple[str, Optional[float]]]) -> List[str]:
    """The acceptance table and the informational ratios."""
    md = ["## Acceptance", "", "| check | ratio | limit | result |", "|---|---|---|---|"]
    for r in acc:
        md.append(f"| {r['name']} | {fmt(r['ratio'], 4)} | {r['op']} {fmt(r['limit'])} | "
                  f"{'PASS' if r['passed'] else 'FAIL'} |")
    md += ["", "Informational ratios (no limit):", "", "| ratio | value |", "|---|---|"]
    for n, x in info:
        md.append(f"| {n} | {fmt(x, 4)} |")
    md.append("")
    return md


def markdown_grid_and_peers(methods: List[str], grid: Dict[str, Dict[str, Record]],
                            peers: List[Record]) -> List[str]:
    """The method × problem tables (ns per step, ns per force evaluation) and the peers' table."""
    md: List[str] = []
    for title, key in (("ns per step", "ns_per_step"), ("ns per force evaluation",
                                                         "ns_per_force_eval")):
        md.append(f"## {title}, method × problem (harness integrate(), NoObserver)")
        md.append("")
        md.append("| method | " + " | ".join(PROBLEMS) + " |")
        md.append("|---|" + "---|" * len(PROBLEMS))
        for m in methods:
            cells = [fmt(grid[m][p][key]) if p in grid[m] else "n/a" for p in PROBLEMS]
            md.append(f"| {m} | " + " | ".join(cells) + " |")
        md.append("")
    md += ["## Peers on the damped pendulum (same γ, h, steps)", "",
           "| implementation | ns/step | ns/force eval | force evals/step |", "|---|---|---|---|"]
    for p in peers:
        md.append(f"| {p['label']} | {fmt(p['ns_per_step'])} | {fmt(p['ns_per_force_eval'])} | "
                  f"{fmt(p['force_evals_per_step'])} |")
    md.append("")
    md.append("GSL rk4imp/rk2imp: gsl_odeiv2_step_apply at fixed h with the analytic Jacobian; both "
              "estimate their error by step doubling (one full step and two half steps, three "
              "nonlinear solves per step), and their Newton tolerance comes from a driver's control "
              "object (epsabs = epsrel = 1e-12).")
    md.append("")
    return md


def markdown_reference(reference: Record, s: Record) -> List[str]:
    """The certified reference against scipy's DOP853 (s: time_scipy's record)."""
    md = ["## Certified reference vs scipy", ""]
    md.append(f"Case: {reference['label']}. Problem: pendulum γ = {reference['gamma']}, "
              f"q0 = {reference['q0']}, p0 = {reference['p0']}; t = {reference['t0']} … "
              f"{reference['t_end']}, {fmt(reference['points'])} output times.")
    md.append("")
    md.append("| solve | tolerance (rtol / atol) | CPU time [ms] | rhs evals |")
    md.append("|---|---|---|---|")
    md.append(f"| GSL {reference['stepper']} + {reference['certifier']} certification (harness) | "
              f"{reference['epsrel']:g} / "
              f"{reference['epsabs']:g}; certifier {reference['cert_epsrel']:g} / "
              f"{reference['cert_epsabs']:g} | {reference['cpu_seconds'] * 1e3:.3f} | "
              f"{fmt(reference['rhs_evals'])} (main solve) |")
    md.append(f"| GSL {reference['stepper']} alone | {reference['epsrel']:g} / "
              f"{reference['epsabs']:g} | {reference['main_only_cpu_seconds'] * 1e3:.3f} | |")
    md.append(f"| scipy {s['scipy_version']} solve_ivp DOP853 | {s['rtol_effective']:g} "
              f"(asked {s['rtol_requested']:g}) / {s['atol']:g} | "
              f"{s['cpu_seconds_min'] * 1e3:.3f} | {s['nfev']} |")
    md.append("")
    md.append(f"Reference error estimate (max-norm difference of the main and certifying solves "
              f"over the output times): {fmt(reference['error_estimate'])}. solve_ivp raises rtol below "
              f"100·eps to 100·eps.")
    md.append("")
    return md


def markdown_overhead(ov: Record, suites: Optional[Record],
                      errors: Dict[str, List[str]]) -> List[str]:
    """The harness overhead table, the default suite's wall times and the benchmarks' errors."""
    md = ["## Harness overhead (bench/cases/overhead-final-error.json)", "",
          "| run | ns/step | reference points |", "|---|---|---|"]
    md.append(f"| run_cases, diagnostics [\"error\"], output_dt = t_end | "
              f"{fmt(ov['run_cases_final_error_ns_per_step'])} | "
              f"{fmt(ov['final_error_reference_points'])} |")
    md.append(f"| bare integrate() of the same {fmt(ov['steps'])} steps | "
              f"{fmt(ov['bare_integrate_ns_per_step'])} | |")
    md.append(f"| run_cases, diagnostics [\"error\"], default output grid | "
              f"{fmt(ov['run_cases_error_grid_ns_per_step'])} | "
              f"{fmt(ov['grid_reference_points'])} |")
    md.append("")
    if suites:
        md.append("## Default suite")
        md.append("")
        md.append(f"Wall time --jobs 1: {suites['jobs1_wall_seconds']:.2f} s; --jobs 2: "
                  f"{suites['jobs2_wall_seconds']:.2f} s; speedup {suites['speedup']:.2f}.")
        md.append("")
    if errors:
        md.append("## Benchmarks that reported errors")
        md.append("")
        for n, e in errors.items():
            md.append(f"- {n}: {'; '.join(sorted(set(e)))}")
        md.append("")
    return md


def write_outputs(a: argparse.Namespace, out: Record, md: List[str]) -> None:
    """bench.json and bench.md (their folders made if missing)."""
    for path in (a.out_json, a.out_md):
        d = os.path.dirname(path)
        if d:
            os.makedirs(d, exist_ok=True)
    with open(a.out_json, "w") as f:
        json.dump(out, f, indent=1, allow_nan=True)
    with open(a.out_md, "w") as f:
        f.write("\n".join(md))


def print_acceptance(acc: List[Record], out_json: str, out_md: str) -> None:
    """The acceptance table on the console."""
    w = max(len(r["name"]) for r in acc)
    print(f"{'acceptance check'.ljust(w)}  {'ratio':>10}  {'limit':>9}  result")
    for r in acc:
        print(f"{r['name'].ljust(w)}  {fmt(r['ratio'], 4):>10}  {r['op']} {fmt(r['limit']):>6}  "
              f"{'PASS' if r['passed'] else 'FAIL'}")
    print(f"wrote {out_json} and {out_md}")


def main() -> int:
    a = parse_args()
    context, runs = load_benchmarks(a.bench_json)
    methods, grid = method_grid(runs)
    peers = peer_table(runs)
    reference, scipy_info = reference_and_scipy(runs, a.scipy_repeats)
    ov = overhead(runs)
    acc: List[Record] = []
    peer_rows(acc, runs, ov, reference, scipy_info)
    kernel_rows(acc, runs)
    pde_rows(acc, runs)
    suites = suite_rows(acc, a.suite_jobs1, a.suite_jobs2)
    info = informational_ratios(runs, ov)
    all_pass = all(r["passed"] for r in acc)
    errors = {n: e["errors"] for n, e in runs.items() if e["errors"]}
    out = {
        "schema_version": 1,
        "bench_json": os.path.abspath(a.bench_json),
        "context": context,
        "time": "CPU time; every number is the minimum over the benchmark's repetitions",
        "methods_x_problems": grid,
        "peers_pendulum": peers,
        "reference": reference,
        "scipy": scipy_info,
        "overhead": ov,
        "suites": suites,
        "acceptance": acc,
        "informational_ratios": [{"name": n, "ratio": r} for n, r in info],
        "benchmark_errors": errors,
        "benchmarks": {n: {"min": e["min"], "repetitions": e["reps"], "label": e.get("label")}
                       for n, e in runs.items()},
        "all_passed": all_pass,
    }
    md = markdown_header(context) + markdown_acceptance(acc, info)
    md += markdown_grid_and_peers(methods, grid, peers)
    if reference and scipy_info:
        md += markdown_reference(reference, scipy_info)
    md += markdown_overhead(ov, suites, errors)
    write_outputs(a, out, md)
    print_acceptance(acc, a.out_json, a.out_md)
    return 0 if all_pass else 1


if __name__ == "__main__":
    sys.exit(main())
