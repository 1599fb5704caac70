"""Case-level records of verify/crosscheck.py: the structure (the report's runs and checks
against what the case file implies), the order fits and method-level diagnostics from OUR runs,
and every check's head, value and verdict from the case file and OUR value."""
from __future__ import annotations

import math
from typing import Any, Dict, List, Optional, Tuple

import numpy as np

from . import diagnostics
from . import xcase
from . import xmethods as xm
from . import xmetrics as xmt
from . import xsweep
from .refmath import fit_order
from .xmetrics import EPS, TINY, Undef
from .xtol import Comp, cmp_abs, cmp_equal, cmp_list, comp, num, worst_status

HEAD_FIELDS = ("metric", "op", "expected", "tolerance", "abs", "negative_control", "form", "methods",
               "across_dt", "refutes")
CHECK_NOT_COMPARED = {"note": "free text", "message": "the C++ message (the verdict is compared)",
                      "inputs": "the report's per-dt inputs of a comparison check (its value is "
                                "compared with ours from our runs)"}
Key = Tuple[str, float]
CASE_KNOWN = ("id", "problem", "methods", "t0", "t_end", "dt_ladder", "diagnostics", "runs", "method_metrics",
              "checks", "checks_not_run", "reference", "overrides", "measures")
CASE_NOT_COMPARED = {"title": "free text", "source": "free text", "file": "the path dampsym read (we read "
                     "it too, or verify/cases by id)", "no_checks_because": "free text", "figures": "drawing options",
                     "errors": "exceptions of the C++ tasks (their checks fail; those are compared)",
                     "problem_check": "dampsym's own check of the problem's Jacobians against central "
                     "differences of its functions (rounding-level numbers; a failure adds a failing check, "
                     "which is compared)"}
REF_NOT_COMPARED = ("certifier", "certifier_epsabs", "certifier_epsrel", "epsabs", "epsrel", "stepper", "rhs_evals",
                    "ok", "kind", "error")


def reference_comps(case: Dict[str, Any], spec: Dict[str, Any], ref: Optional[Tuple[Any, float]]) -> List[Comp]:
    """The certified reference's final state and estimate against OUR reference at t_end
    (estimates of two integrators' errors: within 3 decades of ours), its grid and time."""
    rr = case.get("reference") or {}
    out: List[Comp] = []
    if "points" in rr:
        out.append(cmp_equal("reference.points", xcase.reference_points(spec), rr["points"]))
    if "final_time" in rr:
        out.append(cmp_abs("reference.final_time", float(spec["t_end"]), rr["final_time"], 1e-12, 0.0))
    if ref is None:
        return out
    zr, est = ref
    nz = float(np.linalg.norm(zr))
    base = max(est, 1e3 * EPS * nz)
    if "final_state" in rr:
        th = np.array([num(x) for x in rr["final_state"]])
        d = float(np.linalg.norm(th - zr)) if th.shape == zr.shape else math.inf
        out.append(comp("reference.final_state", zr.tolist(), rr["final_state"], d <= 1e3 * base,
                        "abs 1e3 x max(our estimate, 1e3 eps |z|) = %.3g" % (1e3 * base), rel_diff=d / max(nz, TINY)))
    if rr.get("error_estimate") is not None:
        from .xtol import in_range
        out.append(in_range("reference.error_estimate", est, rr["error_estimate"], 0.0, 1e3 * base,
                            "another integrator's error estimate: within 3 decades of ours"))
    return out


