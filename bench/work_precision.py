#!/usr/bin/python3
"""Work-precision data (docs/benchmarks.md "Work-precision"): dampsym's conformal methods beside
Boost.Odeint, GSL and scipy on the damped pendulum, Kepler's problem and the perturbed rigid body.

    /usr/bin/python3 bench/work_precision.py WP_RAW_JSON --out-json reports/work-precision.json

WP_RAW_JSON is dampsym_bench's Google Benchmark output of the wp/ benchmarks
(`dampsym_bench --benchmark_filter=^wp/ --benchmark_out=F --benchmark_out_format=json`,
bench/bench_workprecision.cpp): per problem, the case it is taken from, the reference and the
vector field at two states (context dampsym.wp.<problem>); per run, the final state, force
evaluations and CPU time of the bare loop (minimum over the repetitions). This script runs scipy's
solve_ivp(DOP853) and solve_ivp(Radau, analytic Jacobian) on the same problems in the same
process run, over rtol = 1e-3 ... 1e-12 with atol = 1e-3 rtol like the C++ adaptive solvers, and
times each solve_ivp call (CPU time, minimum of up to 3 calls; this includes scipy's Python
overhead per step); a scipy ladder stops after a solve that took more than SOLVE_BUDGET (1 s) of
CPU. Every error, C++ or scipy, is computed here by final_error: the relative error
at t_end, |z - z_ref|_2 / |z_ref|_2 (dampsym's error.final_rel). The figure is drawn from the JSON
by tools/figures/work_precision_plot.py.

Exit status: 0; 1 scipy's vector field differs from dampsym's (the samples in the context);
2 bad input (a message naming the file and key)."""

import argparse
import json
import math
import os
import platform
import sys
import time
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple

import numpy as np
from scipy.integrate import solve_ivp

Json = Dict[str, Any]
Rhs = Callable[[float, Any], Any]
SCHEMA = "dampsym-work-precision/1"
RAW_LIMIT = 64 << 20
ORDER = ["pendulum", "kepler", "rigid-body"]  # the rows of the figure, then any other problem
SOLVE_BUDGET = 1.0  # s of CPU per scipy solve before its ladder stops


class BadInput(Exception):
    """Malformed raw benchmark data: exit 2."""


def final_error(z: Sequence[float], ref: Sequence[float]) -> float:
    """The relative error at t_end, |z - ref|_2 / |ref|_2 (dampsym's error.final_rel)."""
    if len(z) != len(ref):
        raise ValueError(f"state of {len(z)} components against a reference of {len(ref)}")
    return math.hypot(*(a - b for a, b in zip(z, ref))) / math.hypot(*ref)


# ---- the problems' vector fields (the same as dampsym's: checked against the samples) ----

def pendulum(p: Json) -> Tuple[Rhs, Rhs]:
    g = float(p["gamma"])

    def f(_t: float, y: Any) -> Any:
        return np.array([y[1], -math.sin(y[0]) - 2.0 * g * y[1]])

    def jac(_t: float, y: Any) -> Any:
        return np.array([[0.0, 1.0], [-math.cos(y[0]), -2.0 * g]])
    return f, jac


def kepler(_p: Json) -> Tuple[Rhs, Rhs]:
    def f(_t: float, y: Any) -> Any:
        r2 = y[0] * y[0] + y[1] * y[1]
        c = 1.0 / (r2 * math.sqrt(r2))
        return np.array([y[2], y[3], -c * y[0], -c * y[1]])

    def jac(_t: float, y: Any) -> Any:
        r2 = y[0] * y[0] + y[1] * y[1]
        c = 1.0 / (r2 * math.sqrt(r2))
        d = 3.0 * c / r2
        return np.array([[0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0],
                         [-c + d * y[0] * y[0], d * y[0] * y[1], 0.0, 0.0],
                         [d * y[0] * y[1], -c + d * y[1] * y[1], 0.0, 0.0]])
    return f, jac


