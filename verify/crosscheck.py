#!/usr/bin/python3
"""Independent Python cross-check of a dampsym report.

    /usr/bin/python3 -m verify.crosscheck REPORT.json [--out DIR] [--jobs N] [--strict]
                                          [--cache DIR [--cache-read-only]]

--cache DIR keeps our own integrations, references and Newton counts (verify/xcache.py: keyed by
their arguments and our sources, never by the report; every comparison is always made).

Exit 0 when nothing disagrees, 1 on any disagreement (with --strict, the ctests' setting, also
when a run, fit, check or field is "not reproduced"), 2 on bad input (naming the file and key).

What decides what (nothing from report.json decides a tolerance, a window, a step count or a
stride): every case is read from its case file -- the one the report says dampsym read, when it
is still there with the case's id, else the file of that id in verify/cases/ -- with the report's
recorded `--set` overrides (verify/xcase.py): the runs (methods x step sizes, the `--method` selection of
the command line), each run's step count (t_end - t0)/dt, the output grid, the diagnostics, the
checks (metric, op, threshold, tolerance; expanded per method and step size as dampsym does).  A
run or check the file implies but the report lacks, one the report has in excess, a head field
(threshold, op, ...) that differs, or a case of the selected suite missing from the report is a
disagreement (group "structure").  Checks of unselected methods may be absent (or listed in the
case's `checks_not_run`).  Cases without a file (dampsym matrix builds them in code) take their
inputs from the report, marked so.  Every "ours" value is computed from scratch by
verify/xproblems.py, verify/xmethods.py, verify/xrun.py and verify/xmetrics.py (written from the
papers and docs/, never from the C++ sources or coefficient tables); a user's method comes from
its method file, read by verify/xmethodfile.py (the files the run loaded: each case file's
`method_files`, the run's `--methods`, methods/ beside its cases directory).

Outcomes (verify/xtol.py): a comparison agrees inside its tolerance and disagrees outside; inside
a tolerance that is not small against the value (>= 0.1 x) it is "not comparable", counted apart
with its reason (never as an agreement): two correct programs cannot be told apart from a wrong
one there.  A run whose final state is not comparable (a chaotic run past its Lyapunov time, as
our own ensemble shows) is "not comparable" as a whole; its other metrics are compared by the
statistics designed for them.  A check's verdict is recomputed from OUR value with the case
file's op and threshold; it is undecidable (not comparable) only when the threshold lies inside
our POSITIVE band of the value.  Every field of every run, fit and check is compared, or listed
under `not_compared` with the reason (verify/xfamilies.py NOT_COMPARED, xrunrec.RUN_NOT_COMPARED,
xcaserec.CHECK_NOT_COMPARED, order_known); a field we do not know is "not reproduced" by name.

Tolerance table, by metric family (verify/xfamilies.py FAMILIES, one compare function each;
"rel r + f" means |ours - theirs| <= r |ours| + f, f computed by us):
  final_time        rel 1e-12: t0 + n h in double.
  final_state       rel 1e-12 explicit / 1e-10 implicit (Newton stops at round-off); the linear
                    path (powers of our one-step matrix) 4 n eps; two-level kg-box (B (5.5))
                    8 eps n max(n, 1/dt) (xrunctx.two_level_tol); when the states differ by more,
                    our ROUND-OFF FLOOR 16 D: D = the relative final-state spread of our run and
                    our run from z0 (1 + 4 eps) componentwise (and from z_{n/2} (1 + 4 eps));
                    relative kicks, so argon's 1e-23 momenta get 4 eps of themselves.
  steps, steps_planned, failed_at_step   equal (from the case file); a divergence step within 1.
  run counts        rhs_evals, jac_evals, newton_iters, max_newton_iters_per_step: explicit methods
                    exactly (steps x stages); implicit ones inside the range of a stated family of
                    correct Newton solvers (verify/xnewton.py), as cost.*.
  error.*           rel 1e-6 (errors >= 1000x our reference's estimate) + our state bound + OUR
                    reference's estimate (exact solutions: their round-off estimate; DOP853
                    certified against rtol 1e-13); max_rel's over |z_ref| at its maximum's point
                    (and any rival within reach), final_rel's at t_end. Beyond that but within
                    the report's own declared reference estimate (<= 1e3 x ours): not comparable.
  error.reference_error_estimate   within 3 decades of ours (or of 1e3 eps |z_ref|): estimates of
                    two different integrators' errors; not comparable by construction, but a
                    planted 1e-3 against our 1e-13 disagrees.
  residuals         *_step_res, *_law_res, *_table_res, E_n max/last: rel 1e-6 + 64 eps (the
                    residual's round-off on its scale: a few sums of products), + 256 eps on the
                    linear path (its rounded one-step matrix).
  *_abs numerators  rel 1e-6 + 64 eps x our largest scale of the run.
  max_global_res    rel 1e-6 + 8 n eps (one rounding eps S(z_k) per step, kept by the law).
  global_res_slope  rel 1e-6 + 8 n eps / run time.
  ratio dev         max_global_ratio_dev, ratio_dev_slope: rel 1e-6 + 8 n max u_n (u_n = eps S_n /
                    |e^{-2 Gamma} I_0|, <= 1e-8 or <= 1e-2 |r_n| where r_n is resolved: then not
                    comparable; slope: / run time).
  momentum factor   max_factor_dev, first_factor: rel 1e-6 + 8 max eps S(z_n)/|X_n|.
  initial_norm      rel 1e-6 + 4 N eps S(z_0): a sum of N vectors in another order.
  scale_initial     rel 64 eps: a function of z0 alone.
  scale_at_max_*    where our maximum residual is above 1e3 x the residual floor: the scale at a
                    step within rel 1e-6 of our maximum (near-ties), rel 1e-6 + state bound; at
                    round-off the argmax is noise: the scale of SOME step of our run (our min..max
                    over the run; not comparable when that range is wide).
  max_rel_step      E_n above 1e-10: equal, or a tie to 1e-9; below: a step in 1..n (not
                    comparable: the argmax of round-off); 1e9 disagrees.
  energy.*          rel 1e-6 + 8 sqrt(n) eps S_H(z0) (random-walk round-off of H = T + V; on S_H for
                    *_res, over the run time for slopes); growth_ratio r = a2/a1 + r u (1/a1 + 1/a2)
                    (u the change's round-off, a1, a2 the halves' maxima); when the change is at
                    round-off: a ratio of two round-off maxima, any positive number (not comparable);
                    the errors against the reference (max/final_abs_error, drift_slope,
                    error_res_slope) + max|grad H(z_ref)| x (state bound + our reference's
                    estimate), within the report's declared estimate: not comparable.
  energy-balance.*  rel 1e-6 + 8 eps max|H| sum|w| / Delta (the difference quotient's round-off).
  dissipation-drift rel 1e-6 + our state tolerance in ln q + 8 eps |Gamma| (slopes: x 2 / span).
  measure.*         rel 1e-6 + the floor propagated pointwise from the state bound and our
                    reference's estimate (energy errors: x max |grad H|).
  local-error       rel 1e-6 + 8 eps |z(t0 + h)| + our exact solution's estimate.
  precession        total, rate: rel 1e-6 + 8 pi n eps (/ span for the rate).
  stability         entries abs 1e-12 max|M|; det, half traces rel 1e-12; *_err rel 1e-6 + 8 eps
                    max(1, |f|), det_*_err 8 eps (|M00 M11| + |M01 M10|) (/ e^{-2 gamma h}): det's
                    two products nearly cancel beyond gamma h = 2; a multivalue method (glm4):
                    not reproduced (its matrix acts on the multivalue state); spectral radius rel 1e-7 and eigenvalues as a set 1e-7 (a near-
                    defective M moves them like sqrt(eps)); F_condition equal unless a 4-eps tie.
  stability sweep   counts within the number of round-off tie points (|1/2 tr M| within 16 eps of
                    e^{-gamma h}); first failures within the range ties allow; F's formula boundary
                    exactly; max_half_trace_err rel 1e-9 + 1e-13.
  trace-taylor      h4_coeff within the truncation of a step-size-h estimate plus round-off
                    (verify/xsweep.py); expected rel 1e-12.
  order fits        ok (and status) equal; the report's slope and R^2 against OUR errors fitted over
                    the report's window (abs 1e-4, 1e-5: errors agreeing to 1e-6 move them less, and
                    a window rule of either side cannot make them differ); the window must be >= 3
                    consecutive ladder step sizes whose errors lie above OUR floor.
  chaotic runs      (D > 1e-8): every trajectory metric + 16 |m - m'| over our ensemble (the C++ run
                    is a third member); attractor mean_se/mean_rse at least |ours| (a batch-means
                    standard error from 10 batches varies by 24 %); Poincare pointwise distances
                    inside the attractor's pair-distance distribution, Hausdorff within a factor 2
                    of our ensemble; wide bands make these "not comparable".
  undefined         a null metric (reason under `undefined.<name>`) must be undefined here by the
                    docs' rule, and a defined one defined; a check on it must have failed.
  other metrics     rel 1e-6 (smooth functions of the trajectory); integers (counts) exactly.
  check value       rel 1e-6 + our band of the metric (ratio/spread: relative bands add; a
                    log-log slope: 2 x the largest relative band / the log span of dt).
  check verdict     the report's `passed` equal to the case file's op and threshold applied to the
                    report's own value, exactly (a flipped verdict, or `<=` evaluated as `<` on a
                    tie, always disagrees); and equal to the verdict from OUR value, undecidable
                    (not comparable) only when the threshold is inside our POSITIVE band.
  summary           the report's counts (cases, runs, checks passed / failed / not run, failed
                    cases) equal to those of its own cases.
  reference         the certified reference's final state within 1e3 x max(our estimate, 1e3 eps
                    |z|) of ours; its estimate within 3 decades of ours; its points and final time
                    from the case file's grid.

Tolerances that stay above 3e-6 relative (every metric x (1 + 3e-6), default suite: 6218
comparisons still agree, 4282 disagree, 2077 not comparable; test_crosscheck_negative.py
scale3e6): integers that stay 0 (undefined_points, explicit methods' Newton counts); step counts,
final states and evaluation counts (not scaled); Newton counts of implicit methods (the solver
family's range); error.* and measures below tol_state |z| / 3e-6 (the final state is known only to
its tolerance); residuals, their numerators and slopes at round-off (below 64 eps / 3e-6); order
slope and R^2 where our error bands allow it; the reference estimate (3 decades); chaotic runs.
"""
import argparse
import json
import math
import os
import sys
import time
from multiprocessing import Pool
from typing import Any, Dict, List, Optional, Tuple

