#!/usr/bin/python3
"""Independent Python cross-check of a dampsym report.

    /usr/bin/python3 verify/crosscheck.py REPORT.json [--out DIR]

The report is read ONLY to learn what to recompute (problem, parameters, method, dt,
steps, t0, final_time) and which C++ numbers to compare against.  Every "ours" value
below is computed from scratch by verify/refmath.py (written from SPEC.md and the
papers); no number from the report is ever used as an expected value or as an input to
our own computation other than those run descriptors.

Compared per run (tolerances from the verification brief):
  final_state          |ours - theirs| / |theirs| <= 1e-10 (explicit), 1e-9 (implicit)
  final_time           ours = t0 + steps*dt, relative 1e-12
  error.final_abs      within a factor 2, or 1e-14 absolute
  invariants.H_gamma   max_step_res, last_step_res, max_global_res, max_global_ratio_dev
                       within a factor 10
                       (both <= 1e-13 agree)
  stability            det, half_trace relative 1e-12; matrix entries 1e-12 * max|M|;
                       spectral_radius relative 1e-7 (sqrt(eps)-sensitive near a double root)
  status (non-ok runs) the same status reproduced (divergence = growth past 1e50 |z0|)
and per (case, method): order.slope from our own errors and our own fit, +-0.02.
Writes DIR/crosscheck.json and DIR/crosscheck.md; exit 0 all agree, 1 any disagreement,
2 bad input.
"""
import argparse
import json
import math
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import refmath as rm  # noqa: E402  (our independent problems, methods and fit)

TOL_STATE = {"explicit": 1e-10, "implicit": 1e-9}
TOL_TIME = 1e-12
TOL_ERR_FACTOR, TOL_ERR_ABS = 2.0, 1e-14
TOL_INV_FACTOR, TOL_INV_FLOOR = 10.0, 1e-13
TOL_STAB = 1e-12
TOL_RHO = 1e-7
TOL_ORDER = 0.02
TOL_REF = 1e-9         # C++ certified GSL reference against our scipy reference (max norm)
TINY = 1e-300          # differences below this (subnormal results) count as equal
MAX_STEPS = 5_000_000  # we do not reproduce runs longer than this (none in the default suite)


class BadInput(Exception):
    pass


# ---------------------------------------------------------------------------------------
# comparison helpers: each returns a dict {quantity, ours, theirs, tolerance, agree}
# ---------------------------------------------------------------------------------------
def num(x):
    """JSON number (nlohmann writes NaN/inf as null) -> float."""
    return math.nan if x is None else float(x)


def cmp_rel(name, ours, theirs, tol, scale=None):
    ours, theirs = num(ours), num(theirs)
    scale = abs(theirs) if scale is None else scale
    diff = abs(ours - theirs)
    ok = diff <= tol * scale or diff <= TINY
    return dict(quantity=name, ours=ours, theirs=theirs, tolerance="rel %g" % tol,
                rel_diff=diff / scale if scale > 0 else diff, agree=bool(ok))


def cmp_state(ours, theirs, tol):
    ours, theirs = np.asarray(ours, float), np.asarray([num(x) for x in theirs])
    if ours.shape != theirs.shape:
        return dict(quantity="final_state", ours=ours.tolist(), theirs=theirs.tolist(),
                    tolerance="rel %g" % tol, agree=False, note="dimension differs")
    diff = float(np.linalg.norm(ours - theirs))
    scale = float(np.linalg.norm(theirs))
    ok = diff <= tol * scale or diff <= TINY
    return dict(quantity="final_state", ours=ours.tolist(), theirs=theirs.tolist(),
                tolerance="rel %g" % tol, rel_diff=diff / scale if scale > 0 else diff,
                agree=bool(ok))


def cmp_factor(name, ours, theirs, factor, abs_tol=0.0, both_below=None):
    """Agree when within a factor of each other, or |ours - theirs| <= abs_tol, or both
    are <= both_below (round-off level residuals)."""
    ours, theirs = num(ours), num(theirs)
    tol = "factor %g" % factor + (" or %g abs" % abs_tol if abs_tol else "") \
        + (" (both <= %g agree)" % both_below if both_below is not None else "")
    ok = (abs(ours - theirs) <= abs_tol
          or (ours > 0 and theirs > 0 and max(ours, theirs) <= factor * min(ours, theirs))
          or (both_below is not None and ours <= both_below and theirs <= both_below))
    return dict(quantity=name, ours=ours, theirs=theirs, tolerance=tol, agree=bool(ok))


