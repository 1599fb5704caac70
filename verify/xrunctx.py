"""One run of a case as the cross-check sees it (RunCtx): the inputs from the case file, our
integration, our metrics with their bands, and the report's run record (only to be compared).
Shared by the run-level core (verify/xours.py) and the diagnostics (verify/diagnostics/)."""
from __future__ import annotations

from typing import Any, Dict, List, Optional

import numpy as np

from . import xmethods as xm

TOL_STATE = {"explicit": 1e-12, "implicit": 1e-10}
FLOOR_K = 16.0
CHAOS_D = 1e-8      # our ensemble's relative spread above which a run's metrics are statistical
EPS = float(np.finfo(float).eps)


def two_level_tol(nsteps: int, dt: float) -> float:
    """Relative final-state tolerance of a scheme on two levels (kg-box, B (5.5)): it forms
    u^{i+2} from the second difference of the levels, so the rounding of each level (a few eps) is
    a velocity kick eps/dt that the recurrence (undamped in y = e^{gamma t} u) carries to the end:
    n kicks, each growing linearly over at most n steps, n^2 eps in u; v, a difference quotient of
    the levels, carries their sum n eps/dt (on the scale of u, time in the problem's units).
    Measured on pde-kg-box-orders at n = 400: the two programs' u 2.5e-12 and v 3.2e-11 apart (they
    round differently at every step: FFT here, a cyclic Thomas solve there), our ensemble's single
    kick at t0 only D = 8.1e-13; 8 eps n max(n, 1/dt) = 2.8e-10."""
    return 8.0 * EPS * nsteps * max(float(nsteps), 1.0 / dt)


class RunCtx:
    """Everything known about one run (method, dt) of a case: the inputs from the case file,
    our integration and metrics, and the report's run record (only to be compared)."""

    def __init__(self, case: Dict[str, Any], spec: Dict[str, Any], prob: Any, run: Dict[str, Any],
                 method: str, dt: float, nsteps: int, stride: int, diags: List[str]) -> None:
        self.case, self.spec, self.prob, self.run = case, spec, prob, run
        self.method, self.dt, self.nsteps, self.stride, self.diags = method, dt, nsteps, stride, diags
        self.t0 = float(spec.get("t0", 0.0))
        self.t_end = float(spec["t_end"])
        self.metrics: Dict[str, Any] = run.get("metrics") or {}
        self.mm: Dict[str, Any] = {}        # our metrics, flat
        self.priv: Dict[str, Any] = {}      # our private quantities (never compared)
        self.unc: Dict[str, float] = {}     # our band of a metric (verdict ties)
        self.band: Dict[str, float] = {}    # chaotic run: our ensemble band per metric
        self.cost_range: Dict[str, Any] = {}
        self.comps: List[Dict[str, Any]] = []
        self.notes: List[str] = []
        self.not_compared: Dict[str, str] = {}
        self.mine: Dict[str, Any] = {}
        self.chaotic: Optional[Dict[str, Any]] = None
        self.D = 0.0                        # our ensemble's relative final-state spread
        self.tol = TOL_STATE["implicit" if method in xm.IMPLICIT else "explicit"]
        if method in xm.TWO_LEVEL:
            self.tol = max(self.tol, two_level_tol(nsteps, dt))
        self.scale = 1.0
        self.state_bound = 0.0
        self.measure_floor: Dict[str, float] = {}
        self.eb_floor = 0.0
        self.diss_max = 0.0

    @property
    def traj(self) -> Any:
        return self.mine.get("traj")

    def wants(self, diag: str) -> bool:
        return diag in self.diags

    def grid_idx(self) -> np.ndarray:
        """Step indices of the output grid t0, t0 + stride dt, ..., t_end."""
        return np.arange(0, self.nsteps + 1, self.stride)


def put(cx: RunCtx, prefix: str, vals: Dict[str, Any]) -> None:
    """Our metrics under `prefix`; a name whose last part starts with '_' is private (kept for
    other computations, never compared)."""
    for k, v in vals.items():
        (cx.priv if k.split(".")[-1].startswith("_") else cx.mm)[prefix + k] = v