def rigid_body(p: Json) -> Tuple[Rhs, Rhs]:
    eps, i1, i2, i3 = (float(p[k]) for k in ("epsilon", "I1", "I2", "I3"))

    def f(t: float, z: Any) -> Any:
        w1, w2, w3 = z[0] / i1, z[1] / i2, z[2] / i3
        g = 0.5 * eps * math.cos(2.0 * t)
        return np.array([z[1] * w3 - z[2] * w2 - g * z[0], z[2] * w1 - z[0] * w3 - g * z[1],
                         z[0] * w2 - z[1] * w1 - g * z[2]])

    def jac(t: float, z: Any) -> Any:
        g = 0.5 * eps * math.cos(2.0 * t)
        a1, a2, a3 = 1.0 / i1, 1.0 / i2, 1.0 / i3
        return np.array([[-g, z[2] * a3 - a2 * z[2], -z[1] * a2 + a3 * z[1]],
                         [-z[2] * a3 + a1 * z[2], -g, z[0] * a1 - a3 * z[0]],
                         [z[1] * a2 - a1 * z[1], -z[0] * a1 + a2 * z[0], -g]])
    return f, jac


SYSTEMS: Dict[str, Callable[[Json], Tuple[Rhs, Rhs]]] = {
    "pendulum": pendulum, "kepler": kepler, "rigid-body": rigid_body}


def check_rhs(name: str, f: Rhs, samples: List[Json]) -> Optional[str]:
    """None when scipy's f agrees with dampsym's vector field at the samples, else why not."""
    for s in samples:
        got, want = f(float(s["t"]), np.array(s["z"], dtype=float)), np.array(s["f"], dtype=float)
        if np.max(np.abs(got - want)) > 1e-14 * (1.0 + np.max(np.abs(want))):
            return f"{name}: scipy's vector field {list(got)} differs from dampsym's {list(want)} " \
                   f"at t = {s['t']}, z = {s['z']}"
    return None


# ---- the raw benchmark file ----

def need(obj: Any, key: str, kind: type, where: str) -> Any:
    """obj[key] of type kind, else BadInput naming where and the key."""
    if not isinstance(obj, dict) or key not in obj:
        raise BadInput(f"{where}: missing key '{key}'")
    v = obj[key]
    if kind is float and isinstance(v, int) and not isinstance(v, bool):
        v = float(v)
    if not isinstance(v, kind) or isinstance(v, bool):
        raise BadInput(f"{where}.{key}: expected {kind.__name__}, got {type(v).__name__}")
    return v


def load_raw(path: str) -> Tuple[Json, Dict[str, Json], Dict[str, List[Json]]]:
    """(Google Benchmark context, problems from the dampsym.wp.* context entries, wp/ runs by
    name with their repetitions)."""
    try:
        if os.path.getsize(path) > RAW_LIMIT:
            raise BadInput(f"{path}: larger than {RAW_LIMIT} bytes")
        with open(path, encoding="utf-8") as fh:
            raw = json.load(fh)
    except (OSError, ValueError) as e:
        raise BadInput(f"{path}: {e}") from None
    ctx = need(raw, "context", dict, path)
    problems: Dict[str, Json] = {}
    for key, text in ctx.items():
        if key.startswith("dampsym.wp."):
            try:
                problems[key[len("dampsym.wp."):]] = json.loads(text)
            except (TypeError, ValueError) as e:
                raise BadInput(f"{path}: context.{key}: not JSON ({e})") from None
    if not problems:
        raise BadInput(f"{path}: context: no dampsym.wp.<problem> entry (not a wp/ run)")
    runs: Dict[str, List[Json]] = {}
    for i, b in enumerate(need(raw, "benchmarks", list, path)):
        name = need(b, "run_name", str, f"{path}: benchmarks[{i}]")
        if name.startswith("wp/") and b.get("run_type") == "iteration":
            runs.setdefault(name, []).append(b)
    return ctx, problems, runs


def seconds(b: Json, where: str) -> float:
    unit = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}.get(b.get("time_unit", ""))
    if unit is None:
        raise BadInput(f"{where}.time_unit: not one of ns, us, ms, s")
    return float(need(b, "cpu_time", float, where)) * unit