import numpy as np

from . import diagnostics
from . import xcache
from . import xcase
from . import xcaserec
from . import xjit
from . import xmethods as xm
from . import xmethodfile
from . import xmetrics as xmt
from . import xrunrec
from .xmetrics import BadInput
from .xours import RunCtx
from .xtol import num

VERDICTS = ("agree", "disagree", "not comparable", "not reproduced")
Rec = Dict[str, Any]


def case_spec(case: Rec) -> Rec:
    """The case file (the one the report names, else verify/cases by id) with the report's
    overrides, or the report's inputs for a case that has none (dampsym matrix)."""
    try:
        spec = xcase.load_spec(case["id"], case.get("overrides"), xcase.recorded_case_file(case))
    except (OSError, ValueError, xcase.CaseFileError) as exc:
        raise BadInput("case %s: its case file: %s" % (case["id"], exc))
    return spec if spec is not None else xcase.spec_from_report(case)


def not_reproduced_case(case: Rec, why: str) -> Rec:
    cid = case["id"]
    recs = [dict(case=cid, method=r.get("method"), dt=r.get("dt"), verdict="not reproduced", reason=why,
                 comparisons=[], notes=[]) for r in case["runs"]]
    chks = [dict(case=cid, method=c.get("method"), check=c.get("name"), metric=c.get("metric"),
                 verdict="not reproduced", reason=why, comparisons=[], notes=[]) for c in case.get("checks") or []]
    orders = [dict(case=cid, method="%s (%s)" % (m, d), verdict="not reproduced", reason=why, comparisons=[], notes=[])
              for m, mmd in sorted((case.get("method_metrics") or {}).items())
              for d in (m.name for m in diagnostics.method_level()) if (mmd or {}).get(d) is not None]
    return dict(runs=recs, orders=orders, checks=chks, structure=[], case=cid, seconds=0.0, cpu_seconds=0.0,
                problem=(case.get("problem") or {}).get("id"))


