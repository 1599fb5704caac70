"""The case as its file states it, independent of the report (verify/crosscheck.py).

The cross-check takes every input that decides what it recomputes and how it judges it -- the
runs (methods x step sizes) and their step counts, the output grid, the checks' metrics,
operators and thresholds -- from the case file (with the report's recorded `--set` overrides
applied, docs/case-keys.md), never from the numbers the report gives for them.  The case file is
the one the report says dampsym read (its `file`), when that is still a readable JSON file with
the case's id -- a case of the user's own directory, `--cases DIR` or a file named on the command
line -- else the file of that id in verify/cases/.  A run or check the file implies but the report lacks (and that the
report's method selection does not explain) is a disagreement, and so is one the report has but
the file does not imply.

Expansion of `expect` into check entries follows docs/case-keys.md ("expect: checks",
"Comparing methods"): a per-method check gives one entry per method and per step size (a
method-level metric: per method), `dt` restricts the step sizes, `ratio` / `spread` give one
entry per step size named "A / B" / "spread(A, B, ...)", `across_dt` one entry.
"""
from __future__ import annotations

import copy
import fnmatch
import glob
import json
import math
import os
import shlex
import stat
from typing import Any, Dict, List, Optional, Tuple

HERE = os.path.dirname(os.path.abspath(__file__))
CASES_DIR = os.path.join(HERE, "cases")
METHOD_LEVEL = ("order", "local-order", "stability-sweep", "trace-taylor")
OPS = ("near", "le", "ge", "lt", "gt")
_INDEX: Dict[str, Dict[str, str]] = {}
# the C plugins the report's run loaded (crosscheck.main; a plugin's methods are compiled code)
RUN_PLUGINS: List[Any] = []
# a case file larger than this is not read as one (a report naming /dev/zero or a huge file)
CASE_FILE_LIMIT = 16 << 20

Json = Dict[str, Any]
CheckKey = Tuple[str, str, Optional[float]]


class CaseFileError(Exception):
    """A case file that cannot be read or expanded (bad input: exit 2)."""


def case_index(cases_dir: str = CASES_DIR) -> Dict[str, str]:
    """id -> path of every case file in a cases directory (verify/cases unless named; each
    directory read once)."""
    key = os.path.abspath(cases_dir)
    if key not in _INDEX:
        index: Dict[str, str] = {}
        for path in sorted(glob.glob(os.path.join(key, "*.json"))):
            try:
                with open(path) as fh:
                    doc = json.load(fh)
            except (OSError, ValueError, RecursionError) as exc:
                raise CaseFileError("%s: not readable JSON (%s)" % (path, exc))
            cid = doc.get("id") if isinstance(doc, dict) else None
            if isinstance(cid, str):
                index[cid] = path
        _INDEX[key] = index
    return _INDEX[key]


def suites_of(path: str) -> List[str]:
    with open(path) as fh:
        return list(json.load(fh).get("suites") or [])


def shlex_split(line: str) -> List[str]:
    try:
        return shlex.split(line)
    except ValueError:
        return line.split()


def set_path(obj: Json, key: str, value: Any) -> None:
    """`--set a.b.c=value`: replace (or add) one dotted key (docs/case-keys.md)."""
    parts = key.split(".")
    for p in parts[:-1]:
        nxt = obj.get(p)
        if not isinstance(nxt, dict):
            nxt = obj[p] = {}
        obj = nxt
    obj[parts[-1]] = value


def recorded_case_file(case: Json) -> Optional[str]:
    """The case file the report says dampsym read (`file`), when it is still there: a regular
    file of at most CASE_FILE_LIMIT bytes holding a JSON object with the case's id; else None."""
    path = case.get("file")
    if not isinstance(path, str) or not path:
        return None
    try:
        st = os.stat(path)
        if not stat.S_ISREG(st.st_mode) or st.st_size > CASE_FILE_LIMIT:
            return None
        with open(path) as fh:
            doc = json.load(fh)
    except (OSError, ValueError, RecursionError):
        return None
    return path if isinstance(doc, dict) and doc.get("id") == case.get("id") else None


