#!/usr/bin/python3
"""Negative tests for verify/crosscheck.py: a corrupted report must be caught and named.

    /usr/bin/python3 -m pytest verify/tests/test_crosscheck_negative.py::test_negative[MODE] \
        --report REPORT.json --workdir WORKDIR          (ctest crosscheck.MODE, from the source root)
    /usr/bin/python3 -m verify.tests.test_crosscheck_negative scale3e6 REPORT.json WORKDIR

Each mode cross-checks a small slice of the report (the cases it corrupts), usually once
unmodified and once corrupted; the corrupted one must exit 1 and add DISAGREE lines that name the
corrupted item:
  perturb  : one run's final_state x (1 + 1e-6)
  metric   : one run's error.final_abs x (1 + 1e-3)
  verdict  : one check's `passed` flipped
  swap     : method names csv1 <-> rk3 swapped in one case
  wrongcoef: a gauss2 run's final state from gauss2 with A_12 of the Gauss tableau + 1e-8
  lawres   : rk3's H_gamma max_step_res and rk3's angular max_law_res, each x 3
  undefined: a metric's definedness flipped both ways (nbody-zero-momentum)
  counts   : Newton counts x 3, a measure x (1 + 1e-3), a sweep count + 5, the h^4 coefficient
             x 1.1, the det error x 3
  kg       : the PDE cases' final states, E_n, an order slope + 0.05 and a verdict
  badinput : not a dampsym report -> exit 2
a cross-check that cannot be talked into agreeing:
  refest   : error.final_abs + 5e-4 with the report's reference_error_estimate 1e-3 (pend-orders,
             a certified reference): the report's estimate must not widen our tolerance
  argmax   : conformal-symplectic.max_rel_step = 1e9 where E_n is at round-off (cs-pendulum
             csv1) and an invariant's scale_at_max_step_res x 1e9 at round-off (osc-orders cimp)
  short    : a run one step short (steps, steps_planned, final_time, and the final state our own
             kernel gives after n - 1 steps): the step count comes from the case file
  threshold: a check's threshold set to 1e30 (the case file's threshold decides)
  deleted  : a run and a check deleted from the report, and a run added
  flipall  : EVERY check verdict of the cheap cases (55 of 87, 566 checks), every tie (a value equal
             to its threshold) and argon's flipped at once; each check must disagree (never agree,
             never "not comparable")
  state7   : every final state x (1 + 1e-7) in argon-crystal, outer-solar-system and kepler/osc
             cases: each run must disagree, or be "not comparable" only where our own ensemble
             shows a spread above 1e-8 (a chaotic run)
  scale3e6 : (a measurement, not a ctest) every metric x (1 + 3e-6): comparisons still agreeing,
             by family
"""
import contextlib
import copy
import io
import json
import os
import subprocess
import sys
from typing import Any, Callable, Dict, List, Optional, Tuple

import pytest

from verify import crosscheck
from verify import xproblems as xp
from verify import xrun

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PY = "/usr/bin/python3"
Rep = Dict[str, Any]
# the cross-check's cache of its own results (--xc-cache; crosscheck.default writes it): our side
# of the slices below is the computation crosscheck.default made, the planted faults are all on
# the report's side, and every comparison is made afresh (verify/xcache.py)
OPTIONS: Dict[str, Any] = {"cache": None}


def run_crosscheck(report: Rep, workdir: str, tag: str, jobs: int = 1,
                   extra: Optional[List[str]] = None) -> Tuple[int, List[str], str]:
    """Cross-check `report` (written to workdir/tag) in this process: (exit status, DISAGREE
    lines, output); `extra` options (default: the cache of OPTIONS, read-only)."""
    d = os.path.join(workdir, tag)
    os.makedirs(d, exist_ok=True)
    path = os.path.join(d, "report.json")
    with open(path, "w") as fh:
        json.dump(report, fh)
    # in this process (the cross-check keeps no state between reports but its case-file index):
    # a fresh interpreter per report would cost ~1.6 CPU s of imports and loop loading each time
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        if extra is None:
            extra = ["--cache", OPTIONS["cache"], "--cache-read-only"] if OPTIONS["cache"] else []
        rc = crosscheck.main([path, "--out", d, "--jobs", str(jobs)] + extra)
    lines = [ln for ln in out.getvalue().splitlines() if ln.startswith("DISAGREE")]
    return rc, lines, out.getvalue() + err.getvalue()


