"""One run's record for verify/crosscheck.py: its run-level fields, final state and every metric
compared (verify/xfamilies.py) or listed as deliberately not compared, with the reason; a field
the cross-check does not know is reported, never skipped."""
from __future__ import annotations

import math
from typing import Any, Dict, List

import numpy as np

from . import diagnostics
from . import xfamilies as xf
from . import xmetrics as xmt
from . import xours
from .xrunctx import RunCtx
from .xtol import Comp, cmp_abs, cmp_equal, comp, in_range, num

# run-level fields: compared below, or not compared with the reason
RUN_COMPARED = ("method", "dt", "steps_planned", "status", "steps", "failed_at_step", "final_time",
                "final_state", "rhs_evals", "jac_evals", "newton_iters", "max_newton_iters_per_step", "metrics")
RUN_NOT_COMPARED = {
    "observed": "what the C++ run attached (recorder, stored grid points, laws, Jacobian pass): a "
                "description of the C++ computation, not a result",
    "wall_seconds": "a clock reading",
    "error": "status error: the exception's message (the status is compared)",
    "solve_failure": "the failed Newton solve's iteration and residual: the C++ solver's own state "
                     "(the status and the step are compared)",
    "coefficients_refuted": "dampsym's coefficient-level checks of a method file's declaration "
                            "(methods --check), not a result of the run: the run itself is compared",
}


def new_record(cx: RunCtx) -> Dict[str, Any]:
    return dict(case=cx.case["id"], method=cx.method, dt=cx.dt, comparisons=cx.comps, notes=cx.notes,
                not_compared=cx.not_compared)


def compare_status(cx: RunCtx) -> bool:
    """A run that did not finish (either side): the status, and the step of a divergence within
    one (overflow near 1e308 rounds either way).  True when the run is done with."""
    status = cx.run.get("status", "ok")
    mine = cx.mine
    if status == "ok" and mine["status"] == "ok":
        return False
    ok = mine["status"] == status
    if ok and status in ("diverged", "solve-failed"):
        # overflow near 1e308, or a Newton iteration at the edge of convergence, rounds either way
        ok = abs(mine["steps"] - int(num(cx.run.get("steps")))) <= 1
    cx.comps.append(comp("status", "%s at %d" % (mine["status"], mine["steps"]),
                         "%s at %s" % (status, cx.run.get("steps")), ok, "equal, the step of failure within 1"))
    return True


def compare_counts(cx: RunCtx) -> None:
    """steps_planned from the case file; steps, failed_at_step, final_time; evaluation counts:
    exact for explicit methods, inside the Newton family's range for implicit ones."""
    cx.comps.append(cmp_equal("steps_planned", cx.nsteps, cx.run.get("steps_planned"),
                              "equal: (t_end - t0) / dt of the case file"))
    if cx.mine["status"] != "ok" or cx.run.get("status", "ok") != "ok":
        for k in ("steps", "failed_at_step", "rhs_evals", "jac_evals", "newton_iters", "max_newton_iters_per_step"):
            if k in cx.run:
                cx.not_compared[k] = "a run that failed: follows the step of failure (compared within 1 by status)"
        return
    cx.comps.append(cmp_equal("steps", cx.mine["steps"], cx.run.get("steps")))
    if "failed_at_step" in cx.run:
        cx.comps.append(cmp_equal("failed_at_step", None, cx.run.get("failed_at_step")))
    for k in ("rhs_evals", "jac_evals", "newton_iters", "max_newton_iters_per_step"):
        if k not in cx.run:
            continue
        key = "run." + k
        if key in cx.cost_range:
            o, lo, hi = cx.cost_range[key]
            cx.comps.append(in_range(k, o, cx.run[k], lo - 1e-9, hi + 1e-9, "Newton family (verify/xnewton.py)"))
        elif key in cx.mm:
            cx.comps.append(cmp_equal(k, cx.mm[key], cx.run[k], "equal: steps x evaluations per step"))
        else:
            cx.not_compared[k] = ("a Newton count depends on the solver variant and round-off in the last "
                                  "update: compared (as the range of a family of correct solvers) where the "
                                  "case asks for cost or checks a count")


