"""The tolerance table of verify/crosscheck.py: one row per metric family, one compare function
per family (the reasons are in crosscheck.py's module docstring, row by row).  `FAMILIES` is
searched in order; the first row whose matcher accepts a metric key compares it.  A key no row
accepts and NOT_COMPARED does not list is reported as unknown (never skipped)."""
from __future__ import annotations

import math
import re
from typing import Any, Callable, Dict, List, Optional, Tuple

import numpy as np

from .xmetrics import EPS, TINY, Undef
from .xrunctx import RunCtx
from .xtol import Comp, cmp_abs, cmp_equal, cmp_list, comp, in_range, num

REL = 1e-6            # smooth functions of two trajectories that agree to <= 1e-10
RES_FLOOR = 64 * EPS  # a residual's round-off on its scale: a few sums of products, 64 eps
LIN_FLOOR = 256 * EPS  # the linear path's one-step matrix carries its own rounding
IMP_FLOOR = 256 * EPS  # implicit methods: Newton stops with its update at round-off, a few eps per
#                        stage and iteration (rb-fig37-eps cimp: 4.8e-14 ours, 3.6e-15 dampsym's)


def res_floor(cx: RunCtx) -> float:
    """The residual floor of this run's method and path."""
    from . import xmethods as xm
    return RES_FLOOR + (LIN_FLOOR if cx.mine.get("linear_path") else 0.0) + (
        IMP_FLOOR if cx.method in xm.IMPLICIT else 0.0)

# deliberately not compared, with the reason (pattern on the flat metric key)
NOT_COMPARED: List[Tuple[str, str]] = [
    (r"(^|\.)wall_seconds$", "a clock reading, not a property of the computation"),
    (r"^conformal-symplectic\.(norm|jacobian)$", "a description string of the measurement"),
    (r"^conformal-symplectic\.jacobian_check\w*$", "dampsym's step Jacobian against its own finite "
     "differences: a self-test of the C++ side (ours is the complex-step Jacobian, exact to eps)"),
    (r"(^|\.)(scale|formula_source|table_source|source|definition)$", "a provenance string"),
    (r"(^|\.)undefined\.", "the reason of an undefined metric (its definedness is compared)"),
    (r"^stability\.power_bounded_reason$", "a description string"),
    (r"^attractor\.probe$", "the probe's name (a description string)"),
    (r"^[\w-]+\.reason$", "free text: why a diagnostic does not apply (its absence of values is compared)"),
]


def not_compared(key: str) -> Optional[str]:
    for pat, why in NOT_COMPARED:
        if re.search(pat, key):
            return why
    return None


def _chaos(cx: RunCtx, key: str) -> float:
    return cx.band.get(key, 0.0)


def f_residual(cx: RunCtx, key: str, ours: Any, theirs: Any) -> Comp:
    """Per-step law residuals and E_n on their scales: rel 1e-6 above the residual floor
    64 eps (+ 256 eps on the linear path; + our ensemble band on a chaotic run)."""
    fl = res_floor(cx) + _chaos(cx, key)
    cx.unc[key] = REL * abs(num(ours)) + fl
    return cmp_abs(key, ours, theirs, REL, fl, "residual floor on our scale")


def f_abs_numerator(cx: RunCtx, key: str, ours: Any, theirs: Any) -> Comp:
    """|X_{n+1} - f X_n| unscaled: the residual floor times our largest scale of the run."""
    base = key.rsplit(".", 1)[0]
    sc = max([0.0] + [float(x) for x in (cx.mm.get(base + ".scale_initial"), cx.priv.get(base + "._scale_max"),
                                           cx.mm.get(base + ".scale_at_max_step_res"),
                                           cx.mm.get(base + ".scale_at_max_law_res"))
                      if isinstance(x, (int, float)) and math.isfinite(x)])
    fl = res_floor(cx) * sc + _chaos(cx, key)
    cx.unc[key] = REL * abs(num(ours)) + fl
    return cmp_abs(key, ours, theirs, REL, fl, "residual floor x our largest scale")