def structure(case: Dict[str, Any], spec: Dict[str, Any], selection: Optional[List[str]]) -> Dict[str, Any]:
    """Case inputs, runs and the set of checks against the case file (with the report's
    overrides and method selection)."""
    comps: List[Comp] = []
    for k in ("t0", "t_end"):
        if k in spec or k == "t0":
            comps.append(cmp_equal(k, float(spec.get(k, 0.0)), case.get(k)))
    comps.append(cmp_list("dt_ladder", xcase.step_sizes(spec), case.get("dt_ladder"), 0.0, 0.0))
    methods = xcase.methods_run(spec, selection)
    comps.append(cmp_equal("methods", methods, case.get("methods"), "the case file's methods (selected)"))
    comps.append(cmp_equal("diagnostics", sorted(xcase.diagnostics(spec)),
                           sorted(xcase.diagnostics(dict(spec, diagnostics=case.get("diagnostics"))))))
    for k, v in sorted(((spec.get("problem") or {}).items())):
        if k != "id" and not isinstance(v, str):   # a name (enum) is recorded as its index
            comps.append(cmp_equal("problem." + k, v, xmt.get_path(case, "problem.params." + k)))
    comps.append(cmp_equal("problem.id", (spec.get("problem") or {}).get("id"), xmt.get_path(case, "problem.id")))
    want = {(m, h) for m in methods for h in xcase.step_sizes(spec)}
    have = [(r.get("method"), float(num(r.get("dt")))) for r in case.get("runs") or []]
    for m, h in sorted(want - set(have)):
        comps.append(comp("run %s dt=%g" % (m, h), "implied by the case file", "missing", False, "present"))
    for m, h in sorted(set(have) - want):
        comps.append(comp("run %s dt=%g" % (m, h), "not in the case file", "present", False, "absent"))
    if len(have) != len(set(have)):
        comps.append(comp("runs", "each once", "a run twice", False, "each (method, dt) once"))
    if spec.get("_from_report"):
        comps = [c for c in comps if not c["quantity"].startswith("run ")]
    rec = dict(case=case["id"], method="(case)", comparisons=comps, notes=[spec.get("_file", "")],
               not_compared={k: v for k, v in CASE_NOT_COMPARED.items() if k in case})
    rec["not_compared"].update({"reference." + k: "the C++ reference's settings and cost" for k in REF_NOT_COMPARED
                                if k in (case.get("reference") or {})})
    unknown = [k for k in case if k not in CASE_KNOWN and k not in CASE_NOT_COMPARED]
    rec["verdict"] = worst_status(comps)
    if unknown and rec["verdict"] == "agree":
        rec.update(verdict="not reproduced", reason="fields not recomputed: " + ", ".join(unknown))
    return rec


def _fit_window(dts: List[float], errs: List[float], window: List[float]) -> Dict[str, Any]:
    """Slope and R^2 of OUR errors over the report's window (so the comparison is tight whatever
    window rule each side uses; the window itself is checked for validity)."""
    pts = [(d, e) for d, e in zip(dts, errs) if any(abs(d - w) <= 1e-12 * w for w in window)]
    if len(pts) < 2 or any(not (e > 0) for _, e in pts):
        return dict(slope=None, r2=None)
    x, y = np.log([d for d, _ in pts]), np.log([e for _, e in pts])
    slope, icept = np.polyfit(x, y, 1)
    ss_res = float(np.sum((y - (slope * x + icept)) ** 2))
    ss_tot = float(np.sum((y - y.mean()) ** 2))
    return dict(slope=float(slope), r2=1.0 - ss_res / ss_tot if ss_tot > 0 else 1.0, n=len(pts))


def _window_valid(ladder: List[float], window: List[float], errs: Dict[float, float], floor: float) -> bool:
    """A window is >= 3 consecutive ladder step sizes whose (our) errors are above our floor."""
    lad = sorted(ladder, reverse=True)
    idx = [i for i, d in enumerate(lad) if any(abs(d - w) <= 1e-12 * w for w in window)]
    if len(idx) != len(window) or len(idx) < 3 or idx != list(range(idx[0], idx[0] + len(idx))):
        return False
    return all(errs.get(lad[i], 0.0) > floor for i in idx)


def local_orders(dts: List[float], es: List[float], window: List[float], theirs: Any, dlt: float) -> Optional[Comp]:
    """The report's local orders between neighbouring step sizes of its window, from OUR errors:
    each within 2 max(our error band / error) / log(h_i / h_{i+1}) + 1e-6.  None when the
    report's list does not run over its window's neighbours (then listed as not compared)."""
    pts = sorted([(d, e) for d, e in zip(dts, es) if any(abs(d - w) <= 1e-12 * w for w in window)], reverse=True)
    if not isinstance(theirs, list) or len(theirs) != len(pts) - 1 or len(pts) < 2:
        return None
    mine = [math.log(pts[i][1] / pts[i + 1][1]) / math.log(pts[i][0] / pts[i + 1][0])
            if pts[i][1] > 0 and pts[i + 1][1] > 0 else math.nan for i in range(len(pts) - 1)]
    band = max(2 * dlt / math.log(pts[i][0] / pts[i + 1][0]) for i in range(len(pts) - 1)) + 1e-6
    return cmp_list("local_orders", mine, theirs, 0.0, band, "our errors over the report's window")