# ---------------------------------------------------------------------------------------
# reproducing one case
# ---------------------------------------------------------------------------------------
def make_problem(case):
    """Our problem object, or (None, reason) when we cannot reproduce it."""
    try:
        pid = case["problem"]["id"]
        params = dict(case["problem"].get("params", {}))
    except (KeyError, TypeError) as exc:
        raise BadInput("case %s: malformed problem (%s)" % (case.get("id"), exc))
    cls = rm.PROBLEMS.get(pid)
    if cls is None:
        return None, "unknown problem '%s'" % pid
    unknown = sorted(set(params) - set(cls.param_names))
    if unknown:
        return None, "problem '%s' has parameters we do not model: %s" % (pid, unknown)
    missing = [k for k in cls.param_names if k not in params]
    if missing:
        raise BadInput("case %s: problem '%s' lacks parameters %s" % (case.get("id"), pid, missing))
    return cls(**{k: float(params[k]) for k in cls.param_names}), None


def reference(prob, t):
    """(our exact or certified reference state at time t after t0, its error estimate, note)."""
    if isinstance(prob, rm.Oscillator):
        return prob.exact(t), 0.0, "exact"
    return prob.reference(t)


def check_run(case, prob, run, t0, my_errors, need_error):
    """Reproduce one run; returns the per-run record.  When the run reports an error or
    need_error is set (the case fits orders), OUR error goes to my_errors[method][dt]."""
    method, dt = run["method"], float(run["dt"])
    rec = dict(case=case["id"], method=method, dt=dt, comparisons=[], notes=[])
    if method not in rm.METHODS:
        rec.update(verdict="not reproduced", reason="unknown method '%s'" % method)
        return rec
    status = run.get("status", "ok")
    steps_key = "steps" if status == "ok" else "steps_planned"
    nsteps = int(run.get(steps_key, run.get("steps", 0)))
    if nsteps > MAX_STEPS:
        rec.update(verdict="not reproduced", reason="%d steps is beyond our budget" % nsteps)
        return rec
    metrics = run.get("metrics") or {}
    inv = metrics.get("invariants") or {}
    want_traj = status == "ok" and "H_gamma" in inv and isinstance(prob, rm.Oscillator)
    # A run the C++ side finished is integrated to the end (only a non-finite state stops
    # it); for a run it reports as failed we call unbounded growth (1e50 |z0|) divergence.
    mine = rm.integrate(method, prob, dt, nsteps, keep=want_traj,
                        blowup=None if status == "ok" else 1e50)

    # runs either side did not finish are compared by status only
    if status != "ok" or mine["status"] != "ok":
        agree = mine["status"] == status
        rec["comparisons"].append(dict(quantity="status", ours=mine["status"], theirs=status,
                                       tolerance="equal", agree=agree, note=mine["message"]))
        rec["verdict"] = "agree" if agree else "disagree"
        return rec

    kind = "implicit" if method in rm.IMPLICIT else "explicit"
    my_t = t0 + nsteps * dt
    comps = rec["comparisons"]
    comps.append(cmp_rel("final_time", my_t, run["final_time"], TOL_TIME,
                         scale=max(1.0, abs(my_t))))
    z = np.array([mine["q"], mine["p"]])
    comps.append(cmp_state(z, run["final_state"], TOL_STATE[kind]))

    # error against OUR exact solution / OUR certified reference
    if "error" in metrics or need_error:
        zref, ref_err, ref_note = reference(prob, my_t - t0)
        err = float(np.linalg.norm(z - zref))
        my_errors.setdefault(method, {})[dt] = err
        if ref_err:
            rec["notes"].append("reference error estimate %.3g (%s)" % (ref_err, ref_note))
        if "error" in metrics:
            comps.append(cmp_factor("error.final_abs", err, metrics["error"].get("final_abs"),
                                    TOL_ERR_FACTOR, abs_tol=TOL_ERR_ABS))

    # conformal invariant H_gamma (B Ex. 1.2) along OUR trajectory, on the scale
    # S = (w^2 q^2 + p^2)/2 + gamma |q p| (docs/conventions.md, "Law residuals and their scales"):
    #   per step  |H_{n+1} - e^{-2 g h} H_n| / S_n                   (B Def. 2.3)
    #   global    |H_n - e^{-2 g t_n} H_0| / S_n
    #   ratio     |H_n - e^{-2 g t_n} H_0| / |e^{-2 g t_n} H_0|      (relative to the law)
    for name, vals in inv.items():
        if name == "H_gamma" and want_traj:
            qs, ps = mine["traj"]
            H = prob.H_gamma(qs, ps)
            S = 0.5 * (prob.omega ** 2 * qs ** 2 + ps ** 2) + prob.gamma * np.abs(qs * ps)
            step = np.abs(H[1:] - math.exp(-2.0 * prob.gamma * dt) * H[:-1]) / S[:-1]
            law = H[0] * np.exp(-2.0 * prob.gamma * dt * np.arange(len(H)))
            glob = np.abs(H - law) / S
            ratio = np.abs(H - law) / np.abs(law)
            for key, ours in (("max_step_res", step.max()), ("last_step_res", step[-1]),
                              ("max_global_res", glob.max()),
                              ("max_global_ratio_dev", ratio.max())):
                if key in vals and vals[key] is None:  # undefined there, with its reason
                    rec["notes"].append("invariants.H_gamma.%s undefined in the report: %s"
                                        % (key, vals.get("undefined", {}).get(key, "")))
                elif key in vals:
                    comps.append(cmp_factor("invariants.H_gamma." + key, float(ours), vals[key],
                                            TOL_INV_FACTOR, both_below=TOL_INV_FLOOR))
        else:
            rec["notes"].append("invariant %s not cross-checked" % name)

    # stability: one-step matrix from OUR step function applied to the unit vectors
    stab = metrics.get("stability")
    if stab is not None:
        if isinstance(prob, rm.Oscillator):
            M = rm.one_step_matrix(method, prob, dt)
            comps.append(cmp_rel("stability.det", np.linalg.det(M), stab.get("det"), TOL_STAB))
            comps.append(cmp_rel("stability.half_trace", 0.5 * np.trace(M),
                                 stab.get("half_trace"), TOL_STAB))
            if "spectral_radius" in stab:   # eigenvalues of a near-defective M move like sqrt(eps)
                comps.append(cmp_rel("stability.spectral_radius",
                                     float(np.abs(np.linalg.eigvals(M)).max()),
                                     stab["spectral_radius"], TOL_RHO))
            if "matrix" in stab:
                theirs = np.array([[num(x) for x in row] for row in stab["matrix"]])
                diff = float(np.abs(M - theirs).max()) if theirs.shape == M.shape else math.inf
                scale = float(np.abs(M).max())
                comps.append(dict(quantity="stability.matrix", ours=M.tolist(),
                                  theirs=theirs.tolist(), tolerance="rel %g" % TOL_STAB,
                                  rel_diff=diff / scale, agree=bool(diff <= TOL_STAB * scale)))
        else:
            rec["notes"].append("stability is defined for the oscillator only; not cross-checked")

    skipped = sorted(set(metrics) - {"error", "invariants", "stability"})
    if skipped:
        rec["notes"].append("metrics not cross-checked: " + ", ".join(skipped))
    rec["verdict"] = "agree" if all(c["agree"] for c in comps) else "disagree"
    return rec