def load_spec(cid: str, overrides: Optional[Json], path: Optional[str] = None) -> Optional[Json]:
    """The case file at `path` (the one the report names, recorded_case_file), else the file of
    `cid` in verify/cases, with the overrides applied; None when there is neither (dampsym matrix
    builds its battery in code)."""
    path = path or case_index().get(cid)
    if path is None:
        return None
    with open(path) as fh:
        spec = json.load(fh)
    spec = copy.deepcopy(spec)
    for key, value in sorted((overrides or {}).items()):
        set_path(spec, key, value)
    spec["_file"] = path
    return spec


def step_sizes(spec: Json) -> List[float]:
    """The case's step sizes in the file's order (`dt` or `dt_ladder`)."""
    if "dt_ladder" in spec:
        return [float(x) for x in spec["dt_ladder"]]
    if "dt" in spec:
        return [float(spec["dt"])]
    raise CaseFileError("%s: key dt: neither dt nor dt_ladder given" % spec.get("_file"))


def steps_for(spec: Json, dt: float) -> int:
    """(t_end - t0) / dt, an integer to 1e-9 relative (docs/case-keys.md `dt`)."""
    t0, t_end = float(spec.get("t0", 0.0)), float(spec["t_end"])
    n = (t_end - t0) / dt
    k = int(round(n))
    if k < 1 or abs(n - k) > 1e-9 * max(1.0, abs(n)):
        raise CaseFileError("%s: key dt: %r does not divide t_end - t0" % (spec.get("_file"), dt))
    return k


def output_stride(spec: Json, dt: float) -> int:
    """Steps between output grid points: output_dt / dt (1 without output_dt: every step of
    the single step size, docs/case-keys.md `output_dt`)."""
    odt = spec.get("output_dt")
    if odt is None:
        return 1
    return max(1, int(round(float(odt) / dt)))


def selected_methods(report: Json) -> Optional[List[str]]:
    """The `--method` globs of the run's command line (None: no selection)."""
    words = shlex_split(((report.get("provenance") or {}).get("command_line")) or "")
    globs: List[str] = []
    for i, w in enumerate(words):
        if w == "--method" and i + 1 < len(words):
            globs.append(words[i + 1])
        elif w.startswith("--method="):
            globs.append(w.split("=", 1)[1])
    return globs or None


def methods_run(spec: Json, selection: Optional[List[str]]) -> List[str]:
    ms = list(spec.get("methods") or [])
    if selection is None:
        return ms
    return [m for m in ms if any(fnmatch.fnmatchcase(m, g) for g in selection)]


def _op_of(name: str, cj: Json) -> Tuple[str, float, Optional[float]]:
    ops = [k for k in OPS if k in cj]
    if len(ops) != 1:
        raise CaseFileError("expect.%s: exactly one of near, le, ge, lt, gt" % name)
    op = ops[0]
    val = cj[op]
    val = float(val) if not isinstance(val, bool) else float(int(val))
    return op, val, (float(cj.get("tol", 0.0)) if op == "near" else None)


def _members(spec: Json, cj: Json) -> Tuple[str, List[str]]:
    all_m = list(spec.get("methods") or [])
    if "ratio" in cj:
        return "ratio", list(cj["ratio"])
    if "spread" in cj:
        return "spread", all_m if cj["spread"] == "all" else list(cj["spread"])
    ms = cj.get("methods")
    return "per-method", all_m if ms == "all" else list(ms or [])


def _head(name: str, cj: Json, label: str, op: str, val: float, tol: Optional[float]) -> Json:
    h: Json = dict(name=name, metric=cj.get("metric"), method=label, op=op, expected=val,
                   negative_control=bool(cj.get("negative_control", False)))
    if tol is not None:
        h["tolerance"] = tol
    if cj.get("abs"):
        h["abs"] = True
    if cj.get("refutes"):
        h["refutes"] = True
    return h