def order_fit(cid: str, method: str, theirs: Dict[str, Any], errs: Dict[float, Tuple[float, float, float]],
              ladder: List[float], ref_norm: float, kind: str, ran: bool = False) -> Dict[str, Any]:
    """An order fit: ours from our errors; the report's slope and R^2 against OUR errors fitted
    over the report's window (abs 1e-4, 1e-5: errors agreeing to 1e-6 move them less), its
    window valid by our floor, its ok/status against ours, its local orders against ours."""
    rec: Dict[str, Any] = dict(case=cid, method=method if kind == "order" else "%s (%s)" % (method, kind),
                               comparisons=[], notes=[])
    if not errs and ran:
        # every run of ours failed (diverged, solve failed): no point to fit, as for the report
        comps = rec["comparisons"]
        comps.append(comp("ok", False, theirs.get("ok"), theirs.get("ok") is False, "equal"))
        comps.append(comp("status", "too few points", theirs.get("status"),
                          theirs.get("status", "too few points") == "too few points", "equal: no run of ours has an error"))
        rec["verdict"] = worst_status(comps)
        return rec
    if not errs:
        rec.update(verdict="not reproduced", reason="no errors of our own for %s" % method)
        return rec
    est = max(v[1] for v in errs.values())
    floor = max(1000 * EPS * max(1.0, ref_norm), 100 * est)
    dts = sorted(errs, reverse=True)
    es = [errs[d][0] for d in dts]
    # errors not small against the solution stay out (conventions §5): the reference's final norm
    # where it resolves it, for the global fit only
    scale = ref_norm if kind == "order" and ref_norm > 100 * est else math.inf
    fit = fit_order(dts, es, floor, scale)
    comps = rec["comparisons"]
    span = math.log(max(dts) / min(dts)) if len(dts) > 1 else 1.0
    dlt = max([errs[d][2] / errs[d][0] for d in dts if errs[d][0] > floor] or [0.0])
    b_slope, b_r2 = 1e-9 + 2 * dlt / span, 1e-5 + 2 * dlt
    t_ok = theirs.get("ok")
    if "status" in theirs:
        t_ok = bool(t_ok) and theirs.get("status") == "ok"
    comps.append(cmp_equal(kind + ".ok", bool(fit["ok"]), bool(t_ok)))
    if "status" in theirs:
        comps.append(cmp_equal(kind + ".status", fit["status"], theirs.get("status")))
    if theirs.get("finest_local_order") is not None and fit.get("finest_local_order") is not None:
        pts = [d for d in dts if errs[d][0] > floor]
        lo_band = 2 * dlt / math.log(pts[-2] / pts[-1]) + 1e-6 if len(pts) > 1 else 1e-6
        comps.append(cmp_abs(kind + ".finest_local_order", fit["finest_local_order"],
                             theirs.get("finest_local_order"), 0.0, lo_band,
                             "our errors at the two finest usable steps"))
    window = [float(w) for w in theirs.get("window_dt") or theirs.get("window") or []]
    if theirs.get("slope") is not None:
        if not window:
            window = fit.get("window_dt") or []
        mine = _fit_window(dts, es, window)
        comps.append(cmp_abs(kind + ".slope", mine["slope"], theirs.get("slope"), 0.0, b_slope,
                             "our errors over the report's window; 1e-9 + 2 max(our error band / error) / "
                             "log span"))
        if theirs.get("r2") is not None:
            comps.append(cmp_abs(kind + ".r2", mine["r2"], theirs.get("r2"), 0.0, b_r2,
                                 "our errors, its window; 1e-5 + 2 max relative error band"))
        lo = local_orders(dts, es, window, theirs.get("local_orders"), dlt)
        if lo is not None:
            comps.append(lo)
        comps.append(comp(kind + ".window", fit.get("window_dt"), window,
                          _window_valid(ladder, window, {d: errs[d][0] for d in errs}, floor),
                          ">= 3 consecutive step sizes with errors above our floor %.3g" % floor))
    rec["fit"] = dict(fit, band_slope=b_slope, band_r2=b_r2)
    rec["verdict"] = worst_status(comps)
    return rec