def f_global_res(cx: RunCtx, key: str, ours: Any, theirs: Any) -> Comp:
    """|I_n - e^{-2 Gamma} I_0| / S_n: one rounding eps S per step, floor 8 n eps."""
    fl = 8 * cx.nsteps * EPS + _chaos(cx, key)
    cx.unc[key] = REL * abs(num(ours)) + fl
    return cmp_abs(key, ours, theirs, REL, fl, "8 n eps accumulated round-off")


def f_global_slope(cx: RunCtx, key: str, ours: Any, theirs: Any) -> Comp:
    fl = 8 * cx.nsteps * EPS / max(cx.nsteps * cx.dt, TINY) + _chaos(cx, key)
    cx.unc[key] = REL * abs(num(ours)) + fl
    return cmp_abs(key, ours, theirs, REL, fl, "8 n eps over the run time")


def f_ratio_dev(cx: RunCtx, key: str, ours: Any, theirs: Any) -> Comp:
    """r_n carries u_n = eps S_n / |e^{-2 Gamma} I_0| per step: floor 8 n max u_n (u_n up to
    1e-2 |r_n| where r_n is resolved by that test: then not comparable, never a tight agree)."""
    u = cx.priv.get(key.rsplit(".", 1)[0] + "._ratio_u", 1e-8)
    fl = 8 * cx.nsteps * u
    if key.endswith("slope"):
        fl /= max(cx.nsteps * cx.dt, TINY)
    fl += _chaos(cx, key)
    cx.unc[key] = REL * abs(num(ours)) + fl
    return cmp_abs(key, ours, theirs, REL, fl, "8 n u_n")


def f_factor(cx: RunCtx, key: str, ours: Any, theirs: Any) -> Comp:
    """Measured momentum factor: round-off eps S_n / |X_n| per step (<= 1e-8 where defined)."""
    fu = 8 * cx.priv.get("momentum.%s._factor_u" % key.split(".")[1], 1e-8) + _chaos(cx, key)
    cx.unc[key] = REL * abs(num(ours)) + fu
    return cmp_abs(key, ours, theirs, REL, fu, "8 eps S_n/|X_n|")


def f_initial_norm(cx: RunCtx, key: str, ours: Any, theirs: Any) -> Comp:
    kk = key.split(".")[1]
    fl = 4 * cx.prob.n * EPS * float(cx.mm.get("momentum.%s.scale_initial" % kk, 0.0))
    return cmp_abs(key, ours, theirs, REL, fl, "N eps S(z0): a sum of N vectors")


def f_scale_initial(cx: RunCtx, key: str, ours: Any, theirs: Any) -> Comp:
    return cmp_abs(key, ours, theirs, 64 * EPS, 0.0, "a function of z0 alone")


def f_scale_at_max(cx: RunCtx, key: str, ours: Any, theirs: Any) -> Comp:
    """S(z_k) at the step k of the maximum residual: where our maximum stands above the residual
    floor, theirs is the scale at a step within rel 1e-6 of our maximum (near-ties); at round-off
    the argmax is noise, and theirs must be the scale of SOME step of the run (our range)."""
    base = key.rsplit(".", 1)[0]
    st_, S_ = cx.priv.get(base + "._step"), cx.priv.get(base + "._S")
    if st_ is None or S_ is None:
        return comp(key, ours, theirs, False, "our per-step residuals")
    mx = float(np.max(st_))
    t = num(theirs)
    if mx > 1e3 * RES_FLOOR:
        cand = S_[st_ >= mx * (1 - REL) - LIN_FLOOR]
        ok = bool(np.any(np.abs(cand - t) <= REL * np.abs(cand) + cx.state_bound))
        return comp(key, ours, theirs, ok, "scale at a step within rel 1e-6 of our max residual "
                    "(%d candidates), rel 1e-6" % len(cand))
    good = S_[st_ >= 0]
    lo, hi = float(good.min()) * (1 - REL), float(good.max()) * (1 + REL)
    return in_range(key, ours, theirs, lo, hi, "argmax of round-off: the scale of some step")


