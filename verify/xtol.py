"""Comparison primitives of verify/crosscheck.py: one comparison record, three outcomes.

A comparison is `agree` when |ours - theirs| is inside its tolerance, `disagree` when outside,
and `not comparable` when inside but the tolerance is not small against the value (>= 0.1 x
max(|ours|, |theirs|)): two correct programs cannot be told apart from a wrong one there (a
chaotic run past its Lyapunov time, the argmax of round-off, two residuals at round-off), so
such a comparison is counted apart from the agreements, with its reason, and never as one.
Every tolerance is computed by the cross-check from its own runs and the case file; none is
read from the report.
"""
from __future__ import annotations

import math
from typing import Any, Dict, List, Optional

LOOSE = 0.1          # tolerance >= LOOSE x value: not comparable
Comp = Dict[str, Any]


def num(x: Any) -> float:
    """A report number (null is NaN)."""
    if x is None or isinstance(x, (str, list, dict)):
        return math.nan
    return float(x)


def outcome(ok: bool, tol_abs: float, ours: float, theirs: float) -> str:
    """agree / disagree / not comparable (module docstring)."""
    if not ok:
        return "disagree"
    mag = max(abs(ours), abs(theirs)) if math.isfinite(ours) and math.isfinite(theirs) else 0.0
    if tol_abs > 0.0 and tol_abs >= LOOSE * mag:
        return "not comparable"
    return "agree"


def comp(name: str, ours: Any, theirs: Any, status: Any, tol: str, **kw: Any) -> Comp:
    """One comparison record; `status` is an outcome or a bool (True = agree)."""
    if isinstance(status, bool) or not isinstance(status, str):
        status = "agree" if status else "disagree"
    d: Comp = dict(quantity=name, ours=ours, theirs=theirs, tolerance=tol,
                   agree=status == "agree", status=status)
    d.update(kw)
    return d


def cmp_abs(name: str, ours: Any, theirs: Any, rel: float, floor: float, why: str = "",
            exact_zero: bool = False) -> Comp:
    """|ours - theirs| <= rel |ours| + floor (ours: the tolerance never depends on the
    report's number).  Both undefined (NaN / null) agree; one undefined disagrees."""
    o, t = num(ours), num(theirs)
    if math.isnan(o) and math.isnan(t):
        return comp(name, o, t, True, "both undefined")
    tol = rel * abs(o) + floor if math.isfinite(o) else 0.0
    diff = abs(o - t) if not (math.isinf(o) and o == t) else 0.0
    ok = diff <= tol or (o == t)
    label = "rel %.3g + %.3g%s" % (rel, floor, " (" + why + ")" if why else "")
    st = outcome(ok, tol, o, t)
    kw: Dict[str, Any] = dict(rel_diff=diff / abs(t) if t else diff, tol_abs=tol)
    if st == "not comparable":
        kw["reason"] = why or "tolerance %.3g not small against the value" % tol
    return comp(name, o, t, st, label, **kw)


def cmp_list(name: str, ours: List[Any], theirs: Any, rel: float, floor: float,
             why: str = "") -> Comp:
    """Entry by entry, as cmp_abs; lengths must match."""
    if not isinstance(theirs, list) or len(theirs) != len(ours):
        return comp(name, ours, theirs, False, "same length")
    worst: Optional[Comp] = None
    for a, b in zip(ours, theirs):
        c = cmp_abs(name, a, b, rel, floor, why)
        if worst is None or _rank(c) > _rank(worst):
            worst = c
    st = worst["status"] if worst else "agree"
    return comp(name, ours, theirs, st, "per entry: rel %.3g + %.3g%s" % (rel, floor, " (" + why + ")" if why else ""))


def _rank(c: Comp) -> int:
    return {"agree": 0, "not comparable": 1, "disagree": 2}[c["status"]]


def cmp_equal(name: str, ours: Any, theirs: Any, why: str = "equal") -> Comp:
    """Exact equality (counts, flags, integers; numbers as doubles)."""
    if isinstance(ours, (int, float)) and isinstance(theirs, (int, float)) \
            and not isinstance(ours, bool) and not isinstance(theirs, bool):
        ok = float(ours) == float(theirs)
    else:
        ok = ours == theirs
    return comp(name, ours, theirs, ok, why)


def in_range(name: str, ours: Any, theirs: Any, lo: float, hi: float, why: str) -> Comp:
    """theirs inside [lo, hi] (our range for a quantity decided by round-off or by sampling);
    not comparable when the range is wide against the value."""
    t = num(theirs)
    ok = lo <= t <= hi
    o = num(ours)
    st = outcome(ok, 0.5 * (hi - lo), o if math.isfinite(o) else t, t)
    kw: Dict[str, Any] = {}
    if st == "not comparable":
        kw["reason"] = why
    return comp(name, ours, theirs, st, "in [%.6g, %.6g] (%s)" % (lo, hi, why), **kw)


def worst_status(comps: List[Comp]) -> str:
    """disagree if any disagrees, else agree (a record with some not-comparable comparisons
    still agrees on the rest; they are counted apart)."""
    return "disagree" if any(c["status"] == "disagree" for c in comps) else "agree"