def order_known(rec: Dict[str, Any], theirs: Dict[str, Any], kind: str) -> None:
    """Fields of an order fit we compare (above) or deliberately do not."""
    known = {"ok", "slope", "r2", "window_dt", "window", "status", "reason", "points", "local_orders", "floor",
             "dts", "errors", "intercept", "dropped", "floor_source", "finest_local_order", "solution_scale"}
    rec["not_compared"] = {k: why for k, why in (
        ("reason", "free text"), ("floor", "the C++ fit's own floor (ours decides the window's validity)"),
        ("points", "how many step sizes the C++ fit used (its window is checked)"),
        ("local_orders", "local orders between neighbours: compared where they run over the window's "
                         "neighbours (see the comparisons), else through the slope"),
        ("errors", "the ladder's errors are compared run by run (error.final_abs)"),
        ("dts", "the ladder (compared with the case file)"), ("intercept", "follows from slope and errors"),
        ("solution_scale", "the reference's final norm (the reference state is compared)"),
        ("dropped", "step sizes the C++ fit dropped below its own floor (the window's validity is checked "
                    "against ours)"), ("floor_source", "a description string"))
        if k in theirs}
    if any(c["quantity"] == "local_orders" for c in rec["comparisons"]):
        rec["not_compared"].pop("local_orders", None)
    unknown = [k for k in theirs if k not in known]
    if unknown:
        rec["unknown"] = unknown
        if rec["verdict"] == "agree":
            rec.update(verdict="not reproduced", reason="fields not recomputed: " + ", ".join(unknown))


Ours = Dict[Tuple[str, Optional[float]], Dict[str, Any]]


def _member_value(ours: Ours, unc: Ours, m: str, d: float, metric: str) -> Any:
    v = (ours.get((m, d)) or {}).get(metric)
    if v is None or isinstance(v, Undef) or isinstance(v, str):
        return v
    b = (unc.get((m, d)) or {}).get(metric)
    return float(v), (float(b) if b is not None else 1e-6 * abs(float(v)))


def comparison_value(hd: Dict[str, Any], spec: Dict[str, Any], ours: Ours, unc: Ours) -> Any:
    """OUR value and band of a ratio / spread / across-dt check (docs/case-keys.md), or a string
    saying why there is none.  Bands: relative bands add for a ratio or max/min; a log-log slope
    moves by twice the largest relative band over the log span of dt."""
    metric, form = hd["metric"], hd.get("form", "per-method")
    dts = [float(hd["dt"])] if hd.get("dt") is not None else xcase.step_sizes(spec)
    hs, vals, rels = [], [], []
    for d in dts:
        xs = [_member_value(ours, unc, m, d, metric) for m in hd["members"]]
        bad = [m for m, x in zip(hd["members"], xs) if not isinstance(x, tuple)]
        if bad:
            x = xs[hd["members"].index(bad[0])]
            return x if isinstance(x, Undef) else "metric %s not recomputed for %s at dt=%g" % (metric, bad[0], d)
        v = [a for a, _ in xs]
        r = [b / abs(a) if a else math.inf for a, b in xs]
        if form == "ratio":
            val, rel = v[0] / v[1], r[0] + r[1]
        elif form == "spread":
            val, rel = max(v) / min(v), r[int(np.argmax(v))] + r[int(np.argmin(v))]
        else:
            val, rel = v[0], r[0]
        hs.append(d)
        vals.append(val)
        rels.append(rel)
    if not hd.get("across_dt"):
        return vals[0], abs(vals[0]) * rels[0]
    if any(not (x > 0.0) or not math.isfinite(x) for x in vals):
        return "log-log slope of non-positive values"
    lx, ly = np.log(hs), np.log(vals)
    slope = float(np.polyfit(lx, ly, 1)[0])
    return slope, 2.0 * max(rels) / max(float(lx.max() - lx.min()), TINY)


