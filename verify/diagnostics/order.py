"""order: the convergence order fitted to OUR global errors over the case's step-size ladder
(docs/conventions.md §5); its record compares the report's fit with ours."""
from __future__ import annotations

from typing import Dict, Tuple

from .. import xcase
from .. import xcaserec
from .. import xmetrics as xmt
from . import Diagnostic, MethodCtx, Rec, register

Errors = Dict[float, Tuple[float, float, float]]


def fit_record(mc: MethodCtx, kind: str, errs: Errors, ref_norm: float) -> Rec:
    """The fit's record; our slope and R^2 (and their bands: how far our errors' bands can move
    the fit) go where the checks read them."""
    ran = any(cx.method == mc.method for cx in mc.ctxs)
    rec = xcaserec.order_fit(mc.case["id"], mc.method, mc.theirs, errs, xcase.step_sizes(mc.spec), ref_norm, kind,
                             ran)
    xcaserec.order_known(rec, mc.theirs, kind)
    fit = rec.pop("fit", None) or {}
    mc.mine[kind + ".slope"] = fit.get("slope") if fit.get("ok") else xmt.Undef("no fit")
    mc.mine[kind + ".r2"] = fit.get("r2") if fit.get("ok") else xmt.Undef("no fit")
    # the window's size from OUR window rule (refmath.fit_order), exact: a check on it sees a window
    # rule of the C++ fit that differs from the documented one (docs/conventions.md §5)
    mc.mine[kind + ".points"] = len(fit.get("window_dt") or []) if fit.get("ok") else xmt.Undef("no fit")
    mc.unc.update({kind + ".slope": fit.get("band_slope", 1e-4), kind + ".r2": fit.get("band_r2", 1e-5),
                   kind + ".points": 0.0})
    return rec


def method_record(mc: MethodCtx) -> Rec:
    """Our errors per step size of this method (error.final_abs, our reference's estimate, our
    band); the reference's norm of the case's last run with an error."""
    errs: Errors = {}
    ref_norm = 1.0
    for cx in mc.ctxs:
        if "error.final_abs" in cx.mm and not isinstance(cx.mm["error.final_abs"], xmt.Undef):
            if cx.method == mc.method:
                errs[cx.dt] = (cx.mm["error.final_abs"], cx.priv["error.est"], cx.state_bound + cx.priv["error.est"])
            ref_norm = cx.priv["error.ref_norm"]
    return fit_record(mc, "order", errs, ref_norm)


register(Diagnostic("order", implies=("error",), per_run=False, method=method_record, rank=0))