def expected_checks(spec: Json) -> Dict[CheckKey, Json]:
    """(name, method label, dt or None) -> the check's head fields and `members` (the methods
    it reads), expanded as dampsym's checks are (module docstring)."""
    out: Dict[CheckKey, Json] = {}
    dts = step_sizes(spec)
    for name, cj in (spec.get("expect") or {}).items():
        op, val, tol = _op_of(name, cj)
        form, members = _members(spec, cj)
        only = cj.get("dt")
        steps = [h for h in dts if only is None or float(only) == h]
        metric = str(cj.get("metric"))
        method_level = metric.split(".")[0] in METHOD_LEVEL
        if form != "per-method" or cj.get("across_dt"):
            groups: List[List[str]] = [members] if form != "per-method" else [[m] for m in members]
            for g in groups:
                sep = " / " if form == "ratio" else ", "
                label = sep.join(g) if form != "spread" else "spread(%s)" % ", ".join(g)
                at: List[Optional[float]] = [None] if cj.get("across_dt") else list(steps)
                for h in at:
                    hd = _head(name, cj, label, op, val, tol)
                    hd.update(form=form, methods=list(g), members=list(g))
                    if cj.get("across_dt"):
                        hd["across_dt"] = cj["across_dt"]
                    if h is not None:
                        hd["dt"] = h
                    out[(name, label, hd.get("dt"))] = hd
            continue
        for m in members:
            hs: List[Optional[float]] = [None] if method_level else list(steps)
            for h in hs:
                hd = _head(name, cj, m, op, val, tol)
                hd["members"] = [m]
                if h is not None:
                    hd["dt"] = h
                out[(name, m, h)] = hd
    return out


def check_key(chk: Json) -> CheckKey:
    dt = chk.get("dt")
    return (str(chk.get("name")), str(chk.get("method")), None if dt is None else float(dt))


def same(a: Any, b: Any) -> bool:
    """Equality of two JSON values, numbers as doubles (1 == 1.0)."""
    if isinstance(a, bool) or isinstance(b, bool):
        return a is b or (not isinstance(a, bool) and not isinstance(b, bool) and a == b)
    if isinstance(a, (int, float)) and isinstance(b, (int, float)):
        return float(a) == float(b) or (math.isnan(float(a)) and math.isnan(float(b)))
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b))
    return bool(a == b)


def output_intervals(spec: Json) -> int:
    """Intervals of the case's output grid (docs/case-keys.md `output_dt`): (t_end - t0) /
    output_dt; without output_dt a grid common to every step size (the coarsest step's count
    divided by its largest divisor that leaves at most 20000 intervals), or 1 (the final time
    only) when the step sizes do not divide each other."""
    if spec.get("_intervals"):
        return int(spec["_intervals"])
    span = float(spec["t_end"]) - float(spec.get("t0", 0.0))
    if spec.get("output_dt") is not None:
        return int(round(span / float(spec["output_dt"])))
    dts = step_sizes(spec)
    coarse = max(dts)
    for h in dts:
        r = coarse / h
        if abs(r - round(r)) > 1e-9 * r:
            return 1
    n = steps_for(spec, coarse)
    for k in range(1, n + 1):
        if n % k == 0 and n // k <= 20000:
            return n // k
    return 1


def grid_stride(spec: Json, dt: float) -> int:
    """Steps of size dt between two output grid points."""
    return max(1, steps_for(spec, dt) // output_intervals(spec))


def diagnostics(spec: Json) -> List[str]:
    """Requested diagnostics with the ones they imply (verify/diagnostics: `order` adds `error`,
    `local-order` adds `local-error`; default ["error"])."""
    from . import diagnostics as registry     # the registry's modules import this one
    return registry.with_implied(list(spec.get("diagnostics") or ["error"]))


def spec_from_report(case: Json) -> Json:
    """A case with no file in verify/cases (dampsym matrix builds its battery in code): its
    inputs as the report records them, marked as such (the structure record says so)."""
    ref = case.get("reference") or {}
    # the output grid: the reference's points, else the points the runs observed (a case without
    # a reference whose file is not at hand)
    pts = int(ref.get("points") or 0) or max(
        [int(((r.get("observed") or {}).get("grid_points")) or 0) for r in case.get("runs") or []] + [0])
    spec: Json = {k: case[k] for k in ("id", "t0", "t_end", "methods", "diagnostics", "measures")
                  if k in case}
    spec["dt_ladder"] = list(case.get("dt_ladder") or [])
    spec["problem"] = {"id": (case.get("problem") or {}).get("id")}
    spec["_intervals"] = max(1, pts - 1) if pts >= 2 else 1
    spec["_from_report"] = True
    spec["_file"] = "(no case file: inputs from the report)"
    return spec


def reference_points(spec: Json) -> int:
    """Points of the reference's grid: the output grid t0..t_end, or t_end alone when the grid
    has one interval (output_dt = t_end - t0, or step sizes with no common grid)."""
    n = output_intervals(spec)
    return 1 if n <= 1 else n + 1