def _ours_for(hd: Dict[str, Any], spec: Dict[str, Any], ours: Ours, unc: Ours, status: Dict[Any, str]) -> Any:
    """(value, band), an Undef, or a string (not recomputed / a run that did not finish / a
    method the cross-check does not step, whose checks are not reproduced either)."""
    unknown = [m for m in (hd.get("members") or [hd.get("method")]) if isinstance(m, str) and m not in xm.METHODS]
    if unknown:
        return "method %s is not reproduced (its runs say why)" % unknown[0]
    if hd.get("form", "per-method") != "per-method" or hd.get("across_dt"):
        return comparison_value(hd, spec, ours, unc)
    key = (hd["method"], hd.get("dt"))
    st = status.get(key, "ok")
    diag = hd["metric"].split(".")[0]
    if st != "ok" and diag != "run" and not (diag in diagnostics.REGISTRY and diagnostics.REGISTRY[diag].keeps_failed):
        return Undef("run %s" % st)
    v = (ours.get(key) or {}).get(hd["metric"])
    m_status = (ours.get(key) or {}).get(diag + ".status", "ok")
    if m_status != "ok":
        return Undef("the measurement %s" % m_status)   # its checks fail with that status
    if v is None:
        return "metric %s not recomputed" % hd["metric"]
    if isinstance(v, (Undef, str)):
        return v
    b = (unc.get(key) or {}).get(hd["metric"], 0.0)
    return float(v), float(b)


def decide(op: str, v: float, exp: float, tol: float) -> bool:
    return {"le": v <= exp, "ge": v >= exp, "lt": v < exp, "gt": v > exp,
            "near": abs(v - exp) <= tol}[op]


def verdict_comp(hd: Dict[str, Any], v: float, band: float, passed: Any) -> Comp:
    """The verdict from OUR value and the case file's op and threshold; a tie (the threshold, or
    near's edge, inside our POSITIVE band) cannot be decided here: not comparable."""
    exp, tol = float(hd["expected"]), float(hd.get("tolerance") or 0.0)
    mine = decide(hd["op"], v, exp, tol)
    edge = abs(abs(v - exp) - tol) if hd["op"] == "near" else abs(v - exp)
    tie = band > 0.0 and edge <= band
    ok = mine == bool(passed)
    st = "agree" if ok and not tie else ("not comparable" if tie else "disagree")
    kw: Dict[str, Any] = dict(note="our value %.17g, band %.3g" % (v, band))
    if tie:
        kw["reason"] = "the threshold lies inside our band"
    return comp("verdict", mine, bool(passed), st, "equal (undecidable only inside our positive band)", **kw)


def own_verdict(hd: Dict[str, Any], rchk: Dict[str, Any]) -> Comp:
    """The report's verdict against ITS OWN value with the case file's op and threshold, exactly
    (a null value fails): a flipped verdict, or a `<=` evaluated as `<` on a tie, is seen even
    where our value cannot decide (our band straddles the threshold)."""
    tv = rchk.get("value")
    if tv is None or not isinstance(tv, (int, float)):
        want = False
    else:
        x = abs(float(tv)) if hd.get("abs") else float(tv)
        want = decide(hd["op"], x, float(hd["expected"]), float(hd.get("tolerance") or 0.0))
    return comp("verdict of its own value", want, bool(rchk.get("passed")), want == bool(rchk.get("passed")),
                "equal: the case file's %s %.17g applied to the report's value" % (hd["op"], float(hd["expected"])))


