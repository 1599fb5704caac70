"""Methods defined in Python (docs/python.md "Your method"): a tableau, read and checked as a
method file (docs/method-files.md), and a step given as a callable, run as a C plugin's method
(docs/plugins.md) through the same runner and diagnostics. Both are registered for the life of the
process under their id; defining the same tableau again (a re-run notebook cell) reuses it."""

from __future__ import annotations

import inspect
import json
from collections.abc import Callable, Iterable, Sequence
from typing import Any, Union

import numpy as np

from . import _dampsym

Coefficient = Union[float, int, str]
Matrix = Union[Sequence[Sequence[Coefficient]], np.ndarray]
Vector = Union[Sequence[Coefficient], np.ndarray]

_loaded: dict[str, str] = {}  # id -> the method file text it was loaded from


def _data(x: Matrix | Vector) -> Any:
    """numpy arrays as lists; strings (exact expressions such as "1/6") kept."""
    if isinstance(x, np.ndarray):
        return x.tolist()
    return [_data(v) if isinstance(v, (list, tuple, np.ndarray)) else v for v in x]


def load_method(definition: dict[str, Any], source: str | None = None) -> str:
    """Loads a method file's content (any family of docs/method-files.md) with every check of a
    file; returns its id. The same definition again is not an error (it is loaded once)."""
    text = json.dumps(definition)
    mid = str(definition.get("id", ""))
    if _loaded.get(mid) == text:
        return mid
    loaded = str(_dampsym.load_method(text, source or f"method {mid!r} from Python"))
    _loaded[loaded] = text
    return loaded


class Tableau:
    """A Runge-Kutta tableau (A, b, c) as a method file's ``rk`` family: the same keys, checks
    (square A, row sums, declared order by rooted trees, claims) and messages.

    Coefficients are numbers or exact strings such as ``"1/2 - sqrt(3)/6"``."""

    def __init__(self, A: Matrix, b: Vector, c: Vector, *, id: str, order: int,
                 claims: Iterable[str] = (), integrating_factor: bool = False,
                 explicit: bool | None = None, citation: str | None = None) -> None:
        definition: dict[str, Any] = {
            "id": id, "family": "rk", "order": order, "claims": list(claims),
            "tableau": {"A": _data(A), "b": _data(b), "c": _data(c)},
        }
        if integrating_factor:
            definition["integrating_factor"] = True
        if explicit is not None:
            definition["explicit"] = explicit
        if citation is not None:
            definition["citation"] = citation
        self.definition = definition
        self.id = load_method(definition, f"Tableau(id={id!r})")

    def checks(self) -> list[dict[str, Any]]:
        """The coefficient-level checks (``dampsym methods --check``): name, what, expected,
        holds, agrees, value, tolerance."""
        return list(_dampsym.check_method(self.id))

    def __repr__(self) -> str:
        return f"Tableau(id={self.id!r})"


_FORMS = {"plain": _dampsym.FORM_PLAIN, "conformal": _dampsym.FORM_CONFORMAL,
          "separable": _dampsym.FORM_SEPARABLE}
_CLAIMS = {"conformal-symplectic": _dampsym.CLAIM_CONFORMAL_SYMPLECTIC,
           "symplectic": _dampsym.CLAIM_SYMPLECTIC,
           "symplectic-if-undamped": _dampsym.CLAIM_SYMPLECTIC,
           "negative-control": _dampsym.CLAIM_NEGATIVE_CONTROL}


def _positional_count(f: Callable[..., Any]) -> int:
    try:
        params = inspect.signature(f).parameters.values()
    except (TypeError, ValueError):
        return 4
    kinds = (inspect.Parameter.POSITIONAL_ONLY, inspect.Parameter.POSITIONAL_OR_KEYWORD)
    if any(p.kind == inspect.Parameter.VAR_POSITIONAL for p in params):
        return 4
    return sum(1 for p in params if p.kind in kinds)


def _with_problem(f: Callable[..., Any]) -> Callable[..., Any]:
    """f as f(t, z, h, problem): a callable of three arguments does not get the problem."""
    if _positional_count(f) >= 4:
        return f
    return lambda t, z, h, problem: f(t, z, h)


class Step:
    """A method given as its step, ``step(t, z, h, problem) -> z_next`` (or ``step(t, z, h)``),
    run like a C plugin's method (docs/plugins.md): the same checks at registration (a probe step
    on a 2-dimensional state), runner, diagnostics and statuses. ``problem`` offers the callbacks of
    the ``form``: ``dim``, ``gamma(t)``, ``damping_factor(t, tau)``, ``rhs(t, z)``; ``N(t, z)``
    (conformal); ``grad_T(p)``, ``force(t, q)`` (separable, z = (q, p)). ``jacobian(t, z, h,
    problem) -> (z_next, J)`` is optional: without it E_n uses central differences of the step, and
    the report says so. An exception in the callable ends that run with status ``error`` and its
    message."""

    def __init__(self, step: Callable[..., Any], *, id: str, order: int,
                 form: str = "separable", claims: Iterable[str] = (),
                 jacobian: Callable[..., Any] | None = None,
                 description: str | None = None) -> None:
        if form not in _FORMS:
            raise _dampsym.InputError(f"Step {id!r}: form: must be one of {', '.join(_FORMS)}, "
                                      f"got {form!r}")
        bits = 0
        for c in claims:
            if c not in _CLAIMS:
                raise _dampsym.InputError(f"Step {id!r}: claims: unknown claim {c!r} (known: "
                                          f"{', '.join(_CLAIMS)})")
            bits |= int(_CLAIMS[c])
        name = getattr(step, "__qualname__", type(step).__name__)
        self.id = id
        self.form = form
        _dampsym.register_step(id, _with_problem(step),
                               None if jacobian is None else _with_problem(jacobian),
                               order, int(_FORMS[form]), bits, description or "",
                               f"python callable {name}")

    def __repr__(self) -> str:
        return f"Step(id={self.id!r}, form={self.form!r})"