def f_max_rel_step(cx: RunCtx, key: str, ours: Any, theirs: Any) -> Comp:
    """The step of max E_n: where E_n stands above round-off, equal or a tie to 1e-9; below,
    any step of the run (the argmax of round-off), never outside 1..steps."""
    Er = cx.priv.get("conformal-symplectic._Er")
    if Er is None:
        return comp(key, ours, theirs, False, "our E_n")
    t = num(theirs)
    if float(np.max(Er)) > 1e-10:
        ok = ours == theirs or (t == int(t) and 1 <= t <= len(Er) and Er[int(t) - 1] >= Er.max() * (1 - 1e-9))
        return comp(key, ours, theirs, ok, "equal, or a tie to 1e-9")
    ok = math.isfinite(t) and t == int(t) and 1 <= t <= len(Er)
    return comp(key, ours, theirs, "not comparable" if ok else "disagree", "a step in [1, %d]" % len(Er),
                reason="argmax of E_n at round-off")


def f_dissipation(cx: RunCtx, key: str, ours: Any, theirs: Any) -> Comp:
    """d = ln q_max + Gamma: ln q known to our state tolerance, Gamma rounded to 8 eps |Gamma|;
    slopes divide that by the time span."""
    G_end = abs(cx.prob.Gamma(cx.t0 + cx.nsteps * cx.dt) - cx.prob.Gamma(cx.t0))
    dfl = cx.tol + 8 * EPS * (G_end + 1.0)
    if "slope" in key:
        dfl *= 2.0 / max(cx.nsteps * cx.dt, TINY)
    cx.unc[key] = dfl
    if isinstance(ours, list):
        return cmp_list(key, ours, theirs, REL, dfl, "state tolerance in ln q")
    return cmp_abs(key, ours, theirs, REL, dfl, "state tolerance in ln q")


def f_newton(cx: RunCtx, key: str, ours: Any, theirs: Any) -> Comp:
    o, lo, hi = cx.cost_range[key]
    return in_range(key, o, theirs, lo - 1e-9, hi + 1e-9,
                    "full to simplified Newton, tests 1e-8 to 1e-15 (verify/xnewton.py)")


def f_measure(cx: RunCtx, key: str, ours: Any, theirs: Any) -> Comp:
    fl = cx.measure_floor.get(key, 0.0) + _chaos(cx, key)
    cx.unc[key] = REL * abs(num(ours)) + fl
    return cmp_abs(key, ours, theirs, REL, fl, "propagated state and reference floor")


def f_energy_balance(cx: RunCtx, key: str, ours: Any, theirs: Any) -> Comp:
    fl = cx.eb_floor if key != "energy-balance.max_rel" else cx.eb_floor / max(cx.diss_max, TINY)
    cx.unc[key] = REL * abs(num(ours)) + fl
    return cmp_abs(key, ours, theirs, REL, fl, "difference-quotient round-off")


def f_growth_ratio(cx: RunCtx, key: str, ours: Any, theirs: Any) -> Comp:
    """max|dH| second half / first half: a ratio of two round-off maxima when the energy change
    is at round-off (then any positive number; not comparable), else rel 1e-6 + the ratio's
    share of each maximum's round-off (a 4th-order Lobatto pair on Kepler: maxima 1.1e-9 known
    to 2.5e-12 each, ratios 0.999989 and 0.999951)."""
    e0 = abs(float(cx.prob.energy(cx.prob.z0)))
    if cx.mm.get("energy.max_abs_change", 1.0) <= 8 * math.sqrt(max(cx.nsteps, 1)) * EPS * e0:
        t = num(theirs)
        return comp(key, ours, theirs, "not comparable" if t > 0 else "disagree", "> 0",
                    reason="ratio of two round-off maxima")
    # each half's maximum is known to the energy change's round-off u (energy.max_abs_change's
    # band); the ratio r = a2/a1 to r u (1/a1 + 1/a2), a1, a2 from r and max(a1, a2)
    r, big = abs(num(ours)), float(cx.mm.get("energy.max_abs_change", 0.0))
    a1, a2 = (big / r, big) if r >= 1.0 else (big, big * r)
    u = 8 * math.sqrt(max(cx.nsteps, 1)) * EPS * energy_scale(cx)
    fl = r * u * (1.0 / max(a1, TINY) + 1.0 / max(a2, TINY)) + _chaos(cx, key)
    cx.unc[key] = REL * r + fl
    return cmp_abs(key, ours, theirs, REL, fl, "each half's maximum to the change's round-off")