def compare_state(cx: RunCtx) -> None:
    """final_time rel 1e-12 (t0 + n h in double); final state at our tolerance (xours)."""
    my_t = cx.t0 + cx.nsteps * cx.dt
    cx.comps.append(cmp_abs("final_time", my_t, cx.run.get("final_time"), 1e-12, 0.0, "t0 + n h"))
    z = cx.mine["z"]
    theirs = np.array([num(x) for x in cx.run.get("final_state") or []])
    note = xours.state_tolerance(cx, theirs)
    diff = float(np.linalg.norm(z - theirs)) if theirs.shape == z.shape else math.inf
    ok = diff <= cx.tol * cx.scale
    st = "disagree" if not ok else ("not comparable" if cx.tol > xours.CHAOS_D else "agree")
    kw: Dict[str, Any] = dict(rel_diff=diff / cx.scale)
    if st == "not comparable":
        kw["reason"] = ("chaotic: our own ensemble spreads by D = %.3g (relative) over the run, above the "
                        "resolution 1e-8 that the comparison needs" % cx.D)
    cx.comps.append(comp("final_state", z.tolist(), theirs.tolist(), st,
                         "rel %.3g%s" % (cx.tol, " (" + note + ")" if note else ""), **kw))


def why_undefined(metrics: Dict[str, Any], key: str) -> Any:
    parts = key.split(".")
    return xmt.get_path(metrics, ".".join(parts[:-1] + ["undefined", parts[-1]]))


def compare_metrics(cx: RunCtx, rec: Dict[str, Any]) -> None:
    """Every flat metric of the report: compared by its family, listed as not compared (with
    the reason), or reported as not recomputed."""
    flat = xmt.flatten("", cx.metrics, {})
    for key, th in sorted(flat.items()):
        why = xf.not_compared(key)
        if why is not None:
            cx.not_compared["metrics." + key] = why
            continue
        if isinstance(th, str) and key not in cx.mm:
            rec.setdefault("unknown", []).append(key)
            continue
        if isinstance(th, str):
            cx.comps.append(cmp_equal(key, cx.mm[key], th))
            continue
        c = xf.compare_metric(cx, key, th, why_undefined(cx.metrics, key))
        if c is None:
            rec.setdefault("unknown", []).append(key)
        else:
            cx.comps.append(c)
    for diag in cx.diags:
        if diag in diagnostics.REGISTRY and diagnostics.REGISTRY[diag].per_run and diag not in cx.metrics:
            cx.comps.append(comp("metrics." + diag, "requested by the case file", "absent", False, "present"))


def run_fields(cx: RunCtx, rec: Dict[str, Any]) -> None:
    """Run-level keys the cross-check does not know are reported."""
    for k in cx.run:
        if k in RUN_NOT_COMPARED:
            cx.not_compared[k] = RUN_NOT_COMPARED[k]
        elif k not in RUN_COMPARED:
            rec.setdefault("unknown", []).append(k)


def finish(rec: Dict[str, Any]) -> Dict[str, Any]:
    """The run's verdict: disagree if any comparison disagrees; not comparable when its final
    state is (a chaotic run); not reproduced when a field is unknown to us; else agree."""
    comps: List[Comp] = rec["comparisons"]
    if any(c["status"] == "disagree" for c in comps):
        rec["verdict"] = "disagree"
    elif rec.get("unknown"):
        rec["verdict"] = "not reproduced"
        rec["reason"] = "fields not recomputed: " + ", ".join(rec["unknown"])
    elif any(c["quantity"] == "final_state" and c["status"] == "not comparable" for c in comps):
        rec["verdict"] = "not comparable"
        rec["reason"] = next(c["reason"] for c in comps if c["quantity"] == "final_state")
    else:
        rec["verdict"] = "agree"
    return rec


def check_run(cx: RunCtx) -> Dict[str, Any]:
    """Our run, its metrics and every comparison with the report's record."""
    rec = new_record(cx)
    run_fields(cx, rec)
    cx.comps.append(cmp_equal("dt", cx.dt, cx.run.get("dt")))
    xours.integrate(cx)
    if compare_status(cx):
        compare_counts(cx)
        return finish(rec)
    compare_state(cx)
    xours.all_metrics(cx)
    compare_counts(cx)
    compare_metrics(cx, rec)
    return finish(rec)