def check_record(cid: str, hd: Dict[str, Any], rchk: Dict[str, Any], spec: Dict[str, Any],
                 ours: Ours, unc: Ours, status: Dict[Any, str]) -> Dict[str, Any]:
    """One check: its head against the case file, its value and verdict against ours."""
    rec: Dict[str, Any] = dict(case=cid, method=hd["method"], check=hd["name"], metric=hd["metric"],
                               comparisons=[], notes=[], not_compared={})
    if hd.get("dt") is not None:
        rec["dt"] = float(hd["dt"])
    comps = rec["comparisons"]
    for f in HEAD_FIELDS:
        want = hd.get(f, False if f == "negative_control" else None)
        got = rchk.get(f, False if f == "negative_control" else None)
        if f == "form" and want is None:
            continue
        if not xcase.same(want, got):
            comps.append(comp(f, want, got, False, "equal to the case file"))
    for k in rchk:
        if k in CHECK_NOT_COMPARED:
            rec["not_compared"][k] = CHECK_NOT_COMPARED[k]
    comps.append(own_verdict(hd, rchk))
    val = _ours_for(hd, spec, ours, unc, status)
    if isinstance(val, str):
        rec.update(verdict="not reproduced", reason=val)
        return rec
    if isinstance(val, Undef):
        comps.append(comp("value", repr(val), rchk.get("value"), rchk.get("value") is None, "null (undefined)"))
        comps.append(comp("verdict", False, bool(rchk.get("passed")), not rchk.get("passed"),
                          "failed (a check on an undefined metric fails)"))
    else:
        v, band = val
        comps.append(cmp_abs("value", v, rchk.get("value"), 1e-6, band + 1e-300, "our band"))
        comps.append(verdict_comp(hd, abs(v) if hd.get("abs") else v, band, rchk.get("passed")))
    rec["verdict"] = worst_status(comps)
    return rec


def checks_records(case: Dict[str, Any], spec: Dict[str, Any], ours: Ours, unc: Ours,
                   status: Dict[Any, str]) -> List[Dict[str, Any]]:
    """Every check the case file implies, matched to the report's by (name, method, dt); one the
    report lacks (unless it lists it in checks_not_run for a method not selected) or has in
    excess is a disagreement."""
    cid = case["id"]
    want = xcase.expected_checks(spec) if not spec.get("_from_report") else {}
    have = {xcase.check_key(c): c for c in case.get("checks") or []}
    not_run = {xcase.check_key(c): c for c in case.get("checks_not_run") or []}
    selected = set(case.get("methods") or [])
    out = []
    for key, hd in want.items():
        if key in have:
            out.append(check_record(cid, hd, have[key], spec, ours, unc, status))
            continue
        legit = not set(hd["members"]) <= selected
        if key in not_run and not legit:
            why = "listed as not run (%s) but its methods were selected" % not_run[key].get("reason")
        elif legit and (key in not_run or "checks_not_run" not in case):
            continue
        else:
            why = "implied by the case file, absent from the report"
        out.append(dict(case=cid, method=hd["method"], check=hd["name"], metric=hd["metric"], verdict="disagree",
                        comparisons=[comp("present", "yes", "missing", False, why)], notes=[]))
    if spec.get("_from_report"):
        for key, c in have.items():
            hd = dict(c, members=list(c.get("methods") or [c.get("method")]))
            out.append(check_record(cid, hd, c, spec, ours, unc, status))
            out[-1]["notes"].append("no case file: threshold from the report")
        return out
    for key in sorted(set(have) - set(want), key=str):
        c = have[key]
        out.append(dict(case=cid, method=c.get("method"), check=c.get("name"), metric=c.get("metric"),
                        verdict="disagree", notes=[],
                        comparisons=[comp("present", "no", "yes", False, "not implied by the case file")]))
    return out


def _in_range(v: Any, rng: Any) -> Any:
    """rng = [ours, lo, hi] of a first-failure step (None = no failure = beyond the grid)."""
    big = math.inf
    val = big if v is None else float(v)
    lo, hi = (big if x is None else x for x in (rng[1], rng[2]))
    return min(lo, hi) * (1 - 1e-12) <= val <= max(lo, hi) * (1 + 1e-12) or val == rng[0]


