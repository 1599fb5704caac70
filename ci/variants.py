#!/usr/bin/python3
"""Held-out variants of a suite's cases, run by dampsym and cross-checked (docs/ci.md "Held-out
variants"): the cases as a user would change them, in the shapes the suite itself never has.

For every case of the suite (cases with method files or a stability sweep are left out) it writes
up to three variants into OUT/cases, each under its own id:

  ladder  a single step dt becomes the ladder [2 dt, dt] (no output_dt: the output grid is then
          the coarse step's, and every diagnostic must still be computed on the grid it is
          defined on; the coarse step may be unstable or hard for Newton);
  odt     a single step dt gets output_dt = 2 dt (an output grid coarser than the step);
  t0      the whole interval shifted by 0.5 (t0 = t0 + 0.5: time-dependent damping and forcing
          read t, and nothing may assume t0 = 0).

A ladder or output grid that does not divide t_end - t0 is not written. Each variant is run alone
first (one that dampsym refuses as bad input, exit 2, is listed and dropped), then all of them in
one run (--jobs), and the report is cross-checked with --strict. Prints the cross-check's summary
and every disagreement; exit 0 when nothing disagrees and nothing is not reproduced, 1 otherwise,
2 on a usage error.

    /usr/bin/python3 ci/variants.py --dampsym build/dampsym [--suite default] [--jobs 2]
                                    [--out DIR] [--max-steps 200000]
"""

from __future__ import annotations

import argparse
import copy
import json
import os
import subprocess
import sys
import tempfile
from typing import Any, Dict, List, Optional

Json = Dict[str, Any]
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def divides(span: float, h: float) -> bool:
    """span is an integer multiple of h (to 1e-9 relative, as dampsym's case parser)."""
    r = span / h
    return abs(r - round(r)) <= 1e-9 * r


def variants(spec: Json, max_steps: int) -> List[Json]:
    """The ladder, odt and t0 variants of one case file's content (see the module docstring)."""
    if spec.get("method_files") or "stability_sweep" in spec:
        return []
    base = copy.deepcopy(spec)
    base["suites"] = ["variants"]
    t0 = float(spec.get("t0", 0.0))
    span = float(spec["t_end"]) - t0
    out: List[Json] = []
    dt = spec.get("dt")
    if isinstance(dt, (int, float)) and not isinstance(dt, bool) and "output_dt" not in spec \
            and span / dt <= max_steps and divides(span, 2 * dt):
        ladder = copy.deepcopy(base)
        del ladder["dt"]
        ladder.update(id=spec["id"] + "-ladder", dt_ladder=[2 * dt, dt])
        odt = copy.deepcopy(base)
        odt.update(id=spec["id"] + "-odt", output_dt=2 * dt)
        out += [ladder, odt]
    shifted = copy.deepcopy(base)
    shifted.update(id=spec["id"] + "-t0", t0=t0 + 0.5, t_end=float(spec["t_end"]) + 0.5)
    out.append(shifted)
    return out


def suite_case_files(dampsym: str, suite: str) -> List[str]:
    """The case files of a suite, as `dampsym list --json` names them."""
    r = subprocess.run([dampsym, "list", "--json", "--suite", suite], capture_output=True, text=True)
    if r.returncode != 0:
        raise SystemExit("variants.py: dampsym list --suite %s: %s" % (suite, r.stderr.strip()))
    return [c["file"] for c in json.loads(r.stdout)["cases"]]


def write_variants(files: List[str], out: str, max_steps: int) -> List[str]:
    os.makedirs(os.path.join(out, "cases"), exist_ok=True)
    paths = []
    for f in files:
        with open(f) as fh:
            spec = json.load(fh)
        for v in variants(spec, max_steps):
            paths.append(os.path.join(out, "cases", v["id"] + ".json"))
            with open(paths[-1], "w") as fh:
                json.dump(v, fh, indent=1)
    return paths


def accepted(dampsym: str, paths: List[str], out: str) -> List[str]:
    """The variants dampsym runs (exit 0 or 1: a check may fail at the new shape; that is the
    cross-check's question, not this one's); the refused ones are printed."""
    ok = []
    for p in paths:
        r = subprocess.run([dampsym, "run", p, "--out", os.path.join(out, "single"), "-q",
                            "--case-timeout", "120"], capture_output=True, text=True)
        if r.returncode in (0, 1):
            ok.append(p)
        else:
            print("variants.py: %s: not run (exit %d): %s" % (os.path.basename(p), r.returncode,
                                                               r.stderr.strip()[-200:]))
    return ok


def crosscheck(report: str, out: str, jobs: int) -> Json:
    r = subprocess.run([sys.executable, "-m", "verify.crosscheck", report, "--out", out,
                        "--strict", "--jobs", str(jobs)], cwd=ROOT, capture_output=True, text=True)
    for line in r.stdout.splitlines():
        if line.startswith(("DISAGREE", "crosscheck:")):
            print(line[:400])
    with open(os.path.join(out, "crosscheck.json")) as fh:
        return dict(json.load(fh))


def verdict(summary: Json) -> int:
    """0 when nothing disagrees and nothing is not reproduced, else 1."""
    bad = sum(summary[k]["disagree"] + summary[k]["not reproduced"]
              for k in ("structure", "runs", "orders", "checks"))
    return 0 if bad == 0 else 1


def main(argv: Optional[List[str]] = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--dampsym", default=os.path.join(ROOT, "build", "dampsym"))
    ap.add_argument("--suite", default="default")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--out", default="")
    ap.add_argument("--max-steps", type=int, default=200000)
    a = ap.parse_args(argv)
    if not os.access(a.dampsym, os.X_OK) or a.jobs < 1 or a.max_steps < 1:
        print("variants.py: give an executable --dampsym, --jobs >= 1, --max-steps >= 1", file=sys.stderr)
        return 2
    out = a.out or tempfile.mkdtemp(prefix="dampsym-variants-")
    paths = write_variants(suite_case_files(a.dampsym, a.suite), out, a.max_steps)
    ok = accepted(a.dampsym, paths, out)
    print("variants.py: %d variants written, %d run (%s)" % (len(paths), len(ok), out))
    report = os.path.join(out, "report")
    subprocess.run([a.dampsym, "run", *ok, "--out", report, "-q", "--jobs", str(a.jobs),
                    "--case-timeout", "120"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return verdict(crosscheck(os.path.join(report, "report.json"), os.path.join(out, "xc"), a.jobs)["summary"])


if __name__ == "__main__":
    sys.exit(main())