def energy_scale(cx: RunCtx) -> float:
    """S_H(z0): |H(z0)|, or the problem's energy scale when larger."""
    e0 = abs(float(cx.prob.energy(cx.prob.z0)))
    if cx.prob.energy_scale is not None:
        e0 = max(e0, float(cx.prob.energy_scale(cx.prob.z0)))
    return e0


def f_energy(cx: RunCtx, key: str, ours: Any, theirs: Any) -> Comp:
    """Energy changes: random-walk round-off 8 sqrt(n) eps S_H(z0) (per S_H for *_res; over
    the run time for slopes)."""
    e0 = energy_scale(cx)
    fl = 8 * math.sqrt(max(cx.nsteps, 1)) * EPS * e0
    why = "8 sqrt(n) eps S_H"
    # H(z_ref) - H(z_n): the reference's and the state's differences through grad H
    ref = float(cx.priv.get("energy.grad_max", 0.0)) * (cx.state_bound + float(cx.priv.get("error.est", 0.0))) \
        if key in REF_ENERGY else 0.0
    if ref:
        fl, why = fl + ref, why + " + |grad H| (state bound + our reference's estimate)"
    per = 1.0 / max(e0, TINY) if "_res" in key else 1.0
    if "slope" in key:
        per /= max(cx.nsteps * cx.dt, TINY)
    fl = fl * per + _chaos(cx, key)
    cx.unc[key] = REL * abs(num(ours)) + fl
    c = cmp_abs(key, ours, theirs, REL, fl, why)
    declared = num((cx.metrics.get("error") or {}).get("reference_error_estimate"))
    est = float(cx.priv.get("error.est", 0.0))
    if ref and c["status"] == "disagree" and math.isfinite(declared) and declared > est:
        wider = c["tol_abs"] + float(cx.priv.get("energy.grad_max", 0.0)) * min(declared, 1e3 * max(est, TINY)) * per
        if abs(num(ours) - num(theirs)) <= wider:
            c.update(status="not comparable", agree=False, tol_abs=wider,
                     reason="within the report's declared reference estimate %.3g (ours %.3g) through |grad H|"
                     % (declared, est))
    return c


# energy metrics against the reference (diagnostics/energy.py energy_error)
REF_ENERGY = ("energy.max_abs_error", "energy.final_abs_error", "energy.drift_slope", "energy.error_res_slope")


def f_local_error(cx: RunCtx, key: str, ours: Any, theirs: Any) -> Comp:
    fl = cx.priv.get("local-error.floor", 0.0)
    if key.endswith("rel"):
        fl /= max(cx.priv.get("local-error.norm", 0.0), TINY)
    cx.unc[key] = REL * abs(num(ours)) + fl
    return cmp_abs(key, ours, theirs, REL, fl, "8 eps |z(t0 + h)| + our exact solution's estimate")


def f_precession(cx: RunCtx, key: str, ours: Any, theirs: Any) -> Comp:
    fl = 8 * math.pi * max(cx.nsteps, 1) * EPS
    if key.endswith("rate"):
        fl /= max(cx.nsteps * cx.dt, TINY)
    fl += _chaos(cx, key)
    cx.unc[key] = REL * abs(num(ours)) + fl
    return cmp_abs(key, ours, theirs, REL, fl, "n rounded angle increments")


