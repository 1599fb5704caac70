#!/usr/bin/python3
"""Negative tests for verify/crosscheck.py: a corrupted report must be caught.

    /usr/bin/python3 verify/test_crosscheck_negative.py MODE REPORT.json WORKDIR

MODE perturb : multiply one run's final_state by (1 + 1e-6); the cross-check must exit 1
               and name exactly that run (case / method / dt) and nothing else.
MODE swap    : swap the method names csv1 <-> rk3 in one case; the cross-check must exit 1
               and name both methods in that case.
MODE badinput: a report that is not a dampsym report; the cross-check must exit 2.
"""
import copy
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def run_crosscheck(report, workdir):
    path = os.path.join(workdir, "report.json")
    with open(path, "w") as fh:
        json.dump(report, fh)
    proc = subprocess.run([sys.executable, os.path.join(HERE, "crosscheck.py"), path,
                           "--out", workdir], capture_output=True, text=True)
    print(proc.stdout + proc.stderr)
    return proc.returncode, [l for l in proc.stdout.splitlines() if l.startswith("DISAGREE")]


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def perturb(report, workdir):
    # first ok run of an implicit method (the looser 1e-9 tolerance), else the first ok run
    # only runs the cross-check reproduces (oscillator and pendulum), so the change is seen
    runs = [(c, r) for c in report["cases"] for r in c["runs"] if r["status"] == "ok"
            and any(r["final_state"]) and c["problem"]["id"] in ("oscillator", "pendulum")]
    case, run = next(((c, r) for c, r in runs if r["method"] == "cimp"), runs[0])
    run["final_state"] = [x * (1.0 + 1e-6) for x in run["final_state"]]
    name = "%s / %s / dt=%g" % (case["id"], run["method"], run["dt"])
    print("perturbed final_state of %s by 1e-6 relative" % name)
    rc, lines = run_crosscheck(report, workdir)
    if rc != 1:
        fail("exit status %d, expected 1" % rc)
    if len(lines) != 1 or not lines[0].startswith("DISAGREE " + name + ":") \
            or "final_state" not in lines[0]:
        fail("expected exactly one disagreement naming %s (final_state), got %s" % (name, lines))


def swap(report, workdir):
    # prefer a case that also fits orders, so the order comparison is exercised as well
    cases = [c for c in report["cases"] if c["problem"]["id"] in ("oscillator", "pendulum")
             and {"csv1", "rk3"} <= {r["method"] for r in c["runs"] if r["status"] == "ok"}]
    case = next((c for c in cases if {"csv1", "rk3"} <= set(c.get("method_metrics") or {})),
                cases[0])
    other = {"csv1": "rk3", "rk3": "csv1"}
    for r in case["runs"]:
        r["method"] = other.get(r["method"], r["method"])
    mm = case.get("method_metrics") or {}
    case["method_metrics"] = {other.get(k, k): v for k, v in mm.items()}
    print("swapped csv1 <-> rk3 in case %s" % case["id"])
    rc, lines = run_crosscheck(report, workdir)
    if rc != 1:
        fail("exit status %d, expected 1" % rc)
    for m in ("csv1", "rk3"):
        if not any(l.startswith("DISAGREE %s / %s" % (case["id"], m)) for l in lines):
            fail("no disagreement named %s / %s" % (case["id"], m))


def badinput(report, workdir):
    rc, _ = run_crosscheck({"schema_version": 99, "cases": "nope"}, workdir)
    if rc != 2:
        fail("exit status %d for a bad report, expected 2" % rc)


def main():
    if len(sys.argv) != 4 or sys.argv[1] not in ("perturb", "swap", "badinput"):
        print(__doc__, file=sys.stderr)
        return 2
    mode, src, workdir = sys.argv[1:]
    os.makedirs(workdir, exist_ok=True)
    with open(src) as fh:
        report = copy.deepcopy(json.load(fh))
    globals()[mode](report, workdir)
    print("PASS: %s" % mode)
    return 0


if __name__ == "__main__":
    sys.exit(main())
