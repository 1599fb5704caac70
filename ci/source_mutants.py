#!/usr/bin/python3
"""Source mutants: one-line changes of dampsym's C++ sources (and of the cross-check's Python),
each rebuilt in one throwaway clone and scored for the default suite and for the cross-check
alone (docs/mutation.md, "Source mutants").

    ci/source_mutants.py [--mutants ci/source_mutants.json] [--out DIR] [--clone DIR]
                         [--only ID ...] [--resume] [--check-only]

A mutant (ci/source_mutants.json) is {id, file, find, replace, class, breaks}: `find` must occur
exactly once in `file` at HEAD. The script clones HEAD once, configures one Release build (the
ccache launcher, CCACHE_BASEDIR = the clone, CCACHE_NOHASHDIR=1 as ci/build.sh: objects of an
unchanged source are cache hits), and runs the baseline: the default suite (`dampsym run --jobs 2
--shard none`) must exit 0 and `verify.crosscheck REPORT --strict` must exit 0, else exit 1.
Then per mutant: apply, `cmake --build --target dampsym` (a failing build: invalid mutant), run
the default suite (killed when it exits 1), run the cross-check on that report alone (killed when
it exits nonzero), revert. A Python mutant (under verify/) changes only the cross-check: it is run
on the baseline report, and the suite is "not applicable" (listed apart).

Writes OUT/results.json and OUT/results.md after every mutant; prints the scores and the
survivors. Exit 0 when the campaign ran (whatever the scores), 1 when the baseline fails, 2 on
bad input (naming the file and key).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from collections import Counter
from dataclasses import asdict, dataclass, field
from typing import Any, Dict, List, Optional, Sequence

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
KEYS = ("id", "file", "find", "replace", "class", "breaks")
FIRST = 5          # failing checks / disagreements recorded per mutant
PY = "/usr/bin/python3"
NICE = ["nice", "-n", "10"]

Json = Any


class BadInput(Exception):
    pass


@dataclass
class Mutant:
    id: str
    file: str
    find: str
    replace: str
    cls: str
    breaks: str

    @property
    def kind(self) -> str:
        return "python" if self.file.endswith(".py") else "cpp"

    @property
    def header(self) -> bool:
        return self.file.endswith((".hpp", ".h"))


@dataclass
class Outcome:
    id: str
    kind: str
    cls: str
    file: str
    breaks: str
    valid: bool = True
    build_seconds: float = 0.0
    build_error: str = ""
    suite_exit: Optional[int] = None       # None: not applicable (Python mutant) or invalid
    suite_killed: Optional[bool] = None
    failed_checks: List[str] = field(default_factory=list)
    failed_count: int = 0
    failed_names: List[str] = field(default_factory=list)  # distinct check names, "name ×n"
    suite_seconds: float = 0.0
    same_as_baseline: Optional[bool] = None  # the report equal to the baseline's but for clocks
    xc_exit: Optional[int] = None
    xc_killed: Optional[bool] = None
    disagreements: List[str] = field(default_factory=list)
    disagree_count: int = 0
    disagree_quantities: List[str] = field(default_factory=list)  # distinct, "quantity ×n"
    xc_seconds: float = 0.0


# ---- the mutant list ------------------------------------------------------------------------

def load_mutants(path: str) -> List[Mutant]:
    """The list file: {"mutants": [{id, file, find, replace, class, breaks}, ...]}; ids unique."""
    try:
        with open(path, encoding="utf-8") as fh:
            doc = json.load(fh)
    except (OSError, ValueError) as exc:
        raise BadInput("%s: %s" % (path, exc)) from exc
    if not isinstance(doc, dict) or not isinstance(doc.get("mutants"), list):
        raise BadInput("%s: key 'mutants' must be a list" % path)
    out: List[Mutant] = []
    seen = set()
    for k, m in enumerate(doc["mutants"]):
        if not isinstance(m, dict):
            raise BadInput("%s: mutants[%d] must be an object" % (path, k))
        for key in KEYS:
            if not isinstance(m.get(key), str) or not m[key]:
                raise BadInput("%s: mutants[%d].%s must be a non-empty string" % (path, k, key))
        extra = sorted(set(m) - set(KEYS))
        if extra:
            raise BadInput("%s: mutants[%d]: unknown key '%s'" % (path, k, extra[0]))
        if m["id"] in seen:
            raise BadInput("%s: mutants[%d].id '%s' given twice" % (path, k, m["id"]))
        if m["find"] == m["replace"]:
            raise BadInput("%s: mutants[%d].replace equals its find" % (path, k))
        seen.add(m["id"])
        out.append(Mutant(m["id"], m["file"], m["find"], m["replace"], m["class"], m["breaks"]))
    return out


def check_finds(root: str, mutants: Sequence[Mutant]) -> None:
    """Every find occurs exactly once in its file under root (else BadInput naming it)."""
    for m in mutants:
        path = os.path.join(root, m.file)
        try:
            with open(path, encoding="utf-8") as fh:
                n = fh.read().count(m.find)
        except OSError as exc:
            raise BadInput("mutant %s: file %s: %s" % (m.id, m.file, exc)) from exc
        if n != 1:
            raise BadInput("mutant %s: its find occurs %d times in %s (must be exactly once)"
                           % (m.id, n, m.file))


def apply(root: str, m: Mutant) -> str:
    """Writes the mutant into root; returns the original text (for revert)."""
    path = os.path.join(root, m.file)
    with open(path, encoding="utf-8") as fh:
        text = fh.read()
    if text.count(m.find) != 1:
        raise BadInput("mutant %s: find not exactly once in %s" % (m.id, m.file))
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(text.replace(m.find, m.replace))
    return text


def revert(root: str, m: Mutant, original: str) -> None:
    with open(os.path.join(root, m.file), "w", encoding="utf-8") as fh:
        fh.write(original)


# ---- what killed it -------------------------------------------------------------------------

def _failed(report_path: str) -> List[Dict[str, Any]]:
    """The failed checks of a report (passed false; not-run checks excluded), each with its
    case id under 'case'."""
    try:
        with open(report_path, encoding="utf-8") as fh:
            report = json.load(fh)
    except (OSError, ValueError):
        return []
    return [dict(ch, case=c.get("id")) for c in report.get("cases", [])
            for ch in c.get("checks", []) if ch.get("passed") is False]


def failed_checks(report_path: str) -> List[str]:
    """'case: check [method, dt]' of every failed check of a report."""
    return ["%s: %s [%s, dt=%s]" % (f["case"], f.get("name"), f.get("method"), f.get("dt"))
            for f in _failed(report_path)]


def same_results(base_report: str, report: str) -> bool:
    """Whether two reports are equal in everything but `provenance` (commit, dirty flag, command
    line, start time) and `timings` (clocks): every final state, metric, fit, check value and
    verdict bit for bit (JSON numbers round-trip doubles exactly)."""
    try:
        docs = []
        for path in (base_report, report):
            with open(path, encoding="utf-8") as fh:
                d = json.load(fh)
            docs.append({k: v for k, v in d.items() if k not in ("provenance", "timings")})
    except (OSError, ValueError):
        return False
    return bool(docs[0] == docs[1])


def _most_common(names: List[str]) -> List[str]:
    return ["%s ×%d" % (k, n) for k, n in Counter(names).most_common(FIRST)]


def failed_names(report_path: str) -> List[str]:
    """Distinct names of the failed checks, most frequent first ('name ×count')."""
    return _most_common([str(f.get("name")) for f in _failed(report_path)])


def disagree_quantities(xc_path: str) -> List[str]:
    """Distinct quantities of the comparisons that disagree or are not reproduced, most frequent
    first ('quantity ×count')."""
    try:
        with open(xc_path, encoding="utf-8") as fh:
            xc = json.load(fh)
    except (OSError, ValueError):
        return []
    return _most_common([c.get("quantity", "?")
                         for g in ("structure", "runs", "orders", "checks") for r in xc.get(g, [])
                         for c in r.get("comparisons", [])
                         if c.get("status") in ("disagree", "not reproduced")])


def record_kills(o: Outcome, out: str, suite_ran: bool) -> None:
    """What killed o, from the report and crosscheck.json saved in out."""
    if suite_ran:
        fails = failed_checks(os.path.join(out, "report.json"))
        o.failed_count, o.failed_checks = len(fails), fails[:FIRST]
        o.failed_names = failed_names(os.path.join(out, "report.json"))
    dis = disagreements(os.path.join(out, "crosscheck.json"))
    o.disagree_count, o.disagreements = len(dis), dis[:FIRST]
    o.disagree_quantities = disagree_quantities(os.path.join(out, "crosscheck.json"))


def disagreements(xc_path: str) -> List[str]:
    """'case/method/dt: quantity' of every cross-check record that disagrees or is not
    reproduced (--strict), from crosscheck.json."""
    try:
        with open(xc_path, encoding="utf-8") as fh:
            xc = json.load(fh)
    except (OSError, ValueError):
        return []
    out = []
    for group in ("structure", "runs", "orders", "checks"):
        for r in xc.get(group, []):
            if r.get("verdict") not in ("disagree", "not reproduced"):
                continue
            qs = [c.get("quantity", "?") for c in r.get("comparisons", [])
                  if c.get("status") in ("disagree", "not reproduced")]
            where = "/".join(str(r[k]) for k in ("case", "method", "dt") if k in r)
            out.append("%s %s: %s" % (group, where, ", ".join(qs[:3]) or r.get("verdict")))
    return out


# ---- running --------------------------------------------------------------------------------

def run(cmd: List[str], cwd: str, log: str, env: Optional[Dict[str, str]] = None,
        timeout: float = 3600.0) -> int:
    with open(log, "w", encoding="utf-8") as fh:
        try:
            return subprocess.run(cmd, cwd=cwd, stdout=fh, stderr=subprocess.STDOUT, env=env,
                                  timeout=timeout, check=False).returncode
        except subprocess.TimeoutExpired:
            fh.write("\n(timed out after %.0f s)\n" % timeout)
            return 124


def build_env(clone: str) -> Dict[str, str]:
    env = dict(os.environ)
    env.update(CCACHE_BASEDIR=clone, CCACHE_NOHASHDIR="1")
    return env


def make_clone(repo: str, clone: str, logdir: str, configure: bool) -> str:
    """A clone of repo's HEAD at clone (reused if it is already one at HEAD), configured unless
    nothing is to be built."""
    head = subprocess.run(["git", "-C", repo, "rev-parse", "HEAD"], capture_output=True,
                          text=True, check=True).stdout.strip()
    if not os.path.isdir(os.path.join(clone, ".git")):
        subprocess.run(["git", "clone", "--quiet", "--shared", "--no-checkout", repo, clone],
                       check=True)
    subprocess.run(["git", "-C", clone, "checkout", "--quiet", "--force", "--detach", head],
                   check=True)
    cfg = ["cmake", "-S", clone, "-B", os.path.join(clone, "build"), "-DCMAKE_BUILD_TYPE=Release",
           "-DDAMPSYM_WERROR=ON", "-DCMAKE_CXX_COMPILER_LAUNCHER=ccache",
           "-DCMAKE_C_COMPILER_LAUNCHER=ccache"]
    if configure and run(cfg, clone, os.path.join(logdir, "configure.log"),
                         build_env(clone)) != 0:
        raise RuntimeError("configure failed: %s/configure.log" % logdir)
    return head


def build(clone: str, log: str) -> int:
    cmd = NICE + ["cmake", "--build", os.path.join(clone, "build"), "-j2", "--target", "dampsym"]
    return run(cmd, clone, log, build_env(clone))


def suite(clone: str, out: str) -> int:
    cmd = NICE + [os.path.join(clone, "build", "dampsym"), "run", "--out", out, "--jobs", "2",
                  "--shard", "none"]
    os.makedirs(out, exist_ok=True)
    return run(cmd, clone, os.path.join(out, "suite.log"))


def crosscheck(clone: str, report: str, out: str) -> int:
    cmd = NICE + [PY, "-m", "verify.crosscheck", report, "--strict", "--out", out, "--jobs", "2"]
    os.makedirs(out, exist_ok=True)
    return run(cmd, clone, os.path.join(out, "crosscheck.log"))


def kept_baseline(clone: str, out: str, head: str) -> bool:
    """A clean baseline recorded in out (out/clean holds its commit) of head, or of a commit that
    differs from head only in ci/ and docs/ (the campaign's own files: same binary, same suite,
    same cross-check)."""
    marker = os.path.join(out, "clean")
    if not (os.path.isfile(marker) and os.path.isfile(os.path.join(out, "report.json"))):
        return False
    with open(marker, encoding="utf-8") as fh:
        commit = fh.read().strip()
    return commit == head or subprocess.run(
        ["git", "-C", clone, "diff", "--quiet", commit, head, "--", ".", ":!ci", ":!docs"],
        check=False).returncode == 0


def baseline(clone: str, out: str, head: str, reuse: bool, need_build: bool) -> str:
    """Builds and runs the unmutated clone; returns its report (RuntimeError if not clean). With
    reuse, a clean baseline of the same commit (--resume) is kept, and only Python mutants left
    to run need no build."""
    os.makedirs(out, exist_ok=True)
    report, marker = os.path.join(out, "report.json"), os.path.join(out, "clean")
    keep = reuse and kept_baseline(clone, out, head)
    if need_build or not keep:
        t = time.perf_counter()
        if build(clone, os.path.join(out, "build.log")) != 0:
            raise RuntimeError("baseline build failed: %s/build.log" % out)
        print("baseline: built in %.0f s" % (time.perf_counter() - t), flush=True)
    if keep:
        print("baseline: clean (kept from %s)" % marker, flush=True)
        return report
    status = suite(clone, out)
    if status != 0:
        raise RuntimeError("baseline suite exit %d (must be 0): %s" % (status, out))
    status = crosscheck(clone, report, out)
    if status != 0:
        raise RuntimeError("baseline cross-check --strict exit %d (must be 0): %s" % (status, out))
    with open(marker, "w", encoding="utf-8") as fh:
        fh.write(head + "\n")
    print("baseline: suite and cross-check clean (%.0f s)" % (time.perf_counter() - t), flush=True)
    return report


def score_cpp(clone: str, m: Mutant, out: str, o: Outcome, base_report: str) -> None:
    """Build, suite and cross-check of one applied C++ mutant into o."""
    t = time.perf_counter()
    status = build(clone, os.path.join(out, "build.log"))
    o.build_seconds = time.perf_counter() - t
    if status != 0:
        o.valid = False
        o.build_error = "build exit %d (%s/build.log)" % (status, out)
        return
    t = time.perf_counter()
    o.suite_exit = suite(clone, out)
    o.suite_seconds = time.perf_counter() - t
    o.suite_killed = o.suite_exit == 1
    o.same_as_baseline = same_results(base_report, os.path.join(out, "report.json"))
    if not os.path.isfile(os.path.join(out, "report.json")):
        return                                   # no report: nothing to cross-check
    score_xc(clone, os.path.join(out, "report.json"), out, o)


def score_xc(clone: str, report: str, out: str, o: Outcome) -> None:
    t = time.perf_counter()
    o.xc_exit = crosscheck(clone, report, out)
    o.xc_seconds = time.perf_counter() - t
    o.xc_killed = o.xc_exit != 0
    record_kills(o, out, o.kind == "cpp")


def score_one(clone: str, m: Mutant, out: str, base_report: str) -> Outcome:
    o = Outcome(m.id, m.kind, m.cls, m.file, m.breaks)
    os.makedirs(out, exist_ok=True)
    original = apply(clone, m)
    try:
        if m.kind == "python":
            score_xc(clone, base_report, out, o)
        else:
            score_cpp(clone, m, out, o, base_report)
    finally:
        revert(clone, m, original)
    with open(os.path.join(out, "outcome.json"), "w", encoding="utf-8") as fh:
        json.dump(asdict(o), fh, indent=1)
    return o


# ---- scores and tables ----------------------------------------------------------------------

def scores(outcomes: Sequence[Outcome]) -> Dict[str, Json]:
    """Suite and cross-check scores over the valid C++ mutants; the Python (cross-check-only)
    mutants apart; survivors by id."""
    valid = [o for o in outcomes if o.kind == "cpp" and o.valid]
    # Equivalent on the default suite: a survivor whose report equals the baseline's (no check
    # of the default suite, nor the cross-check of its report, can see it; listed apart).
    equiv = [o for o in valid if o.same_as_baseline and not o.suite_killed]
    cpp = [o for o in valid if o not in equiv]
    py = [o for o in outcomes if o.kind == "python"]

    def frac(k: int, n: int) -> Optional[float]:
        return None if n == 0 else k / n

    suite_k = sum(1 for o in cpp if o.suite_killed)
    xc_k = sum(1 for o in cpp if o.xc_killed)
    py_k = sum(1 for o in py if o.xc_killed)
    return {
        "valid_cpp": len(cpp), "invalid": [o.id for o in outcomes if not o.valid],
        "equivalent_on_suite": [o.id for o in equiv],
        "suite_killed": suite_k, "suite_score": frac(suite_k, len(cpp)),
        "crosscheck_killed": xc_k, "crosscheck_score": frac(xc_k, len(cpp)),
        "either_killed": sum(1 for o in cpp if o.suite_killed or o.xc_killed),
        "python_mutants": len(py), "python_crosscheck_killed": py_k,
        "suite_survivors": [o.id for o in cpp if not o.suite_killed],
        "crosscheck_survivors": [o.id for o in cpp if not o.xc_killed]
        + [o.id for o in py if not o.xc_killed],
    }


def _pct(x: Optional[float]) -> str:
    return "n/a" if x is None else "%.1f %%" % (100.0 * x)


def _verdict(killed: Optional[bool]) -> str:
    return "n/a" if killed is None else ("killed" if killed else "**survived**")


def markdown(outcomes: Sequence[Outcome], s: Dict[str, Json], head: str) -> str:
    lines = ["# Source mutants at %s" % head[:12], "",
             "Default suite: %d of %d valid C++ mutants killed (%s); cross-check alone: %d of %d "
             "(%s); either: %d. Cross-check mutants (Python, suite not applicable): %d of %d "
             "killed. Invalid (build failed): %s. Equivalent on the default suite (report equal "
             "to the baseline's but for clocks; not in the scores): %s." % (
                 s["suite_killed"], s["valid_cpp"], _pct(s["suite_score"]),
                 s["crosscheck_killed"], s["valid_cpp"], _pct(s["crosscheck_score"]),
                 s["either_killed"], s["python_crosscheck_killed"], s["python_mutants"],
                 ", ".join(s["invalid"]) or "none", ", ".join(s["equivalent_on_suite"]) or "none"),
             ""]
    cols = "| id | class | file | suite | failed checks: count, names | cross-check | " \
           "disagreements: count, quantities | build / suite / xc s |"
    for title, kind in (("C++ mutants", "cpp"), ("Cross-check mutants (Python)", "python")):
        rows = [o for o in outcomes if o.kind == kind]
        if not rows:
            continue
        lines += ["## " + title, "", cols, "|" + "---|" * 8]
        for o in rows:
            fc = "%d: %s" % (o.failed_count, "; ".join(o.failed_names[:3])) if o.failed_count \
                else ("—" if o.suite_exit is None else "none (exit %s)" % o.suite_exit)
            dis = "%d: %s" % (o.disagree_count, "; ".join(o.disagree_quantities[:3])) \
                if o.disagree_count else "none (exit %s)" % o.xc_exit
            suite_v = "invalid: " + o.build_error if not o.valid else _verdict(o.suite_killed)
            xc_v = _verdict(o.xc_killed)
            if o.id in s["equivalent_on_suite"]:
                suite_v = xc_v = "equivalent on the suite"
            lines.append("| %s | %s | %s | %s | %s | %s | %s | %.0f / %.0f / %.0f |" % (
                o.id, o.cls, o.file, suite_v, fc.replace("|", "\\|"), xc_v,
                dis.replace("|", "\\|"), o.build_seconds, o.suite_seconds, o.xc_seconds))
        lines.append("")
    return "\n".join(lines)


def write_results(out: str, head: str, outcomes: Sequence[Outcome]) -> Dict[str, Json]:
    s = scores(outcomes)
    with open(os.path.join(out, "results.json"), "w", encoding="utf-8") as fh:
        json.dump({"tool": "ci/source_mutants.py", "commit": head, "scores": s,
                   "mutants": [asdict(o) for o in outcomes]}, fh, indent=1)
    with open(os.path.join(out, "results.md"), "w", encoding="utf-8") as fh:
        fh.write(markdown(outcomes, s, head))
    return s


def load_previous(out: str, ids: Sequence[str]) -> Dict[str, Outcome]:
    """Outcomes of earlier runs into out (--resume), by id: each mutant's OUT/ID/outcome.json
    (written as soon as it is scored, so an interrupted campaign loses none)."""
    done: Dict[str, Outcome] = {}
    for i in ids:
        try:
            with open(os.path.join(out, i, "outcome.json"), encoding="utf-8") as fh:
                done[i] = Outcome(**json.load(fh))
        except (OSError, ValueError, TypeError):
            pass
    return done


# ---- main -----------------------------------------------------------------------------------

def parse_args(argv: Optional[Sequence[str]]) -> argparse.Namespace:
    ap = argparse.ArgumentParser(description=(__doc__ or "").split("\n")[0])
    ap.add_argument("--mutants", default=os.path.join(ROOT, "ci", "source_mutants.json"))
    ap.add_argument("--out", default=os.path.join(ROOT, "build", "source-mutants"))
    ap.add_argument("--clone", default=None, help="the throwaway clone (default OUT/clone)")
    ap.add_argument("--only", action="append", default=[],
                    help="run only this mutant id (repeatable; run in the order given)")
    ap.add_argument("--resume", action="store_true", help="keep the outcomes in OUT/results.json")
    ap.add_argument("--check-only", action="store_true",
                    help="validate the list and its finds at HEAD, run nothing")
    return ap.parse_args(argv)


def select(mutants: List[Mutant], only: Sequence[str]) -> List[Mutant]:
    """The mutants named by --only, in that order (each once), or all in the list's order."""
    by_id = {m.id: m for m in mutants}
    for i in only:
        if i not in by_id:
            raise BadInput("--only %s: no such mutant" % i)
    return [by_id[i] for i in dict.fromkeys(only)] if only else list(mutants)