def result_of(workdir: str, tag: str) -> Rep:
    with open(os.path.join(workdir, tag, "crosscheck.json")) as fh:
        return json.load(fh)


def fail(msg: str) -> None:
    pytest.fail(msg, pytrace=False)


def compare(base_report: Rep, bad_report: Rep, workdir: str, must_name: List[str],
            must_quantity: Tuple[str, ...] = ()) -> None:
    _, base_lines, _ = run_crosscheck(base_report, workdir, "base")
    rc, lines, out = run_crosscheck(bad_report, workdir, "bad")
    new = [ln for ln in lines if ln not in base_lines]
    print("\n".join(new))
    if rc != 1:
        print(out)
        fail("exit status %d, expected 1" % rc)
    for name in must_name:
        if not any(ln.startswith("DISAGREE " + name) for ln in new):
            fail("no new disagreement names %s; new: %s" % (name, new))
    for q in must_quantity:
        if not any(q in ln for ln in new):
            fail("no new disagreement names the quantity %s; new: %s" % (q, new))
    print("caught and named: %s" % ", ".join(must_name))


def slice_of(report: Rep, *cids: str) -> Rep:
    cases = [copy.deepcopy(c) for c in report["cases"] if c["id"] in cids]
    if len(cases) != len(cids):
        fail("cases %s not all in the report" % (cids,))
    prov = dict(report.get("provenance") or {}, command_line="dampsym run " + " ".join(cids))
    chks = [k for c in cases for k in c.get("checks") or []]
    summary = dict(report.get("summary") or {}, cases=len(cases), runs=sum(len(c["runs"]) for c in cases),
                   checks_passed=sum(1 for k in chks if k.get("passed")),
                   checks_failed=sum(1 for k in chks if not k.get("passed")),
                   failed_cases=sum(1 for c in cases if any(not k.get("passed") for k in c.get("checks") or [])))
    return dict(report, cases=cases, provenance=prov, summary=summary)


def case_of(rep: Rep, cid: str) -> Rep:
    return next(c for c in rep["cases"] if c["id"] == cid)


def run_of(case: Rep, method: str) -> Rep:
    return next(r for r in case["runs"] if r["method"] == method and r.get("status", "ok") == "ok")


def rname(cid: str, r: Rep) -> str:
    return "%s / %s / dt=%g" % (cid, r["method"], r["dt"])


def our_state(case: Rep, method: str, dt: float, steps: int, env: Dict[str, str]) -> List[float]:
    """Our own kernel's state after `steps` steps (verify/xrun.py): in this process, or in a fresh
    interpreter with `env` (XC_PERTURB_GAUSS is read when verify/xmethods.py is imported)."""
    if not env:
        prob = xp.make_problem(case["problem"]["id"], case["problem"]["params"])
        return [float(x) for x in xrun.integrate(method, prob, dt, steps, case["t0"])["z"]]
    code = ("import sys, json; from verify import xproblems as xp, xrun; "
            "c = json.loads(sys.stdin.read()); p = xp.make_problem(c['problem']['id'], c['problem']['params']); "
            "o = xrun.integrate(%r, p, %r, %d, c['t0']); print(json.dumps(o['z'].tolist()))"
            % (method, dt, steps))
    proc = subprocess.run([PY, "-c", code], input=json.dumps(case), capture_output=True, text=True,
                          env=dict(os.environ, **env), cwd=ROOT)
    if proc.returncode:
        fail(proc.stderr)
    return json.loads(proc.stdout)


def mode_badinput(report: Rep, workdir: str) -> None:
    rc, _, _ = run_crosscheck({"schema_version": 99, "cases": "nope"}, workdir, "bad")
    if rc != 2:
        fail("exit status %d for a bad report, expected 2" % rc)


def mode_perturb_metric(report: Rep, workdir: str, mode: str) -> None:
    base = slice_of(report, "osc-orders")
    bad = copy.deepcopy(base)
    r = run_of(bad["cases"][0], "cimp")
    if mode == "perturb":
        r["final_state"] = [x * (1 + 1e-6) for x in r["final_state"]]
    else:
        r["metrics"]["error"]["final_abs"] *= 1 + 1e-3
    compare(base, bad, workdir, [rname("osc-orders", r)])