def check_orders(case, prob, t0, my_errors, runs_by_method):
    """Fit OUR errors with OUR window rule and compare the slope with the report's."""
    out = []
    for method, mm in sorted((case.get("method_metrics") or {}).items()):
        theirs = (mm or {}).get("order")
        if theirs is None:
            continue
        rec = dict(case=case["id"], method=method, comparisons=[], notes=[])
        if prob is None or method not in rm.METHODS:
            rec.update(verdict="not reproduced", reason="problem or method not reproduced")
            out.append(rec)
            continue
        errs = my_errors.get(method, {})
        if len(errs) < len(runs_by_method.get(method, [])):
            rec["notes"].append("only %d of %d runs had our own error" %
                                (len(errs), len(runs_by_method.get(method, []))))
        zref, ref_err, _ = reference(prob, float(case["t_end"]) - t0)
        # floor: 1000 eps max(1, |exact final state|); for numerical references also
        # 100 x the reference's own error estimate (SPEC §4)
        floor = max(1000.0 * rm.EPS * max(1.0, float(np.linalg.norm(zref))), 100.0 * ref_err)
        mine = rm.fit_order(list(errs.keys()), list(errs.values()), floor)
        rec["ours_fit"] = mine
        t_ok = bool(theirs.get("ok"))
        if mine["ok"] and t_ok:
            c = dict(quantity="order.slope", ours=mine["slope"], theirs=num(theirs.get("slope")),
                     tolerance="abs %g" % TOL_ORDER)
            c["agree"] = bool(abs(c["ours"] - c["theirs"]) <= TOL_ORDER)
        else:
            c = dict(quantity="order.ok", ours=mine["ok"], theirs=t_ok, tolerance="equal",
                     agree=mine["ok"] == t_ok,
                     note="ours: %s; theirs: %s" % (mine.get("reason", "fit ok"),
                                                    theirs.get("reason", "fit ok")))
        rec["comparisons"].append(c)
        if mine["ok"] and t_ok and "window_dt" in theirs \
                and [float(d) for d in theirs["window_dt"]] != mine["window_dt"]:
            rec["notes"].append("windows differ: ours %s, theirs %s" % (mine["window_dt"],
                                                                        theirs.get("window_dt")))
        rec["verdict"] = "agree" if c["agree"] else "disagree"
        out.append(rec)
    return out


