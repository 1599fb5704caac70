"""The cross-check's diagnostics, one module each (verify/diagnostics/<name>.py, the name as the
case files and dampsym spell it, '-' as '_'), mirroring dampsym's diagnostic registry.

Each module calls `register(Diagnostic(...))` once: its name, what it needs of our run and its
recomputation (the hooks below).  The run-level core (verify/xours.py) and the case-level core
(verify/crosscheck.py) only iterate over the registry; they name no diagnostic.  Every module of
this package is imported here, so adding a diagnostic is adding its module (the test
verify/tests/test_registry.py fails while a diagnostic that dampsym knows has none).
"""
from __future__ import annotations

import importlib
import pkgutil
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, List, Optional, Tuple

import numpy as np

from ..xrunctx import RunCtx

Rec = Dict[str, Any]


@dataclass
class MethodCtx:
    """One method of a case for a method-level diagnostic: the report's record of it (`theirs`,
    under method_metrics.<method>.<name>), our runs of the case, and where our values and bands
    of its method-level metrics go (read by the checks)."""
    case: Rec
    spec: Rec
    prob: Any
    method: str
    theirs: Any
    ctxs: List[RunCtx]
    mine: Rec
    unc: Rec


@dataclass(frozen=True)
class Diagnostic:
    """One diagnostic's recomputation.

    implies        diagnostics it switches on (order: error)
    per_run        the report carries `metrics.<name>` on every run of a case that asks for it
    trajectory     needs our trajectory recorded (its run hook runs only when there is one)
    newton_counts  needs the Newton-family range of an implicit method's counts
    final_state    its run hook also works from our final state alone (a run whose trajectory
                   was not kept: the oscillator's linear path)
    keeps_failed   its metrics do not depend on the run finishing (a matrix of the method alone)
    run            per-run metrics into cx.mm / cx.unc / cx.priv, after the final state is judged
    grid           metrics sampled on the output grid of a trajectory (ours, ensemble=False, or
                   a member of our ensemble of a chaotic run, ensemble=True: only those a band is
                   taken of)
    member         after the bands of one ensemble member's grid metrics `alt` are taken
    chaotic_reference  True when the case's reference itself is chaotic for this run
    method         the method-level record (a fit, a sweep) from our runs of the case
    rank           position of its method-level record among a method's records
    """
    name: str
    implies: Tuple[str, ...] = ()
    per_run: bool = True
    trajectory: bool = False
    newton_counts: bool = False
    final_state: bool = False
    keeps_failed: bool = False
    run: Optional[Callable[[RunCtx], None]] = None
    grid: Optional[Callable[[RunCtx, np.ndarray, bool], Rec]] = None
    member: Optional[Callable[[RunCtx, Rec], None]] = None
    chaotic_reference: Optional[Callable[[RunCtx], bool]] = None
    method: Optional[Callable[[MethodCtx], Rec]] = None
    rank: int = 0
    module: str = field(default="", compare=False)


REGISTRY: Dict[str, Diagnostic] = {}


def register(d: Diagnostic) -> Diagnostic:
    """Adds a diagnostic (once per name)."""
    if d.name in REGISTRY:
        raise ValueError("diagnostic %s registered twice" % d.name)
    REGISTRY[d.name] = d
    return d


def enabled(diags: List[str]) -> List[Diagnostic]:
    """The registered diagnostics among `diags`, in name order (their hooks are independent)."""
    return [REGISTRY[n] for n in sorted(set(diags)) if n in REGISTRY]


def with_implied(diags: List[str]) -> List[str]:
    """`diags` with the diagnostics they imply appended (by the implying one's rank, once each)."""
    out = list(diags)
    for d in sorted(REGISTRY.values(), key=lambda d: (d.rank, d.name)):
        if d.name in diags:
            out += [m for m in d.implies if m not in out]
    return out


def method_level() -> List[Diagnostic]:
    """The diagnostics with a method-level record, in the order of the records."""
    return sorted((d for d in REGISTRY.values() if d.method is not None), key=lambda d: (d.rank, d.name))


def _load_all() -> None:
    for info in sorted(pkgutil.iter_modules(__path__), key=lambda i: i.name):
        importlib.import_module("%s.%s" % (__name__, info.name))


_load_all()