def mode_verdict(report: Rep, workdir: str) -> None:
    base = slice_of(report, "osc-orders")
    bad = copy.deepcopy(base)
    chk = next(k for k in bad["cases"][0]["checks"] if k.get("metric") == "order.slope")
    chk["passed"] = not chk["passed"]
    compare(base, bad, workdir, ["osc-orders / %s / check '%s'" % (chk["method"], chk["name"])])


def mode_swap(report: Rep, workdir: str) -> None:
    base = slice_of(report, "osc-orders")
    bad = copy.deepcopy(base)
    other = {"csv1": "rk3", "rk3": "csv1"}
    for r in bad["cases"][0]["runs"]:
        r["method"] = other.get(r["method"], r["method"])
    compare(base, bad, workdir, ["osc-orders / csv1", "osc-orders / rk3"])


def mode_lawres(report: Rep, workdir: str) -> None:
    base = slice_of(report, "osc-overdamped-hgamma-law", "nbody-zero-momentum")
    bad = copy.deepcopy(base)
    r1 = run_of(case_of(bad, "osc-overdamped-hgamma-law"), "rk3")
    r1["metrics"]["invariants"]["H_gamma"]["max_step_res"] *= 3.0
    r2 = run_of(case_of(bad, "nbody-zero-momentum"), "rk3")
    r2["metrics"]["momentum"]["angular"]["max_law_res"] *= 3.0
    compare(base, bad, workdir, [rname("osc-overdamped-hgamma-law", r1), rname("nbody-zero-momentum", r2)],
            ("invariants.H_gamma.max_step_res", "momentum.angular.max_law_res"))


def mode_undefined(report: Rep, workdir: str) -> None:
    base = slice_of(report, "nbody-zero-momentum")
    bad = copy.deepcopy(base)
    c = bad["cases"][0]
    r1 = run_of(c, "csv1")
    m = r1["metrics"]["momentum"]["linear"]
    if m.get("max_factor_dev") is not None:
        fail("csv1's linear max_factor_dev is defined at zero total momentum")
    m["max_factor_dev"] = 0.0
    m.get("undefined", {}).pop("max_factor_dev", None)
    r2 = run_of(c, "csv2")
    m = r2["metrics"]["momentum"]["angular"]
    m["max_law_res"] = None
    m.setdefault("undefined", {})["max_law_res"] = "corrupted: reported undefined"
    compare(base, bad, workdir, [rname(c["id"], r1), rname(c["id"], r2)],
            ("momentum.linear.max_factor_dev", "momentum.angular.max_law_res"))


def mode_counts(report: Rep, workdir: str) -> None:
    base = slice_of(report, "pend-table41-g0", "osc-fig31-k1", "osc-stability-sweep", "osc-trace-fig34",
                    "osc-stability-det")
    bad = copy.deepcopy(base)
    cs = {c["id"]: c for c in bad["cases"]}
    r = run_of(cs["pend-table41-g0"], "cimp")
    r["metrics"]["cost"]["newton_iters_per_step"] *= 3.0
    names = [rname("pend-table41-g0", r)]
    r = run_of(cs["osc-fig31-k1"], "cse-etd")
    r["metrics"]["measure"]["theta_mean_abs"] *= 1 + 1e-3
    names.append(rname("osc-fig31-k1", r))
    cs["osc-stability-sweep"]["method_metrics"]["csv1"]["stability-sweep"]["F_violations"] += 5
    names.append("osc-stability-sweep / csv1 (stability-sweep)")
    cs["osc-trace-fig34"]["method_metrics"]["cimp"]["trace-taylor"]["h4_coeff"] *= 1.1
    names.append("osc-trace-fig34 / cimp (trace-taylor)")
    r = run_of(cs["osc-stability-det"], "rk3")
    r["metrics"]["stability"]["det_abs_err"] *= 3.0
    names.append(rname("osc-stability-det", r))
    compare(base, bad, workdir, names, ("cost.newton_iters_per_step", "measure.theta_mean_abs",
                                        "stability-sweep.F_violations", "trace-taylor.h4_coeff",
                                        "stability.det_abs_err"))


