"""dampsym from Python (docs/python.md).

The same C++ runner, diagnostics, checks and messages as the ``dampsym`` command line, in process::

    import dampsym
    report = dampsym.run("osc-orders")                  # a case id, a case file or a dict
    report["summary"]["checks_failed"]                  # report.json's content
    mine = dampsym.Tableau(A, b, c, id="my-rk", order=2)  # a method file's data and checks
    dampsym.matrix(methods=[mine, "csv1"])              # the method x property matrix

Errors are exceptions carrying the command line's message: :class:`InputError` (a ValueError:
bad input, the CLI's exit status 2) and :class:`OutputError` (an OSError, exit status 3). The GIL is
released while the C++ code runs; a Python step takes it again for each call.
"""

from __future__ import annotations

import builtins
import json
import os
from collections.abc import Iterable, Sequence
from typing import Any, Union

import numpy as np

from . import _dampsym
from ._dampsym import InputError, OutputError
from ._methods import Step, Tableau, load_method

__all__ = [
    "CompletedCommand",
    "InputError",
    "OutputError",
    "Report",
    "Step",
    "Tableau",
    "cli",
    "list",
    "load_method",
    "matrix",
    "run",
    "version",
]

PathLike = Union[str, "os.PathLike[str]"]
CaseLike = Union[PathLike, dict]
MethodLike = Union[PathLike, Tableau, Step]


class Report(dict):  # type: ignore[type-arg]
    """report.json (or matrix.json) as a dict; ``text`` is the JSON text the C++ code wrote,
    byte for byte the command line's (before ``"provenance"``), ``exit_status`` the CLI's."""

    text: str = ""
    exit_status: int = 0


class CompletedCommand:
    """What :func:`cli` returns: the command line's exit status and its output."""

    def __init__(self, returncode: int, stdout: str, stderr: str) -> None:
        self.returncode = returncode
        self.stdout = stdout
        self.stderr = stderr

    def __repr__(self) -> str:
        return f"CompletedCommand(returncode={self.returncode})"


def version() -> str:
    """``dampsym --version``: the version and the git commit the library was built from."""
    return str(_dampsym.version())


def cli(args: Sequence[str]) -> CompletedCommand:
    """Runs the command line in this process (``dampsym ARGS...``), its output captured."""
    status, out, err = _dampsym.cli(builtins.list(args))
    return CompletedCommand(int(status), str(out), str(err))


def _options(jobs: int, method_files: Sequence[str], plugins: Iterable[PathLike],
             cases_dir: PathLike | None, time_budget: float, keep_series: bool) -> Any:
    if not isinstance(jobs, int) or jobs < 1:
        raise InputError(f"--jobs: must be a whole number >= 1, got {jobs!r}")
    o = _dampsym.Options()
    o.jobs = jobs
    o.time_budget = float(time_budget)
    o.keep_series = keep_series
    o.method_files = builtins.list(method_files)
    o.plugins = [os.fspath(p) for p in plugins]
    o.cases_dir = "" if cases_dir is None else os.fspath(cases_dir)
    return o


def _method_files(methods: Iterable[MethodLike] | None) -> builtins.list[str]:
    """The method files among ``methods`` (Tableau and Step objects are registered already)."""
    files: builtins.list[str] = []
    for m in methods or ():
        if isinstance(m, (Tableau, Step)):
            continue
        files.append(os.fspath(m))
    return files


def _case_target(case: CaseLike) -> str:
    if isinstance(case, dict):
        return json.dumps(case)
    return os.fspath(case)


def _arrays(report: Report) -> Report:
    """Each run's final state as a numpy array."""
    for c in report.get("cases", ()):
        for r in c.get("runs", ()):
            if isinstance(r.get("final_state"), builtins.list):
                r["final_state"] = np.asarray(r["final_state"], dtype=float)
    return report


def _series_arrays(series: builtins.list[dict]) -> dict[str, dict]:  # type: ignore[type-arg]
    """Each case's series (docs/reports.md "Series files") by case id, their samples (t, y; an
    orbit's t and states) as numpy arrays."""
    out: dict[str, dict] = {}  # type: ignore[type-arg]
    for doc in series:
        for run in doc.get("runs", ()):
            for s in run.get("series", {}).values():
                for key in ("t", "y", "states", "exact"):  # samples; an orbit's states
                    if isinstance(s.get(key), builtins.list):
                        s[key] = np.asarray(s[key], dtype=float)
        out[str(doc.get("case"))] = doc
    return out


def _report(text: str, status: int) -> Report:
    r = Report(json.loads(text))
    r.text = text
    r.exit_status = status
    return r


def run(case: CaseLike | Sequence[CaseLike], *, methods: Iterable[MethodLike] | None = None,
        jobs: int = 1, figures: bool = False, time_budget: float = 0.02,
        plugins: Iterable[PathLike] = (), cases_dir: PathLike | None = None) -> Report:
    """Runs cases as ``dampsym run`` does and returns report.json's content.

    ``case``: a case id, a case file's path, a case as a dict (docs/case-keys.md), or a list of
    these. ``methods``: method files (``--methods``), :class:`Tableau` and :class:`Step` objects.
    ``figures=True`` keeps each case's time series (``run --figures``' series files) under
    ``report["series"][case_id]``, the samples as numpy arrays; each run's ``final_state`` is a
    numpy array. Failing checks do not raise: see ``report["summary"]`` and ``exit_status``."""
    cases = [case] if isinstance(case, (str, dict, os.PathLike)) else builtins.list(case)
    opts = _options(jobs, _method_files(methods), plugins, cases_dir, time_budget, figures)
    text, series, status = _dampsym.run([_case_target(c) for c in cases], opts)
    report = _arrays(_report(text, status))
    if figures:
        report["series"] = _series_arrays(json.loads(series))
    return report


def matrix(methods: Iterable[MethodLike] | None = None, *, jobs: int = 1,
           plugins: Iterable[PathLike] = (), cases_dir: PathLike | None = None) -> Report:
    """The method x property matrix (docs/matrix.md) as matrix.json's content, the battery's
    report under ``["report"]``. ``methods``: method ids or globs, :class:`Tableau` and
    :class:`Step` objects, method files (``*.json``, whose methods join); all when None."""
    globs: builtins.list[str] = []
    for m in methods or ():
        if isinstance(m, (Tableau, Step)):
            globs.append(m.id)
        elif os.fspath(m).endswith(".json") and os.path.isfile(m):
            globs.extend(_dampsym.load_method_file(os.fspath(m)))
        else:
            globs.append(os.fspath(m))
    opts = _options(jobs, [], plugins, cases_dir, 0.0, False)
    text, report_text, status = _dampsym.matrix(globs, opts)
    out = _report(text, status)
    out["report"] = _arrays(_report(report_text, status))
    return out


def list(*args: str) -> builtins.list[dict]:  # type: ignore[type-arg]  # noqa: A001
    """``dampsym list --json ARGS...``: the cases (``--suite S``, ``--filter GLOB``, ...)."""
    done = cli(["list", "--json", *args])
    if done.returncode != 0:
        raise InputError(done.stderr.strip().removeprefix("dampsym: "))
    doc = json.loads(done.stdout)
    return builtins.list(doc["cases"] if isinstance(doc, dict) else doc)