def f_poincare_chaotic(cx: RunCtx, key: str, ours: Any, theirs: Any) -> Comp:
    """Chaotic run: a pointwise distance after the transient is a draw from the attractor's pair
    distances (all pairs of our sections and our reference's); pointwise_max is the max of n
    draws; the Hausdorff distance within a factor 2 of our ensemble's."""
    P = cx.priv["poincare._pairs"]
    D = np.sort(P.ravel())
    if key.endswith("pointwise_final"):
        lo, hi, why = float(D[0]), float(D[-1]), "one draw of the attractor's pair distances"
    elif key.endswith("pointwise_max"):
        q = 1e-3 ** (1.0 / P.shape[0])
        lo, hi = float(D[min(len(D) - 1, int(q * len(D)))]), 1.01 * float(D[-1])
        why = "max of %d draws: [1e-3 quantile, 1.01 x largest pair]" % P.shape[0]
    else:
        ens = [float(ours), float(cx.priv.get("poincare._alt_hausdorff", ours))]
        lo, hi, why = 0.5 * min(ens), 2.0 * max(ens), "factor 2 around our ensemble"
    cx.unc[key] = max(hi - float(ours), float(ours) - lo)
    return in_range(key, ours, theirs, lo, hi, "chaotic run, statistical: " + why)


def f_stability(cx: RunCtx, key: str, ours: Any, theirs: Any) -> Comp:
    """The oscillator's one-step matrix: entries abs 1e-12 max|M|; det, half traces rel 1e-12;
    the errors |x - f| abs 8 eps max(1, |f|) + rel 1e-6 of ours; rho rel 1e-7 (eigenvalues of a
    near-defective M move like sqrt(eps)); F's condition equal unless a 4-eps tie."""
    if key == "stability.matrix":
        M = np.array(ours)
        return cmp_list(key, M.ravel().tolist(), [num(x) for r in theirs for x in r] if isinstance(theirs, list)
                        else theirs, 0.0, 1e-12 * float(np.abs(M).max()), "1e-12 max|M|")
    if key == "stability.eigenvalues":
        return f_eigenvalues(cx, key, ours, theirs)
    if key == "stability.spectral_radius":
        return cmp_abs(key, ours, theirs, 1e-7, 0.0, "near-defective M: sqrt(eps)")
    if key == "stability.F_condition":
        margin = abs(cx.mm["stability.half_trace"]) - math.exp(-cx.prob.g * cx.dt)
        tie = abs(margin) <= 4 * EPS * math.exp(-cx.prob.g * cx.dt)
        return comp(key, ours, theirs, ours == theirs or tie, "equal (a tie within 4 eps)", margin=margin)
    if key in ("stability.det_abs_err", "stability.det_rel_err"):
        return f_det_err(cx, key, ours, theirs)
    if key.endswith("_abs_err") or key.endswith("_rel_err") or key.endswith("exact_err"):
        ref_ = max(1.0, abs(float(cx.mm.get("stability.det_expected", 1.0))),
                   abs(float(cx.mm.get("stability.half_trace_formula", 1.0) or 1.0)))
        cx.unc[key] = REL * abs(num(ours)) + 8 * EPS * ref_
        return cmp_abs(key, ours, theirs, REL, 8 * EPS * ref_, "two O(1) numbers rounded a few times")
    if isinstance(ours, int) and not isinstance(ours, bool):
        return cmp_equal(key, ours, theirs)
    return cmp_abs(key, ours, theirs, 1e-12, 0.0, "a few roundings of a 2x2 product")


def f_det_err(cx: RunCtx, key: str, ours: Any, theirs: Any) -> Comp:
    """|det M - e^{-2 gamma h}| (over e^{-2 gamma h} for the relative form): det M = M00 M11 -
    M01 M10 rounds like its two products, 8 eps (|M00 M11| + |M01 M10|), which is much more than
    8 eps det where the products nearly cancel (gamma h > 2: det = e^{-4.3} of O(1) entries)."""
    M = np.array(cx.mm["stability.matrix"], float)
    prods = abs(M[0, 0] * M[1, 1]) + abs(M[0, 1] * M[1, 0])
    fl = 8 * EPS * max(1.0, prods)
    if key.endswith("rel_err"):
        fl = 8 * EPS * max(1.0, prods / max(float(cx.mm.get("stability.det_expected", 1.0)), TINY))
    cx.unc[key] = REL * abs(num(ours)) + fl
    return cmp_abs(key, ours, theirs, REL, fl, "det of two products, each rounded")