def mode_kg(report: Rep, workdir: str) -> None:
    base = slice_of(report, "pde-kg-momentum", "pde-kg-cs", "pde-kg-orders", "pde-burgers-casimir",
                    "pde-schrodinger-invariants", "pde-nls-mass")
    bad = copy.deepcopy(base)
    cs = {c["id"]: c for c in bad["cases"]}
    r = run_of(cs["pde-kg-momentum"], "csv2")
    r["final_state"] = [x * (1 + 1e-10) for x in r["final_state"]]
    names = [rname("pde-kg-momentum", r)]
    r = run_of(cs["pde-kg-cs"], "rk4")
    r["metrics"]["conformal-symplectic"]["max_rel"] *= 3.0
    names.append(rname("pde-kg-cs", r))
    cs["pde-kg-orders"]["method_metrics"]["csv1"]["order"]["slope"] += 0.05
    names.append("pde-kg-orders / csv1")
    chk = next(k for k in cs["pde-kg-orders"]["checks"] if k["method"] == "csv1" and k["metric"] == "order.slope")
    chk["passed"] = not chk["passed"]
    names.append("pde-kg-orders / csv1 / check '%s'" % chk["name"])
    r = run_of(cs["pde-burgers-casimir"], "heun")
    r["metrics"]["invariants"]["casimir"]["max_step_res"] *= 3.0
    names.append(rname("pde-burgers-casimir", r))
    r = run_of(cs["pde-schrodinger-invariants"], "implicit-midpoint")
    r["metrics"]["invariants"]["energy"]["max_step_res"] *= 3.0
    names.append(rname("pde-schrodinger-invariants", r))
    r = run_of(cs["pde-nls-mass"], "cimp")
    r["final_state"] = [x * (1 + 1e-8) for x in r["final_state"]]
    names.append(rname("pde-nls-mass", r))
    compare(base, bad, workdir, names, ("final_state", "conformal-symplectic.max_rel", "order.slope", "verdict",
                                        "invariants.casimir.max_step_res", "invariants.energy.max_step_res"))


def mode_wrongcoef(report: Rep, workdir: str) -> None:
    base = slice_of(report, "families-orders-3-4")
    bad = copy.deepcopy(base)
    cc = bad["cases"][0]
    run = run_of(cc, "gauss2")
    run["final_state"] = our_state(cc, "gauss2", float(run["dt"]), int(run["steps"]),
                                   {"XC_PERTURB_GAUSS": "2,0,1,1e-8"})
    print("gauss2 dt=%g final state from a tableau with A_12 + 1e-8: %s" % (run["dt"], run["final_state"]))
    compare(base, bad, workdir, [rname("families-orders-3-4", run)])


def mode_refest(report: Rep, workdir: str) -> None:
    base = slice_of(report, "pend-orders")
    bad = copy.deepcopy(base)
    r = bad["cases"][0]["runs"][0]
    r["metrics"]["error"]["final_abs"] += 5e-4
    r["metrics"]["error"]["reference_error_estimate"] = 1e-3
    compare(base, bad, workdir, [rname("pend-orders", r)], ("error.final_abs", "error.reference_error_estimate"))


def mode_argmax(report: Rep, workdir: str) -> None:
    base = slice_of(report, "cs-pendulum", "osc-orders")
    bad = copy.deepcopy(base)
    r1 = run_of(case_of(bad, "cs-pendulum"), "csv1")
    if r1["metrics"]["conformal-symplectic"]["max_rel"] > 1e-13:
        fail("csv1's E_n on cs-pendulum is not at round-off")
    r1["metrics"]["conformal-symplectic"]["max_rel_step"] = 1e9
    r2 = run_of(case_of(bad, "osc-orders"), "cimp")
    inv = r2["metrics"]["invariants"]["H_gamma"]
    if inv["max_step_res"] > 1e-13:
        fail("cimp's H_gamma law on osc-orders is not at round-off")
    inv["scale_at_max_step_res"] *= 1e9
    compare(base, bad, workdir, [rname("cs-pendulum", r1), rname("osc-orders", r2)],
            ("conformal-symplectic.max_rel_step", "invariants.H_gamma.scale_at_max_step_res"))


