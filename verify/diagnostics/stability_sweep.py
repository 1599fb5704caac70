"""stability-sweep: where a method's one-step matrix on the oscillator keeps the conformal
symplectic relation over a grid of (omega h, gamma h) (verify/xsweep.py)."""
from __future__ import annotations

from .. import xcaserec
from .. import xmethods as xm
from .. import xproblems as xp
from .. import xsweep
from . import Diagnostic, MethodCtx, Rec, register


def method_record(mc: MethodCtx) -> Rec:
    rec: Rec = dict(case=mc.case["id"], method=mc.method + " (stability-sweep)", comparisons=[], notes=[])
    if not isinstance(mc.prob, xp.Oscillator) or mc.method not in xm.METHODS:
        rec.update(verdict="not reproduced", reason="stability-sweep needs the oscillator and a known method")
        return rec
    if mc.method in xm.MULTIVALUE:
        rec.update(verdict="not reproduced", reason="%s is a multivalue method: the cross-check has no "
                   "one-step matrix of its multivalue state" % mc.method)
        return rec
    if not mc.spec.get("stability_sweep"):
        rec.update(verdict="not reproduced", reason="the case file has no `stability_sweep`")
        return rec
    xcaserec.compare_sweep(xsweep.sweep(mc.method, mc.spec["stability_sweep"]), mc.theirs, rec["comparisons"],
                           mc.mine, mc.unc)
    rec["verdict"] = "agree" if all(c["agree"] for c in rec["comparisons"]) else "disagree"
    return rec


register(Diagnostic("stability-sweep", per_run=False, method=method_record, rank=2))