def campaign(args: argparse.Namespace, mutants: List[Mutant]) -> int:
    out = os.path.abspath(args.out)
    clone = os.path.abspath(args.clone or os.path.join(out, "clone"))
    os.makedirs(out, exist_ok=True)
    done = load_previous(out, [m.id for m in mutants]) if args.resume else {}
    need_build = any(m.kind == "cpp" and m.id not in done for m in mutants)
    head = make_clone(ROOT, clone, out, need_build or not args.resume)
    check_finds(clone, mutants)
    try:
        base = baseline(clone, os.path.join(out, "baseline"), head, args.resume, need_build)
    except RuntimeError as exc:
        print("source mutants: %s" % exc, file=sys.stderr)
        return 1
    outcomes: List[Outcome] = []
    for m in mutants:                            # kept outcomes first: every write lists them
        if m.id in done:
            o = done[m.id]
            record_kills(o, os.path.join(out, m.id), o.suite_exit is not None)
            if o.suite_exit is not None:
                o.same_as_baseline = same_results(base, os.path.join(out, m.id, "report.json"))
            outcomes.append(o)
    for m in mutants:
        if m.id in done:
            continue
        o = score_one(clone, m, os.path.join(out, m.id), base)
        outcomes.append(o)
        print("%-26s %-6s suite %-9s (%d failed) cross-check %-9s (%d disagree)  %.0f/%.0f/%.0f s"
              % (m.id, m.kind, _verdict(o.suite_killed) if o.valid else "invalid",
                 o.failed_count, _verdict(o.xc_killed), o.disagree_count, o.build_seconds,
                 o.suite_seconds, o.xc_seconds), flush=True)
        write_results(out, head, outcomes)
    s = write_results(out, head, outcomes)
    print("default suite: %d/%d (%s); cross-check alone: %d/%d (%s); Python mutants killed by "
          "the cross-check: %d/%d" % (s["suite_killed"], s["valid_cpp"], _pct(s["suite_score"]),
                                       s["crosscheck_killed"], s["valid_cpp"],
                                       _pct(s["crosscheck_score"]), s["python_crosscheck_killed"],
                                       s["python_mutants"]))
    print("equivalent on the default suite (report equal to the baseline's; not scored): %s"
          % (", ".join(s["equivalent_on_suite"]) or "none"))
    print("survivors of the suite: %s" % (", ".join(s["suite_survivors"]) or "none"))
    print("survivors of the cross-check: %s" % (", ".join(s["crosscheck_survivors"]) or "none"))
    print("wrote %s/results.{json,md}" % out)
    return 0


def main(argv: Optional[Sequence[str]] = None) -> int:
    args = parse_args(argv)
    try:
        mutants = select(load_mutants(args.mutants), args.only)
        if args.check_only:
            check_finds(ROOT, mutants)
            print("source mutants: %d, every find exactly once at %s" % (len(mutants), ROOT))
            return 0
        return campaign(args, mutants)
    except BadInput as exc:
        print("source mutants: bad input: %s" % exc, file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