def check_case(case):
    for key in ("id", "problem", "runs"):
        if key not in case:
            raise BadInput("a case lacks '%s'" % key)
    prob, why = make_problem(case)
    if prob is None:
        runs = [dict(case=case["id"], method=r.get("method"), dt=r.get("dt"),
                     verdict="not reproduced", reason=why, comparisons=[], notes=[])
                for r in case["runs"]]
        return runs, check_orders(case, None, 0.0, {}, {})
    t0 = float(case.get("t0", 0.0))
    need_error = "order" in (case.get("diagnostics") or []) or any(
        "order" in (mm or {}) for mm in (case.get("method_metrics") or {}).values())
    my_errors, runs_by_method, recs = {}, {}, []
    for run in case["runs"]:
        try:
            run_m, run_dt = run["method"], run["dt"]
            run["final_state"], run["final_time"]
        except (KeyError, TypeError) as exc:
            raise BadInput("case %s: malformed run (%s)" % (case["id"], exc))
        runs_by_method.setdefault(run_m, []).append(run_dt)
        recs.append(check_run(case, prob, run, t0, my_errors, need_error))
    ref = case.get("reference") or {}
    if ref.get("kind") == "gsl-certified" and ref.get("final_state") is not None:
        # the C++ reference state at t_end against OUR scipy reference (compared, never used)
        zref, ref_err, note = reference(prob, float(ref["final_time"]) - t0)
        theirs = np.array([num(x) for x in ref["final_state"]])
        diff = float(np.max(np.abs(zref - theirs)))
        recs.append(dict(case=case["id"], method="(reference)", notes=[note],
                         comparisons=[dict(quantity="reference.final_state", ours=list(zref),
                                           theirs=list(theirs), tolerance="max-norm %g" % TOL_REF,
                                           difference=diff, agree=bool(diff <= TOL_REF))],
                         verdict="agree" if diff <= TOL_REF else "disagree"))
    return recs, check_orders(case, prob, t0, my_errors, runs_by_method)