def mode_short(report: Rep, workdir: str) -> None:
    base = slice_of(report, "osc-orders")
    bad = copy.deepcopy(base)
    r = run_of(bad["cases"][0], "rk3")
    n, dt = int(r["steps"]) - 1, float(r["dt"])
    r.update(steps=n, steps_planned=n, final_time=r["final_time"] - dt,
             final_state=our_state(bad["cases"][0], "rk3", dt, n, {}))
    compare(base, bad, workdir, [rname("osc-orders", r)], ("steps_planned",))


def mode_threshold(report: Rep, workdir: str) -> None:
    base = slice_of(report, "osc-orders")
    bad = copy.deepcopy(base)
    chk = next(k for k in bad["cases"][0]["checks"] if k["op"] in ("le", "lt"))
    chk["expected"] = 1e30
    label = "osc-orders / %s / check '%s'" % (chk["method"], chk["name"])
    compare(base, bad, workdir, [label], ("expected",))


def mode_deleted(report: Rep, workdir: str) -> None:
    base = slice_of(report, "osc-orders")
    bad = copy.deepcopy(base)
    c = bad["cases"][0]
    gone = c["runs"].pop(1)
    extra = copy.deepcopy(c["runs"][0])
    extra["dt"] = 0.3
    c["runs"].append(extra)
    chk = c["checks"].pop(0)
    compare(base, bad, workdir, ["osc-orders / (case)", "osc-orders / %s / check '%s'" % (chk["method"], chk["name"])],
            ("run %s dt=%g" % (gone["method"], gone["dt"]), "run %s dt=0.3" % extra["method"]))


def cheap_cases(report: Rep, budget: int) -> List[str]:
    """Cases whose runs take at most `budget` planned steps x state size in all."""
    out = []
    for c in report["cases"]:
        work = sum(int(r.get("steps_planned") or 0) * max(1, len(r.get("final_state") or [])) for r in c["runs"])
        if work <= budget:
            out.append(c["id"])
    return out


def ties(report: Rep) -> List[str]:
    """Cases with a check whose value equals its threshold (an exact tie: a count 0 <= 0)."""
    return [c["id"] for c in report["cases"]
            if any(k.get("value") is not None and k["value"] == k.get("expected") for k in c.get("checks") or [])]


def mode_flipall(report: Rep, workdir: str) -> None:
    ids = sorted(set(cheap_cases(report, 50_000)) | set(ties(report)) | {"argon-crystal"})
    bad = slice_of(report, *ids)
    flipped = 0
    for c in bad["cases"]:
        for k in c.get("checks") or []:
            k["passed"] = not k["passed"]
            flipped += 1
    rc, _, out = run_crosscheck(bad, workdir, "flipall", jobs=2)
    res = result_of(workdir, "flipall")
    missed = [r for r in res["checks"] if r["verdict"] != "disagree"]
    for r in missed:
        print("NOT CAUGHT: %s / %s / %s: %s" % (r["case"], r["method"], r["check"], r.get("reason") or [
            (c["quantity"], c["status"], c.get("reason")) for c in r["comparisons"]]))
    print("%d verdicts flipped in %d cases (%d exact ties among them); %d caught"
          % (flipped, len(ids), sum(1 for c in bad["cases"] for k in c["checks"]
                                    if k.get("value") is not None and k["value"] == k["expected"]),
             flipped - len(missed)))
    if rc != 1 or missed or len(res["checks"]) != flipped:
        fail("exit %d, %d flipped verdicts not caught, %d check records for %d checks"
             % (rc, len(missed), len(res["checks"]), flipped))


