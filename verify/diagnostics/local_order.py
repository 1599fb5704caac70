"""local-order: the order of the one-step error (local-error) over the case's step-size ladder."""
from __future__ import annotations

import numpy as np

from . import Diagnostic, MethodCtx, Rec, register
from .order import Errors, fit_record


def method_record(mc: MethodCtx) -> Rec:
    """Our one-step errors of this method, their floors; the scale |z0|."""
    errs: Errors = {cx.dt: (cx.mm["local-error.abs"], 0.0, cx.priv["local-error.floor"])
                    for cx in mc.ctxs if cx.method == mc.method and "local-error.abs" in cx.mm}
    return fit_record(mc, "local-order", errs, float(np.linalg.norm(mc.prob.z0)))


register(Diagnostic("local-order", implies=("local-error",), per_run=False, method=method_record, rank=1))
