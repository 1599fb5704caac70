"""trace-taylor: the h^4 coefficient of a method's half trace on the oscillator against
e^{-gamma h} (docs/conventions.md §5; verify/xsweep.trace_taylor)."""
from __future__ import annotations

from .. import xcaserec
from .. import xmethods as xm
from .. import xproblems as xp
from . import Diagnostic, MethodCtx, Rec, register


def method_record(mc: MethodCtx) -> Rec:
    rec: Rec = dict(case=mc.case["id"], method=mc.method + " (trace-taylor)", comparisons=[], notes=[])
    if not isinstance(mc.prob, xp.Oscillator) or mc.method not in xm.METHODS:
        rec.update(verdict="not reproduced", reason="trace-taylor needs the oscillator and a known method")
        return rec
    if mc.method in xm.MULTIVALUE:
        rec.update(verdict="not reproduced", reason="%s is a multivalue method: the cross-check has no "
                   "one-step matrix of its multivalue state" % mc.method)
        return rec
    xcaserec.compare_trace_taylor(mc.method, mc.prob, mc.spec, mc.theirs, rec["comparisons"], mc.mine, mc.unc)
    rec["verdict"] = "agree" if all(c["agree"] for c in rec["comparisons"]) else "disagree"
    return rec


register(Diagnostic("trace-taylor", per_run=False, method=method_record, rank=3))