def cpp_point(name: str, reps: List[Json], ref: List[float], where: str) -> Json:
    """One C++ run: the minimum CPU time over its repetitions, its counters, its error."""
    failed = [b.get("error_message", "error") for b in reps if b.get("error_occurred")]
    b = reps[0]
    pt: Json = {"benchmark": name}
    for k in ("h", "rtol", "atol"):
        if k in b:
            pt[k] = float(need(b, k, float, where))
    if failed:
        pt["failed"] = str(failed[0])
        return pt
    z = [float(need(b, f"z{i}", float, where)) for i in range(len(ref))]
    pt.update({"cpu_seconds": min(seconds(r, where) for r in reps),
               "force_evals": int(need(b, "force_evals", float, where)),
               "jac_evals": int(need(b, "jac_evals", float, where)),
               "steps": int(need(b, "steps", float, where)),
               "final_state": z, "error": final_error(z, ref)})
    return pt


def run_key(name: str) -> Tuple[str, str, int]:
    """wp/<problem>/<solver>/<k>[/min_time:...][/repeats:...] -> (problem, solver, k)."""
    parts = name.split("/")
    if len(parts) < 4 or not parts[3].isdigit():
        raise BadInput(f"benchmark {name!r}: not wp/<problem>/<solver>/<k>")
    return parts[1], parts[2], int(parts[3])


LIBRARY = {"odeint": "Boost.Odeint", "gsl": "GSL", "scipy": "scipy"}


def cpp_series(problem: str, runs: Dict[str, List[Json]], ref: List[float],
               path: str) -> List[Json]:
    """The C++ series of one problem, in the order of the benchmarks, each ladder in order."""
    series: Dict[str, List[Tuple[int, Json]]] = {}
    for name, reps in runs.items():
        p, solver, k = run_key(name)
        if p == problem:
            series.setdefault(solver, []).append((k, cpp_point(name, reps, ref,
                                                                f"{path}: {name}")))
    out = []
    for solver, pts in series.items():
        lib = LIBRARY.get(solver.split("-")[0], "dampsym")
        adaptive = any("rtol" in pt for _, pt in pts)
        out.append({"solver": solver, "library": lib, "kind": "adaptive" if adaptive else "fixed",
                    "points": [pt for _, pt in sorted(pts, key=lambda kp: kp[0])]})
    return out


def timed_solve(method: str, f: Rhs, jac: Rhs, spec: Json, rtol: float, atol: float) -> Json:
    """One scipy solve_ivp run (CPU time: the minimum of up to 3 calls, fewer past 0.5 s)."""
    kw: Json = {"jac": jac} if method == "Radau" else {}
    times, sol = [], None
    for _ in range(3):
        c0 = time.process_time()
        sol = solve_ivp(f, (spec["t0"], spec["t_end"]), np.array(spec["initial_state"]),
                        method=method, rtol=rtol, atol=atol, **kw)
        times.append(time.process_time() - c0)
        if sum(times) > 0.5 or not sol.success:
            break
    assert sol is not None
    pt: Json = {"rtol": rtol, "atol": atol}
    if not sol.success:
        pt["failed"] = str(sol.message)
        return pt
    z = [float(v) for v in sol.y[:, -1]]
    pt.update({"cpu_seconds": min(times), "force_evals": int(sol.nfev),
               "jac_evals": int(sol.njev), "steps": int(sol.t.size - 1), "final_state": z,
               "error": final_error(z, spec["reference"]["final_state"])})
    return pt


def scipy_series(spec: Json, exponents: Sequence[int]) -> List[Json]:
    """scipy's DOP853 and Radau over the tolerance ladder; a ladder stops after a solve that
    took more than SOLVE_BUDGET s of CPU (Radau's tight tolerances take tens of seconds)."""
    f, jac = SYSTEMS[spec["problem"]](spec["params"])
    out = []
    for method in ("DOP853", "Radau"):
        s: Json = {"solver": f"scipy-{method}", "library": "scipy", "kind": "adaptive",
                   "points": []}
        for k in exponents:
            rtol = 10.0 ** -k
            pt = timed_solve(method, f, jac, spec, rtol, spec["atol_over_rtol"] * rtol)
            s["points"].append(pt)
            if pt.get("cpu_seconds", 0.0) > SOLVE_BUDGET and k != exponents[-1]:
                s["ladder_stopped"] = (f"after rtol {rtol:.0e}: that solve took "
                                       f"{pt['cpu_seconds']:.2g} s of CPU (budget {SOLVE_BUDGET:g} s)")
                break
        out.append(s)
    return out