PLUGIN_WHY = ("method '%s' is not defined here: with a C plugin loaded (docs/plugins.md) it may be "
              "the plugin's compiled code, which the cross-check has no definition of to step")


def run_contexts(case: Rec, spec: Rec, prob: Any, plugins: bool = False) -> Tuple[List[Rec], List[RunCtx]]:
    """Our run of every report run the case file implies (runs it does not imply are named in
    the structure record), integrated over the case file's step count; `plugins`: the run loaded
    C plugins (an unknown method is then said to be possibly theirs)."""
    want = {(m, h) for m in spec.get("methods") or [] for h in xcase.step_sizes(spec)}
    diags = xcase.diagnostics(spec)
    recs, ctxs = [], []
    for run in case["runs"]:
        try:
            method, dt = run["method"], float(run["dt"])
        except (KeyError, TypeError, ValueError) as exc:
            raise BadInput("case %s: key runs: malformed run (%s)" % (case["id"], exc))
        if (method, dt) not in want:
            continue
        if method not in xm.METHODS:
            why = xmethodfile.UNSUPPORTED.get(method, PLUGIN_WHY % method if plugins else "unknown method '%s'" % method)
            recs.append(dict(case=case["id"], method=method, dt=dt, verdict="not reproduced",
                             reason=why, comparisons=[], notes=[]))
            continue
        cx = RunCtx(case, spec, prob, run, method, dt, xcase.steps_for(spec, dt), xcase.grid_stride(spec, dt), diags)
        recs.append(xrunrec.check_run(cx))
        ctxs.append(cx)
    return recs, ctxs