def compare_sweep(ours: Any, theirs: Any, comps: Any, mine: Any, unc: Any) -> None:
    """Sweep metrics (verify/xsweep.py): counts agree within the number of round-off ties, first
    failure steps within the range ties allow, F's formula boundary exactly, the half-trace
    error rel 1e-9 + 1e-13 (M's entries carry a few eps of rounding), the grid exactly."""
    for k, v in theirs.items():
        if isinstance(v, str):
            continue
        if k in ("grid",):
            comps.append(comp("stability-sweep.grid", ours["grid"], v, ours["grid"] == v, "equal"))
        elif k == "omega":
            continue                       # an input (the case's stability_sweep.omega)
        elif k in ("rows", "first_row"):
            rows_t = v if k == "rows" else [v]
            rows_o = ours["rows"] if k == "rows" else [ours["first_row"]]
            ok, worst = len(rows_t) == len(rows_o), ""
            for ro, rt in zip(rows_o, rows_t):
                if abs(ro["gamma"] - num(rt.get("gamma"))) > 1e-12 * max(1.0, abs(ro["gamma"])):
                    ok, worst = False, "gamma %s" % rt.get("gamma")
                for kk in ("h_F_empirical", "h_power_unbounded", "h_F_formula"):
                    if kk in rt and kk in ro and not _in_range(rt[kk], ro[kk]):
                        ok, worst = False, "%s at gamma %g: ours %s, theirs %s" % (kk, ro["gamma"], ro[kk][0], rt[kk])
                if "max_half_trace_err" in rt and rt["max_half_trace_err"] is not None:
                    a, b = ro["max_half_trace_err"], num(rt["max_half_trace_err"])
                    if not abs(a - b) <= 1e-9 * abs(b) + 1e-13:
                        ok, worst = False, "max_half_trace_err at gamma %g: %r vs %r" % (ro["gamma"], a, b)
            comps.append(comp("stability-sweep.%s" % k, "%d rows" % len(rows_o), "%d rows" % len(rows_t), ok,
                              "first failures within the ties' range, h_F_formula equal, max_half_trace_err "
                              "rel 1e-9 + 1e-13", note=worst))
            if k == "first_row":
                for kk in ("h_F_empirical", "h_power_unbounded"):
                    rng = ours["first_row"][kk]
                    if rng[0] is not None:
                        mine["stability-sweep.first_row." + kk] = rng[0]
                        unc["stability-sweep.first_row." + kk] = max(
                            abs((x if x is not None else rng[0]) - rng[0]) for x in rng)
                mine["stability-sweep.first_row.gamma"] = ours["first_row"]["gamma"]
        elif k in ours:
            o, ties = ours[k]
            t_ = num(v)
            comps.append(comp("stability-sweep." + k, o, v, abs(o - t_) <= ties,
                              "equal within %d round-off tie points" % ties))
            mine["stability-sweep." + k] = o
            unc["stability-sweep." + k] = ties
        else:
            comps.append(comp("stability-sweep." + k, "not computed", v, False, "metric unknown to us"))


def compare_trace_taylor(method: str, prob: Any, spec: Dict[str, Any], theirs: Any, comps: Any, mine: Any, unc: Any) -> None:
    """h^4 coefficient (verify/xsweep.trace_taylor, at h = the case's first step size): ours is
    extrapolated to ~1e-6; the report's estimate may carry the truncation of any estimator at
    step sizes <= h, which the band bounds.  Expected: docs/conventions.md §5's magnitudes."""
    w, g = prob.w, prob.g
    h = xcase.step_sizes(spec)[0]
    c, band = xsweep.trace_taylor(method, w, g, h)
    exp_ = {"cimp": (w * w - g * g) ** 2 / 12, "csv1": w * w * (w * w + 4 * g * g) / 24,
            "csv2": (2 * w ** 4 + 5 * g * g * w * w - 4 * g ** 4) / 48}.get(method)
    vals = {"h4_coeff": (c, band)}
    if exp_ is not None:
        exp_ = abs(exp_)
        vals["h4_coeff_expected"] = (exp_, 1e-12 * exp_)
        vals["h4_coeff_abs_err"] = (abs(c - exp_), band)
        vals["h4_coeff_rel_err"] = ((abs(c - exp_) / exp_, band / exp_) if exp_ > 0
                                    else (Undef("expected coefficient 0"), 0.0))
    for k, v in theirs.items():
        if isinstance(v, str) or k == "undefined":
            continue
        key = "trace-taylor." + k
        if k not in vals:
            comps.append(comp(key, "not computed", v, False, "metric unknown to us"))
            continue
        o, b = vals[k]
        mine[key], unc[key] = o, b
        if v is None or isinstance(o, Undef):
            comps.append(comp(key, repr(o), v, (v is None) == isinstance(o, Undef), "both undefined, or both defined"))
            continue
        comps.append(comp(key, o, v, abs(o - num(v)) <= b, "abs %.3g: truncation of a step-size-h estimate "
                          "plus round-off" % b if k != "h4_coeff_expected" else "rel 1e-12"))


# ---------------------------------------------------------------------------------------