def f_eigenvalues(cx: RunCtx, key: str, ours: Any, theirs: Any) -> Comp:
    """Eigenvalues of M as a set: each of theirs within 1e-7 |lambda| + 1e-7 of one of ours
    (a near-defective pair moves like sqrt(eps))."""
    ev = np.linalg.eigvals(np.array(cx.mm["stability.matrix"]))
    try:
        th = [complex(num(x[0]), num(x[1])) if isinstance(x, list) else complex(num(x), 0.0) for x in theirs]
    except (TypeError, IndexError):
        return comp(key, ev.tolist(), theirs, False, "a list of (re, im)")
    ok = len(th) == len(ev) and all(np.min(np.abs(ev - t)) <= 1e-7 * abs(t) + 1e-7 for t in th)
    return comp(key, [[float(e.real), float(e.imag)] for e in ev], theirs, ok, "as a set, 1e-7")


def f_default(cx: RunCtx, key: str, ours: Any, theirs: Any) -> Comp:
    """Any other metric: a smooth function of the trajectory, rel 1e-6 (+ our ensemble band on a
    chaotic run); lists per entry; integers exactly."""
    if isinstance(ours, list):
        return cmp_list(key, ours, theirs, REL, 1e-300 + _chaos(cx, key))
    if isinstance(ours, (int, np.integer)) and not isinstance(ours, bool) and not _chaos(cx, key):
        return cmp_equal(key, int(ours), theirs, "equal (a count)")
    fl = _chaos(cx, key)
    cx.unc.setdefault(key, REL * abs(num(ours)) + fl)
    return cmp_abs(key, ours, theirs, REL, fl + 1e-300, "smooth in the trajectory")


def f_error(cx: RunCtx, key: str, ours: Any, theirs: Any) -> Comp:
    """error.*: our state bound plus OUR reference's estimate (never the report's); rel 1e-6
    besides when the error is >= 1000x that estimate (a property of the method). A difference
    beyond that band but within the report's own declared reference estimate (held to 3 decades
    of ours by f_ref_estimate) is "not comparable": the report's reference may be that far off
    by its own account, which decides nothing either way."""
    est = float(cx.priv.get("error.est", 0.0))
    sl = cx.state_bound + est
    per = 1.0  # the band per unit of absolute state difference (1 / |z_ref| for relative errors)
    if key.endswith("rel"):  # on |z_ref(t_n)| (diagnostics/error.py: max_rel's at its argmax)
        per = float(cx.priv.get(key + ".band", sl / TINY)) / max(sl, TINY)
        sl *= per
    big = abs(num(ours)) >= 1000 * max(est, TINY)
    c = cmp_abs(key, ours, theirs, REL if big else 0.0, sl, "state bound + our reference's estimate")
    declared = num((cx.metrics.get("error") or {}).get("reference_error_estimate"))
    if c["status"] == "disagree" and math.isfinite(declared) and declared > est:
        wider = c["tol_abs"] + min(declared, 1e3 * max(est, TINY)) * per
        if abs(num(ours) - num(theirs)) <= wider:
            c.update(status="not comparable", agree=False, tol_abs=wider,
                     reason="within the report's declared reference estimate %.3g (ours %.3g)"
                     % (declared, est))
    return c


def f_ref_estimate(cx: RunCtx, key: str, ours: Any, theirs: Any) -> Comp:
    """The report's reference estimate against ours: estimates of two integrators' errors (GSL
    rk8pd against DOP853), so within 3 decades of the larger of ours and 1e3 eps |z_ref|."""
    base = max(float(ours), 1e3 * EPS * float(cx.priv.get("error.ref_norm", 1.0)), 1e-300)
    cx.unc[key] = 1e3 * base
    return in_range(key, ours, theirs, 0.0, 1e3 * base, "another integrator's error estimate: "
                    "within 3 decades of ours")


Matcher = Callable[[RunCtx, str], bool]
Compare = Callable[[RunCtx, str, Any, Any], Comp]


def _ends(*s: str) -> Matcher:
    return lambda cx, k: k.endswith(s)