def method_records(case: Rec, spec: Rec, prob: Any, ctxs: List[RunCtx], ours: Any) -> List[Rec]:
    """Each method's method-level records (order fits, sweeps, ...: verify/diagnostics) from our
    runs of the case, for every one the report holds."""
    out = []
    for method, mmd in sorted((case.get("method_metrics") or {}).items()):
        for d in diagnostics.method_level():
            theirs = (mmd or {}).get(d.name)
            if theirs is None or d.method is None:
                continue
            mc = diagnostics.MethodCtx(case, spec, prob, method, theirs, ctxs, ours.setdefault((method, None), {}),
                                       ours.setdefault(("__unc__", method), {}))
            out.append(d.method(mc))
    return out


def check_case(case: Rec, selection: Optional[List[str]]) -> Rec:
    t_case, c_case = time.perf_counter(), time.process_time()
    for key in ("id", "problem", "runs"):
        if key not in case:
            raise BadInput("a case lacks '%s'" % key)
    spec = case_spec(case)
    prob, why = xmt.make_problem(case)
    if prob is None:
        return not_reproduced_case(case, why or "problem not modelled")
    struct = xcaserec.structure(case, spec, selection)
    runs, ctxs = run_contexts(case, spec, prob, bool(xcase.RUN_PLUGINS))
    ours: Dict[Any, Rec] = {(cx.method, cx.dt): cx.mm for cx in ctxs}
    unc: Dict[Any, Rec] = {(cx.method, cx.dt): cx.unc for cx in ctxs}
    status = {(cx.method, cx.dt): cx.mine.get("status", "ok") for cx in ctxs}
    orders = method_records(case, spec, prob, ctxs, ours)
    for k in [k for k in ours if k[0] == "__unc__"]:
        unc[(k[1], None)] = ours.pop(k)
    checks = xcaserec.checks_records(case, spec, ours, unc, status)
    ref = next(((cx.priv["error.ref_final"], cx.priv["error.est"]) for cx in ctxs if "error.ref_final" in cx.priv), None)
    struct["comparisons"] += xcaserec.reference_comps(case, spec, ref)
    struct["verdict"] = "disagree" if any(c["status"] == "disagree" for c in struct["comparisons"]) else struct["verdict"]
    return dict(runs=runs, orders=orders, checks=checks, structure=[struct], case=case["id"],
                seconds=time.perf_counter() - t_case, cpu_seconds=time.process_time() - c_case,
                problem=case["problem"].get("id"))


def _worker(args: Tuple[Rec, Optional[List[str]]]) -> Rec:
    try:
        before = dict(xcache.STATS)
        with np.errstate(all="ignore"):     # diverged runs: inf/nan are compared as such
            rec = check_case(*args)
        rec["cache"] = {k: xcache.STATS[k] - before[k] for k in before}
        return rec
    except BadInput as exc:
        return dict(bad_input=str(exc))
    except Exception as exc:   # a fault of ours: name the case
        raise RuntimeError("case %s: %s" % (args[0].get("id"), exc)) from exc