# ---------------------------------------------------------------------------------------
# output
# ---------------------------------------------------------------------------------------
def finite_json(x):
    """Strict JSON: non-finite floats become null, numpy scalars become Python numbers."""
    if isinstance(x, dict):
        return {k: finite_json(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [finite_json(v) for v in x]
    if isinstance(x, (float, np.floating)):
        return float(x) if math.isfinite(x) else None
    if isinstance(x, np.bool_):
        return bool(x)
    return x


def fmt(x):
    if isinstance(x, float):
        return "%.6g" % x
    if isinstance(x, list):
        return "[" + ", ".join(fmt(v) for v in x) + "]"
    return str(x)


def label(rec):
    return "%s / %s" % (rec["case"], rec["method"]) + (" / dt=%g" % rec["dt"] if "dt" in rec else "")


def write_markdown(path, result):
    s = result["summary"]
    lines = ["# dampsym independent cross-check", "",
             "Report: `%s`  " % result["report"],
             "Time: %.2f s (every run integrated in full, no subsampling)  " % result["elapsed_seconds"],
             "",
             "| | agree | disagree | not reproduced |", "|---|---|---|---|",
             "| runs | %d | %d | %d |" % (s["runs"]["agree"], s["runs"]["disagree"], s["runs"]["not reproduced"]),
             "| order fits | %d | %d | %d |" % (s["orders"]["agree"], s["orders"]["disagree"], s["orders"]["not reproduced"]),
             "| comparisons | %d | %d | |" % (s["comparisons"]["agree"], s["comparisons"]["disagree"]), ""]
    bad = [r for r in result["runs"] + result["orders"] if r["verdict"] == "disagree"]
    if bad:
        lines += ["## Disagreements", ""]
        for r in bad:
            for c in r["comparisons"]:
                if not c["agree"]:
                    lines.append("- **%s**: %s ours %s, theirs %s (tolerance %s)" % (
                        label(r), c["quantity"], fmt(c["ours"]), fmt(c["theirs"]), c["tolerance"]))
        lines.append("")
    nr = [r for r in result["runs"] + result["orders"] if r["verdict"] == "not reproduced"]
    if nr:
        lines += ["## Not reproduced", ""] + ["- %s: %s" % (label(r), r["reason"]) for r in nr] + [""]
    lines += ["## Per run", "", "| case | method | dt | verdict | quantity | ours | theirs | rel. diff | tolerance |",
              "|---|---|---|---|---|---|---|---|---|"]
    for r in result["runs"] + result["orders"]:
        dt = fmt(float(r["dt"])) if r.get("dt") is not None else (
            "t_end" if r.get("method") == "(reference)" else "fit")
        for c in r["comparisons"] or [dict(quantity="-", ours="-", theirs="-", tolerance="-")]:
            rd = c.get("rel_diff")
            lines.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
                r["case"], r["method"], dt, r["verdict"] if c.get("agree", True) else "**disagree**",
                c["quantity"], fmt(c["ours"]), fmt(c["theirs"]),
                "%.2g" % rd if rd is not None else "", c["tolerance"]))
    notes = sorted({n for r in result["runs"] + result["orders"] for n in r.get("notes", [])})
    if notes:
        lines += ["", "## Notes", ""] + ["- " + n for n in notes]
    with open(path, "w") as fh:
        fh.write("\n".join(lines) + "\n")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("report", help="dampsym report.json")
    ap.add_argument("--out", help="output directory (default: the report's directory)")
    args = ap.parse_args(argv)
    t_start = time.perf_counter()
    try:
        try:
            with open(args.report) as fh:
                report = json.load(fh)
        except (OSError, ValueError) as exc:
            raise BadInput("cannot read %s: %s" % (args.report, exc))
        if not isinstance(report, dict) or report.get("schema_version") != 1 \
                or not isinstance(report.get("cases"), list):
            raise BadInput("%s is not a schema_version 1 dampsym report" % args.report)
        runs, orders = [], []
        for case in report["cases"]:
            r, o = check_case(case)
            runs += r
            orders += o
    except BadInput as exc:
        print("crosscheck: bad input: %s" % exc, file=sys.stderr)
        return 2

    def count(recs):
        return {v: sum(r["verdict"] == v for r in recs) for v in ("agree", "disagree", "not reproduced")}
    comps = [c for r in runs + orders for c in r["comparisons"]]
    elapsed = time.perf_counter() - t_start
    result = dict(tool="verify/crosscheck.py", report=os.path.abspath(args.report),
                  elapsed_seconds=elapsed,
                  summary=dict(runs=count(runs), orders=count(orders),
                               comparisons=dict(agree=sum(c["agree"] for c in comps),
                                                disagree=sum(not c["agree"] for c in comps))),
                  runs=runs, orders=orders)
    out = args.out or os.path.dirname(os.path.abspath(args.report))
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "crosscheck.json"), "w") as fh:
        json.dump(finite_json(result), fh, indent=1)
    write_markdown(os.path.join(out, "crosscheck.md"), result)

    s = result["summary"]
    for r in runs + orders:
        if r["verdict"] == "disagree":
            bad = "; ".join("%s ours %s theirs %s%s (tol %s)" % (
                c["quantity"], fmt(c["ours"]), fmt(c["theirs"]),
                " rel diff %.2g" % c["rel_diff"] if c.get("rel_diff") is not None else "",
                c["tolerance"]) for c in r["comparisons"] if not c["agree"])
            print("DISAGREE %s: %s" % (label(r), bad))
    nr = s["runs"]["not reproduced"] + s["orders"]["not reproduced"]
    print("crosscheck: runs %d agree, %d disagree, %d not reproduced; order fits %d agree, "
          "%d disagree, %d not reproduced; %d comparisons" % (
              s["runs"]["agree"], s["runs"]["disagree"], s["runs"]["not reproduced"],
              s["orders"]["agree"], s["orders"]["disagree"], s["orders"]["not reproduced"], len(comps)))
    if nr:
        print("crosscheck: %d not reproduced (see crosscheck.md)" % nr)
    print("crosscheck: wrote %s/crosscheck.{json,md} in %.2f s" % (out, elapsed))
    return 1 if s["runs"]["disagree"] + s["orders"]["disagree"] else 0


if __name__ == "__main__":
    sys.exit(main())