def machine(ctx: Json) -> Json:
    """The machine and the load, from Google Benchmark's context and this process."""
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as fh:
            cpu = next((ln.split(":", 1)[1].strip() for ln in fh if ln.startswith("model name")),
                       platform.processor())
    except OSError:
        cpu = platform.processor()
    import scipy
    return {"cpu": cpu, "cpus": ctx.get("num_cpus"), "mhz_per_cpu": ctx.get("mhz_per_cpu"),
            "host": ctx.get("host_name"), "date": ctx.get("date"),
            "load_avg_cpp": ctx.get("load_avg"), "load_avg_scipy": list(os.getloadavg()),
            "dampsym_build": ctx.get("dampsym.build"), "python": platform.python_version(),
            "numpy": np.__version__, "scipy": scipy.__version__,
            "os": f"{platform.system()} {platform.release()}"}


def problem_entry(label: str, spec: Json, runs: Dict[str, List[Json]], path: str) -> Json:
    where = f"{path}: context.dampsym.wp.{label}"
    for k, kind in (("problem", str), ("params", dict), ("t0", float), ("t_end", float),
                    ("initial_state", list), ("atol_over_rtol", float), ("rtol_exponents", list),
                    ("rhs_samples", list), ("reference", dict), ("case", str)):
        need(spec, k, kind, where)
    ref = need(spec["reference"], "final_state", list, f"{where}.reference")
    if spec["problem"] not in SYSTEMS:
        raise BadInput(f"{where}.problem: {spec['problem']!r} is none of {sorted(SYSTEMS)}")
    lo, hi = spec["rtol_exponents"]
    return {"id": label, "case": spec["case"], "case_file": spec.get("case_file"),
            "problem": spec["problem"], "params": spec["params"], "t0": spec["t0"],
            "t_end": spec["t_end"], "initial_state": spec["initial_state"],
            "reference": spec["reference"],
            "series": cpp_series(label, runs, ref, path) + scipy_series(spec, range(lo, hi + 1))}


def main(argv: Optional[List[str]] = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("raw")
    ap.add_argument("--out-json", required=True)
    a = ap.parse_args(argv)
    try:
        ctx, problems, runs = load_raw(a.raw)
        for label, spec in problems.items():
            f, _ = SYSTEMS.get(need(spec, "problem", str, f"{a.raw}: {label}"),
                               lambda _p: (lambda t, y: None, lambda t, y: None))(
                need(spec, "params", dict, f"{a.raw}: {label}"))
            why = check_rhs(label, f, need(spec, "rhs_samples", list, f"{a.raw}: {label}"))
            if why:
                print(f"work_precision.py: {why}", file=sys.stderr)
                return 1
        order = sorted(problems, key=lambda k: (ORDER.index(k) if k in ORDER else len(ORDER), k))
        entries = [problem_entry(label, problems[label], runs, a.raw) for label in order]
    except BadInput as e:
        print(f"work_precision.py: {e}", file=sys.stderr)
        return 2
    out = {"schema": SCHEMA, "machine": machine(ctx),
           "error_measure": "relative error at t_end, |z - z_ref|_2 / |z_ref|_2 "
                            "(dampsym's error.final_rel)",
           "time_measure": "CPU time of one integration from t0 to t_end, minimum over "
                           "repetitions: the bare loop for the C++ solvers (Google Benchmark), "
                           "the solve_ivp call for scipy (including its Python overhead)",
           "problems": entries}
    with open(a.out_json, "w", encoding="utf-8") as fh:
        json.dump(out, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