# ---------------------------------------------------------------------------------------
def finite_json(x: Any) -> Any:
    if isinstance(x, dict):
        return {k: finite_json(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [finite_json(v) for v in x]
    if isinstance(x, (float, np.floating)):
        return float(x) if math.isfinite(x) else None
    if isinstance(x, np.bool_):
        return bool(x)
    if isinstance(x, np.integer):
        return int(x)
    if isinstance(x, np.ndarray):
        return finite_json(x.tolist())
    if isinstance(x, xmt.Undef):
        return repr(x)
    return x


def fmt(x: Any) -> str:
    if isinstance(x, float):
        return "%.6g" % x
    if isinstance(x, list):
        return "[" + ", ".join(fmt(v) for v in x) + "]"
    return str(x)


def label(rec: Rec) -> str:
    s = "%s / %s" % (rec["case"], rec.get("method"))
    if rec.get("check"):
        s += " / check '%s'" % rec["check"]
    if rec.get("dt") is not None:
        s += " / dt=%g" % rec["dt"]
    return s


def count(recs: List[Rec]) -> Dict[str, int]:
    return {v: sum(r["verdict"] == v for r in recs) for v in VERDICTS}


def comparisons_tally(recs: List[Rec]) -> Dict[str, int]:
    out = {"agree": 0, "disagree": 0, "not comparable": 0}
    for r in recs:
        for c in r["comparisons"]:
            out[c["status"]] += 1
    return out


def _vec(x: Any) -> str:
    return fmt(x) if not isinstance(x, list) else "(vector)"


def gfm_cell(x: Any) -> str:
    """A table cell that GitHub/GitLab Markdown keeps as one cell: '|' escaped, one line."""
    return str(x).replace("\\", "\\\\").replace("|", "\\|").replace("\n", " ")


VERDICT_RANK = {"agree": 0, "not comparable": 1, "not reproduced": 2, "disagree": 3}


def deviation(c: Rec) -> Optional[float]:
    """|ours - theirs| / tolerance of a comparison with an absolute tolerance (xtol.cmp_abs)."""
    tol = c.get("tol_abs")
    if not isinstance(tol, float) or not tol > 0.0:
        return None
    try:
        d = abs(float(c["ours"]) - float(c["theirs"]))
    except (TypeError, ValueError):
        return None
    return d / tol if math.isfinite(d) else None


def case_summary(case: str, recs: List[Rec]) -> Tuple[str, str, str, str, str]:
    """One case's row: runs compared (not 'not reproduced'), runs agreeing, the largest
    |ours - theirs| / tolerance of any comparison (and which), the case's worst verdict."""
    runs = [r for r in recs if "dt" in r and r.get("check") is None and r["verdict"] != "not reproduced"]
    agreeing = sum(1 for r in runs if r["verdict"] == "agree")
    worst, worst_q = -1.0, ""
    for r in recs:
        for c in r["comparisons"]:
            dv = deviation(c)
            if dv is not None and dv > worst:
                worst, worst_q = dv, c["quantity"]
    verdict = max((r["verdict"] for r in recs), key=lambda v: VERDICT_RANK.get(v, 0), default="agree")
    nc = sum(1 for r in recs if r["verdict"] == "not comparable")
    if verdict == "not comparable" or (verdict == "agree" and nc):
        verdict = "agree (%d not comparable)" % nc
    return (case, str(len(runs)), "%d of %d" % (agreeing, len(runs)),
            "%.2g (%s)" % (worst, worst_q) if worst >= 0 else "",
            verdict if verdict != "disagree" else "**disagree**")


def case_summary_table(result: Rec) -> List[str]:
    """The per-case summary (GFM table, every cell escaped), cases in the report's order."""
    by_case: Dict[str, List[Rec]] = {}
    for g in ("structure", "runs", "orders", "checks"):
        for r in result[g]:
            by_case.setdefault(r["case"], []).append(r)
    order = [t[0] for t in result["timing"]] + [c for c in by_case if c not in {t[0] for t in result["timing"]}]
    L = ["", "## Per case", "",
         "Runs compared: runs not 'not reproduced'; deviation / tolerance: the largest |ours - theirs| / "
         "tolerance of the case's comparisons with an absolute tolerance (above 1: a disagreement); verdict: "
         "the worst of its runs, fits, checks and structure (disagree, not reproduced, not comparable, agree).",
         "", "| case | runs compared | agreeing | max deviation / tolerance | verdict |", "|---|---|---|---|---|"]
    for cid in order:
        L.append("| " + " | ".join(gfm_cell(x) for x in case_summary(cid, by_case[cid])) + " |")
    return L


def write_markdown(path: str, result: Rec) -> None:
    s = result["summary"]
    L = ["# dampsym independent cross-check", "", "Report: `%s`  " % result["report"],
         "Time: %.2f s wall (every run integrated in full, no subsampling)" % result["elapsed_seconds"], "",
         "| | agree | disagree | not comparable | not reproduced |", "|---|---|---|---|---|"]
    for k in ("structure", "runs", "orders", "checks"):
        L.append("| %s | %s |" % (k, " | ".join(str(s[k][v]) for v in VERDICTS)))
    c = s["comparisons"]
    L += ["", "Comparisons: %d agree, %d disagree, %d not comparable (counted apart: each has its reason)."
          % (c["agree"], c["disagree"], c["not comparable"])]
    L += case_summary_table(result)
    L += ["", "## Time per case (CPU seconds do not depend on the machine's load)", "",
          "| case | problem | wall s | CPU s |", "|---|---|---|---|"]
    L += ["| %s | %s | %.2f | %.2f |" % (gfm_cell(t[0]), gfm_cell(t[1]), t[2], t[3]) for t in result["timing"]]
    allr = result["structure"] + result["runs"] + result["orders"] + result["checks"]
    for title, st in (("Disagreements", "disagree"), ("Not comparable", "not comparable")):
        rows = ["- **%s**: %s ours %s, theirs %s (tolerance %s)%s" % (
            label(r), c["quantity"], _vec(c["ours"]), _vec(c["theirs"]), c["tolerance"],
            ": " + c["reason"] if c.get("reason") else "") for r in allr for c in r["comparisons"] if c["status"] == st]
        if rows:
            L += ["", "## " + title, ""] + rows
    nr = [r for r in allr if r["verdict"] == "not reproduced"]
    if nr:
        L += ["", "## Not reproduced", ""] + ["- %s: %s" % (label(r), r.get("reason")) for r in nr]
    L += ["", "## Per comparison", "", "| item | verdict | quantity | ours | theirs | rel. diff | tolerance |",
          "|---|---|---|---|---|---|---|"]
    for r in allr:
        for c in r["comparisons"]:
            rd = c.get("rel_diff")
            L.append("| " + " | ".join(gfm_cell(x) for x in (
                label(r), c["status"] if c["status"] != "disagree" else "**disagree**", c["quantity"],
                _vec(c["ours"]), _vec(c["theirs"]), "%.2g" % rd if rd is not None else "", c["tolerance"])) + " |")
    with open(path, "w") as fh:
        fh.write("\n".join(L) + "\n")


def load_report(path: str) -> Rec:
    try:
        with open(path) as fh:
            report = json.load(fh)
    except (OSError, ValueError) as exc:
        raise BadInput("cannot read %s: %s" % (path, exc))
    if not isinstance(report, dict) or report.get("schema_version") not in (1, 2) \
            or not isinstance(report.get("cases"), list):
        raise BadInput("%s: key schema_version: not a schema_version 1 or 2 dampsym report" % path)
    for c in report["cases"]:
        if not isinstance(c, dict) or "id" not in c or "runs" not in c or "problem" not in c:
            raise BadInput("%s: key cases: a case lacks id/problem/runs" % path)
    return report


def run_all(report: Rec, jobs: int) -> List[Rec]:
    """Every case, longest first (planned steps) so the pool stays busy; results in report order."""
    cases = report["cases"]
    sel = xcase.selected_methods(report)
    cost = lambda c: -sum(int(num(r.get("steps_planned", r.get("steps", 0))) or 0) for r in c["runs"])  # noqa: E731
    order = sorted(range(len(cases)), key=lambda i: cost(cases[i]))
    try:   # the 10^7-step runs: keep freed memory in the heap (glibc mallopt), inherited by workers
        import ctypes
        libc = ctypes.CDLL("libc.so.6")
        libc.mallopt(-4, 0)
        libc.mallopt(-1, 1 << 40)
    except (OSError, AttributeError):
        pass
    xcase.case_index()
    if jobs > 1:
        with Pool(jobs) as pool:
            res = pool.map(_worker, [(cases[i], sel) for i in order], chunksize=1)
    else:
        res = [_worker((cases[i], sel)) for i in order]
    bad = [r for r in res if "bad_input" in r]
    if bad:
        raise BadInput(bad[0]["bad_input"])
    return [r for _, r in sorted(zip(order, res), key=lambda x: x[0])]


def load_method_files(report: Rec) -> List[str]:
    """The user's methods of the run (verify/xmethodfile.py): from each case's file, the run's
    --methods and the methods/ beside its cases directory."""
    index = xcase.case_index(run_cases_dir(report.get("provenance") or {}))
    files = [xcase.recorded_case_file(c) or index.get(c["id"]) for c in report["cases"]]
    return xmethodfile.load_all(report, [f for f in files if f])


def run_cases_dir(prov: Rec) -> str:
    """The cases directory of the run (its `--cases`, recorded as provenance.cases_dir) when it
    is still a directory, else verify/cases."""
    d = prov.get("cases_dir")
    return d if isinstance(d, str) and d and os.path.isdir(d) else xcase.CASES_DIR


def suite_cases(report: Rec) -> Optional[List[str]]:
    """The case ids the run's command line selects when it names a suite and no case (the
    suite's case files in the run's cases directory; "all": every one); None when it cannot be
    told (named cases, a shard, a merge, dampsym matrix)."""
    prov = report.get("provenance") or {}
    if "shard" in prov or "merged_from" in prov:
        return None
    words = xcase.shlex_split(prov.get("command_line") or "")
    if "run" not in words:
        return None
    rest, suites, i = words[words.index("run") + 1:], [], 0
    with_value = {"--out", "--jobs", "--suite", "--method", "--set", "--time-budget", "--shard", "--junit",
                  "--case-timeout", "--max-memory", "--figure-format", "--cases", "--methods"}
    while i < len(rest):
        w = rest[i]
        if w in with_value:
            suites += [rest[i + 1]] if w == "--suite" and i + 1 < len(rest) else []
            i += 2
            continue
        if w.startswith("--suite="):
            suites.append(w.split("=", 1)[1])
        elif not w.startswith("-"):
            return None
        i += 1
    suites = suites or ["default"]
    index = xcase.case_index(run_cases_dir(prov))
    return sorted(cid for cid, path in index.items()
                  if "all" in suites or set(suites) & set(xcase.suites_of(path)))


SUMMARY_KNOWN = ("cases", "failed_cases", "runs", "checks_passed", "checks_failed", "checks_not_run",
                 "methods_refuted")


def summary_record(report: Rec) -> Rec:
    """The report's summary against its own cases (counts it must add up to)."""
    cases, s = report["cases"], report.get("summary") or {}
    chks = [k for c in cases for k in c.get("checks") or []]
    ours = dict(cases=len(cases), runs=sum(len(c["runs"]) for c in cases),
                checks_passed=sum(1 for k in chks if k.get("passed")),
                checks_failed=sum(1 for k in chks if not k.get("passed")),
                failed_cases=sum(1 for c in cases if any(not k.get("passed") for k in c.get("checks") or [])),
                checks_not_run=sum(len(c.get("checks_not_run") or []) for c in cases),
                methods_refuted=len({r.get("method") for c in cases for r in c["runs"] if r.get("coefficients_refuted")}))
    comps = [dict(quantity="summary." + k, ours=ours[k], theirs=s[k], tolerance="equal: counted from its cases",
                  agree=ours[k] == s[k], status="agree" if ours[k] == s[k] else "disagree") for k in SUMMARY_KNOWN if k in s]
    rec = dict(case="(report)", method="(summary)", comparisons=comps, notes=[],
               verdict="disagree" if any(c["status"] == "disagree" for c in comps) else "agree")
    unknown = [k for k in s if k not in SUMMARY_KNOWN]
    if unknown and rec["verdict"] == "agree":
        rec.update(verdict="not reproduced", reason="fields not recomputed: " + ", ".join("summary." + k for k in unknown))
    return rec


def report_cases(report: Rec) -> List[Rec]:
    """A case twice, or a case of the selected suite that the report lacks (or one outside it)."""
    ids = [c["id"] for c in report["cases"]]
    out = []
    for i in sorted({i for i in ids if ids.count(i) > 1}):
        out.append(("case %s" % i, "once", "twice"))
    want = suite_cases(report)
    if want is not None:
        out += [("case %s" % i, "in the suite", "missing") for i in sorted(set(want) - set(ids))]
        out += [("case %s" % i, "not in the suite", "present") for i in sorted(set(ids) - set(want))]
    return [dict(case="(report)", method="(cases)", verdict="disagree", notes=[],
                 comparisons=[dict(quantity=q, ours=o, theirs=t, tolerance="the suite's case files",
                                   agree=False, status="disagree")]) for q, o, t in out]


def print_findings(result: Rec) -> None:
    for r in result["structure"] + result["runs"] + result["orders"] + result["checks"]:
        if r["verdict"] == "disagree":
            print("DISAGREE %s: %s" % (label(r), "; ".join(
                "%s ours %s theirs %s (tol %s)" % (c["quantity"], _vec(c["ours"]), _vec(c["theirs"]), c["tolerance"])
                for c in r["comparisons"] if c["status"] == "disagree")))
    s = result["summary"]
    line = "; ".join("%s %s" % (k, "/".join(str(s[k][v]) for v in VERDICTS)) for k in ("structure", "runs", "orders",
                                                                                    "checks"))
    c = s["comparisons"]
    print("crosscheck: (agree/disagree/not comparable/not reproduced) %s" % line)
    print("crosscheck: comparisons %d agree, %d disagree, %d not comparable"
          % (c["agree"], c["disagree"], c["not comparable"]))


def main(argv: Optional[List[str]] = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").split("\n")[0])
    ap.add_argument("report")
    ap.add_argument("--out")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--strict", action="store_true",
                    help="exit 1 also when anything is not reproduced")
    ap.add_argument("--cache", metavar="DIR",
                    help="keep our own integrations, references and Newton counts in DIR and reuse them "
                         "(keyed by their inputs and our sources, never by the report: verify/xcache.py)")
    ap.add_argument("--cache-read-only", action="store_true", help="read the --cache, add nothing to it")
    args = ap.parse_args(argv)
    t_start = time.perf_counter()
    try:
        xcache.configure(args.cache, write=not args.cache_read_only)
        report = load_report(args.report)
        load_method_files(report)   # registered here: the forked workers inherit them
        xcase.RUN_PLUGINS[:] = ((report.get("provenance") or {}).get("selection") or {}).get("plugins") or []
        warm_s = xjit.warm()   # compile the loops once here; the forked workers inherit them
        res = run_all(report, args.jobs)
    except BadInput as exc:
        print("crosscheck: bad input: %s" % exc, file=sys.stderr)
        return 2
    except OSError as exc:
        print("crosscheck: bad input: --cache %s: %s" % (args.cache, exc), file=sys.stderr)
        return 2
    groups = {k: [x for r in res for x in r[k]] for k in ("structure", "runs", "orders", "checks")}
    groups["structure"] = [summary_record(report)] + report_cases(report) + groups["structure"]
    summary: Rec = {k: count(v) for k, v in groups.items()}
    summary["comparisons"] = comparisons_tally([x for v in groups.values() for x in v])
    result = dict(tool="verify/crosscheck.py", report=os.path.abspath(args.report),
                  elapsed_seconds=time.perf_counter() - t_start, summary=summary,
                  timing=[(r["case"], r.get("problem", "?"), r["seconds"], r["cpu_seconds"]) for r in res],
                  cpu_seconds=sum(r["cpu_seconds"] for r in res), jit_warmup_seconds=warm_s,
                  cache=dict(directory=xcache.directory(), **{k: sum(r["cache"][k] for r in res) for k in xcache.STATS}),
                  coefficient_sources=xm.COEFFICIENT_SOURCES, **groups)
    out = args.out or os.path.dirname(os.path.abspath(args.report))
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "crosscheck.json"), "w") as fh:
        json.dump(finite_json(result), fh, indent=1)
    write_markdown(os.path.join(out, "crosscheck.md"), result)
    print_findings(result)
    print("crosscheck: wrote %s/crosscheck.{json,md} in %.2f s wall, %.1f s CPU in the workers"
          " (compiled loops: %s, %.2f s to compile or load them)"
          % (out, result["elapsed_seconds"], result["cpu_seconds"], "numba" if xjit.HAVE_NUMBA else "off", warm_s))
    if xcache.directory() is not None:
        print("crosscheck: cache %s: %d hits, %d misses, %d stored" % (
            xcache.directory(), result["cache"]["hits"], result["cache"]["misses"], result["cache"]["stored"]))
    nrep = sum(summary[k]["not reproduced"] for k in groups)
    if args.strict and nrep:
        print("crosscheck: --strict: %d item(s) not reproduced (crosscheck.md lists them)" % nrep)
        return 1
    return 1 if any(summary[k]["disagree"] for k in groups) else 0


if __name__ == "__main__":
    sys.exit(main())