FAMILIES: List[Tuple[str, Matcher, Compare]] = [
    ("reference estimate", lambda cx, k: k == "error.reference_error_estimate", f_ref_estimate),
    ("errors", lambda cx, k: k.startswith("error."), f_error),
    ("Newton counts", lambda cx, k: k in cx.cost_range, f_newton),
    ("chaotic Poincare", lambda cx, k: cx.chaotic is not None and "poincare._pairs" in cx.priv and k in (
        "poincare.pointwise_final", "poincare.pointwise_max", "poincare.set_hausdorff"), f_poincare_chaotic),
    ("dissipation drift", lambda cx, k: k.startswith("dissipation-drift.") and k.split(".")[-1] in (
        "first", "last", "slope", "range", "slope_minus_reference", "max_abs_diff_reference"), f_dissipation),
    ("measures", lambda cx, k: k.startswith("measure."), f_measure),
    ("energy balance", lambda cx, k: k.startswith("energy-balance.") and k != "energy-balance.points",
     f_energy_balance),
    ("momentum factor", lambda cx, k: k.startswith("momentum.") and k.endswith(("factor_dev", "first_factor")),
     f_factor),
    ("momentum initial norm", lambda cx, k: k.startswith("momentum.") and k.endswith("initial_norm"), f_initial_norm),
    ("residual numerators", _ends("max_step_abs", "max_law_abs"), f_abs_numerator),
    ("scale at the maximum", _ends("scale_at_max_step_res", "scale_at_max_law_res"), f_scale_at_max),
    ("initial scales", _ends("scale_initial"), f_scale_initial),
    ("growth ratio", _ends("growth_ratio"), f_growth_ratio),
    ("local error", lambda cx, k: k in ("local-error.abs", "local-error.rel"), f_local_error),
    ("precession", lambda cx, k: k.startswith("precession.") and k.endswith(("total", "rate")), f_precession),
    ("argmax of E_n", lambda cx, k: k == "conformal-symplectic.max_rel_step", f_max_rel_step),
    ("global residual slope", lambda cx, k: k.startswith("invariants.") and k.endswith("global_res_slope"),
     f_global_slope),
    ("global residual", _ends("max_global_res"), f_global_res),
    ("ratio deviation", lambda cx, k: k.startswith("invariants.") and k.endswith(
        ("max_global_ratio_dev", "ratio_dev_slope")), f_ratio_dev),
    ("stability", lambda cx, k: k.startswith("stability."), f_stability),
    ("residuals", lambda cx, k: any(s in k for s in ("step_res", "law_res", "table_res", "conformal-symplectic.max_",
                                                       "conformal-symplectic.last_")), f_residual),
    ("energy", lambda cx, k: k.startswith("energy."), f_energy),
    ("other metrics", lambda cx, k: True, f_default),
]


def family_of(cx: RunCtx, key: str) -> Tuple[str, Compare]:
    for name, match, fn in FAMILIES:
        if match(cx, key):
            return name, fn
    return "other metrics", f_default


def undef_comp(key: str, ours: Any, theirs: Any, why: Any) -> Comp:
    """A metric null in the report (undefined there, reason `why`) or undefined here: both must
    be undefined by the docs' rule."""
    return comp(key, repr(ours) if isinstance(ours, Undef) else ours,
                "undefined (%s)" % why if theirs is None else theirs,
                isinstance(ours, Undef) == (theirs is None), "both undefined, or both defined")


def compare_metric(cx: RunCtx, key: str, theirs: Any, why_undef: Any) -> Optional[Comp]:
    """Compare one flat metric of the report with ours, or None when it is not recomputed."""
    ours = cx.mm.get(key)
    if key not in cx.mm:
        return None
    if theirs is None or isinstance(ours, Undef):
        return undef_comp(key, ours, theirs, why_undef)
    name, fn = family_of(cx, key)
    c = fn(cx, key, ours, theirs)
    c["family"] = name
    return c


def tally(comps: List[Comp]) -> Dict[str, int]:
    out: Dict[str, int] = {"agree": 0, "disagree": 0, "not comparable": 0}
    for c in comps:
        out[c["status"]] += 1
    return out