def mode_state7(report: Rep, workdir: str) -> None:
    ids = ["argon-crystal", "outer-solar-system", "kepler-table21", "osc-orders", "pend-orders", "rb-orders"]
    bad = slice_of(report, *ids)
    n = 0
    for c in bad["cases"]:
        for r in c["runs"]:
            if r.get("status", "ok") == "ok":
                r["final_state"] = [x * (1 + 1e-7) for x in r["final_state"]]
                n += 1
    rc, _, _ = run_crosscheck(bad, workdir, "state7", jobs=2)
    res = result_of(workdir, "state7")
    missed = []
    for r in res["runs"]:
        fs = next((c for c in r["comparisons"] if c["quantity"] == "final_state"), None)
        chaotic = fs is not None and fs["status"] == "not comparable" and "chaotic" in (fs.get("reason") or "")
        if fs is None or not (fs["status"] == "disagree" or chaotic):
            missed.append(r)
        elif chaotic:
            print("not comparable (%s): %s / %s / dt=%g" % (fs["reason"], r["case"], r["method"], r["dt"]))
    for r in missed:
        print("NOT CAUGHT: %s / %s / dt=%g" % (r["case"], r["method"], r["dt"]))
    oss = [r for r in res["runs"] if r["case"] == "outer-solar-system"]
    if rc != 1 or missed or not oss or any(r["verdict"] != "disagree" for r in oss):
        fail("exit %d; %d of %d perturbed final states not caught; outer solar system: %s"
             % (rc, len(missed), n, [r["verdict"] for r in oss]))
    print("%d final states x (1 + 1e-7): every one caught" % n)


def scaled(x: Any, f: float) -> Any:
    if isinstance(x, dict):
        return {k: scaled(v, f) for k, v in x.items()}
    if isinstance(x, list):
        return [scaled(v, f) for v in x]
    if isinstance(x, (int, float)) and not isinstance(x, bool):
        return x * f
    return x


def mode_scale3e6(report: Rep, workdir: str) -> None:
    """A measurement (no ctest: a whole cross-check): every metric of every run and fit x
    (1 + 3e-6); prints how many comparisons still agree, by family."""
    bad = copy.deepcopy(report)
    for c in bad["cases"]:
        for r in c["runs"]:
            r["metrics"] = scaled(r.get("metrics") or {}, 1 + 3e-6)
        c["method_metrics"] = scaled(c.get("method_metrics") or {}, 1 + 3e-6)
    run_crosscheck(bad, workdir, "scale3e6", jobs=2)
    res = result_of(workdir, "scale3e6")
    fam: Dict[str, Dict[str, int]] = {}
    for g in ("runs", "orders"):
        for r in res[g]:
            for c in r["comparisons"]:
                f = c.get("family", c["quantity"] if g == "runs" else "order fits")
                d = fam.setdefault(f, {"agree": 0, "disagree": 0, "not comparable": 0})
                d[c["status"]] += 1
    for f, d in sorted(fam.items(), key=lambda x: -x[1]["agree"]):
        print("%-28s agree %5d  disagree %5d  not comparable %5d" % (f, d["agree"], d["disagree"], d["not comparable"]))
    print("total: %s" % {k: sum(d[k] for d in fam.values()) for k in ("agree", "disagree", "not comparable")})


MODES: Dict[str, Callable[[Rep, str], None]] = {
    "badinput": mode_badinput, "perturb": lambda r, w: mode_perturb_metric(r, w, "perturb"),
    "metric": lambda r, w: mode_perturb_metric(r, w, "metric"), "verdict": mode_verdict, "swap": mode_swap,
    "lawres": mode_lawres, "undefined": mode_undefined, "counts": mode_counts, "kg": mode_kg,
    "wrongcoef": mode_wrongcoef, "refest": mode_refest, "argmax": mode_argmax, "short": mode_short,
    "threshold": mode_threshold, "deleted": mode_deleted, "flipall": mode_flipall, "state7": mode_state7,
    "scale3e6": mode_scale3e6,
}


@pytest.mark.parametrize("mode", sorted(m for m in MODES if m != "scale3e6"))
def test_negative(mode: str, report_path: str, workdir: str, xc_cache: Optional[str]) -> None:
    """The planted fault of `mode` is caught and named (the module docstring lists them)."""
    OPTIONS["cache"] = xc_cache
    wd = os.path.join(workdir, mode)
    os.makedirs(wd, exist_ok=True)
    with open(report_path) as fh:
        report = json.load(fh)
    MODES[mode](report, wd)


def main() -> int:
    """The measurement scale3e6 (not a test): MODE REPORT.json WORKDIR."""
    if len(sys.argv) != 4 or sys.argv[1] not in MODES:
        print(__doc__, file=sys.stderr)
        return 2
    mode, src, workdir = sys.argv[1:]
    os.makedirs(workdir, exist_ok=True)
    with open(src) as fh:
        report = json.load(fh)
    MODES[mode](report, workdir)
    print("PASS: %s" % mode)
    return 0


if __name__ == "__main__":
    sys.exit(main())
