#!/usr/bin/python3
"""Coefficient mutants of every built-in method whose coefficients are data (docs/mutation.md).

For each exportable built-in (`dampsym methods --export ID --as ID.x`, docs/method-files.md) it
writes copies of the method file with one coefficient multiplied by (1 + 1e-6) and runs each copy
through three stages, each of which can kill it:

  check   `dampsym methods --check --methods MUTANT`: a coefficient check that agrees with the
          declaration for the unmutated export disagrees for the mutant;
  matrix  `dampsym matrix --methods MUTANT --method MUTANT_ID` exits 1;
  cases   the default-suite cases that name the built-in, run with the mutant in its place
          (`dampsym run CASES --methods MUTANT --substitute ID=MUTANT_ID`), exit 1.

A stage is used for a method only if the unmutated export passes it (the baseline). A survivor is
an equivalent mutant only if both hold: its steps equal the export's bit for bit on random states
of three problems (constant damping, time-dependent forcing, time-dependent damping), and a rule
(UNREAD) states why the coefficient is never read. Prints the per-stage and total scores and the
survivors; exit 1 if a coefficient mutant survives without such a proof, 2 on bad input.

    ci/mutants.py [--dampsym build/dampsym] [--jobs 2] [--method rk4 ...] [--out DIR]
    ci/mutants.py --roundtrip      # only: every export steps bit for bit like its built-in
"""

from __future__ import annotations

import argparse
import concurrent.futures
import copy
import json
import os
import random
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple

FACTOR = 1.0 + 1e-6
ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
STAGES = ("check", "matrix", "cases")

Path = Tuple[Any, ...]
Json = Any


# ---- mutation sites -------------------------------------------------------------------------

def _term_sites(entry: Json, path: Path) -> List[Tuple[Path, str]]:
    """Sites of one exponential coefficient: a constant, a term {coef, phi, arg} or a list."""
    if isinstance(entry, list):
        out: List[Tuple[Path, str]] = []
        for k, t in enumerate(entry):
            out += _term_sites(t, path + (k,))
        return out
    if isinstance(entry, dict):
        sites = [(path + ("coef",), "coefficient")]
        if "arg" in entry:
            sites.append((path + ("arg",), "argument"))
        return sites
    return [(path, "coefficient")]


def _number_sites(value: Json, path: Path, kind: str) -> List[Tuple[Path, str]]:
    """Sites of a number, vector or matrix (nested lists of numbers)."""
    if isinstance(value, list):
        out: List[Tuple[Path, str]] = []
        for k, v in enumerate(value):
            out += _number_sites(v, path + (k,), kind)
        return out
    return [(path, kind)]


def _exp_sites(key: str, value: Json, path: Path) -> List[Tuple[Path, str]]:
    """Sites of one key of an exponential tableau B(2.10): c numbers, A a matrix of
    coefficient functions, phi and b vectors of them, phi0 one."""
    if key == "c":
        return _number_sites(value, path, "coefficient")
    if key == "phi0":
        return _term_sites(value, path)
    out: List[Tuple[Path, str]] = []
    for i, v in enumerate(value):
        if key == "A":
            for j, e in enumerate(v):
                out += _term_sites(e, path + (i, j))
        else:
            out += _term_sites(v, path + (i,))
    return out


def sites(doc: Json) -> List[Tuple[Path, str]]:
    """Every mutation site of a method file, with its kind: coefficient (a number of the step
    map, or an exponential term's coef), argument (an exponential term's arg) or certificate (a
    GLM's G and D, read by the G-symplecticity check only)."""
    fam = doc["family"]
    out: List[Tuple[Path, str]] = []
    if fam in ("rk", "partitioned-rk", "exponential-rk", "partitioned-exponential-rk"):
        exp = fam.endswith("exponential-rk")
        for tab in ("tableau", "q", "p"):
            for key in ("c", "A", "phi", "b", "phi0"):
                if tab not in doc or key not in doc[tab]:
                    continue
                value, path = doc[tab][key], (tab, key)
                out += (_exp_sites(key, value, path) if exp
                        else _number_sites(value, path, "coefficient"))
    elif fam == "general-linear":
        for key in ("A", "U", "B", "V", "c", "G", "D"):
            if key in doc:
                kind = "certificate" if key in ("G", "D") else "coefficient"
                out += _number_sites(doc[key], (key,), kind)
        for key in ("A", "U", "B", "V", "c"):
            if key in doc.get("starting", {}):
                out += _number_sites(doc["starting"][key], ("starting", key), "coefficient")
    else:
        raise ValueError("unknown family " + str(fam))
    return out


def get_at(doc: Json, path: Path) -> Json:
    node = doc
    for k in path:
        if isinstance(node, dict) and k == "coef" and k not in node:
            return 1.0  # a term without coef has coef 1 (docs/method-files.md)
        node = node[k]
    return node


def mutate(doc: Json, path: Path, factor: float = FACTOR) -> Json:
    """A copy of doc with the number at path multiplied by factor."""
    out = copy.deepcopy(doc)
    node = out
    for k in path[:-1]:
        node = node[k]
    node[path[-1]] = float(get_at(doc, path)) * factor
    return out


def path_name(path: Path) -> str:
    return ".".join(str(k) for k in path)


def mutant_id(export_id: str, path: Path) -> str:
    return export_id + ".m." + path_name(path)


# ---- equivalent mutants ---------------------------------------------------------------------

# Coefficients no kernel reads, with the reason (each also has to pass the bitwise step test).
UNREAD: Dict[Tuple[str, str, str], str] = {
    ("partitioned-rk", "p", "c"):
        "the p tableau's c is never read: the partitioned engine integrates time with the q "
        "tableau's c (src/methods/partitioned_rk.hpp, docs/method-files.md)",
    ("partitioned-exponential-rk", "p", "c"):
        "the tilde tableau's c is never read: stage times use c-hat, c-tilde is B's printed "
        "column kept as data (src/methods/partitioned_exponential_rk.hpp, "
        "exponential_tableaux.hpp)",
}


def unread_reason(family: str, path: Path) -> Optional[str]:
    if len(path) >= 2:
        return UNREAD.get((family, str(path[0]), str(path[1])))
    return None


def step_cases(ids: Sequence[str], seed: int, count: int = 4) -> List[Json]:
    """Cases stepping each method a few steps from random states and start times on three
    problems: constant damping (pendulum), time-dependent forcing (driven pendulum: every stage
    time is read) and time-dependent damping (Hill)."""
    rng = random.Random(seed)
    problems = [{"id": "pendulum", "gamma": 0.1},
                {"id": "driven-pendulum", "gamma": 0.375, "lambda": 1.5, "f": 3.375},
                {"id": "hill", "epsilon": 0.5, "kappa": 1.0}]
    out = []
    for k in range(count):
        for p in problems:
            t0 = round(rng.uniform(0.0, 5.0), 6)
            dt = rng.choice([0.05, 0.2, 0.5])
            prob = dict(p, q0=rng.uniform(-2.0, 2.0), p0=rng.uniform(-2.0, 2.0))
            out.append({"id": "steps-%s-%d" % (p["id"], k), "problem": prob, "methods": list(ids),
                        "t0": t0, "t_end": t0 + 4 * dt, "dt": dt,
                        "no_checks_because": "the runs' final states are compared bit for bit"})
    return out


def final_states(report: Json) -> Dict[Tuple[str, str], List[float]]:
    out = {}
    for c in report["cases"]:
        for r in c["runs"]:
            out[(c["id"], r["method"])] = r["final_state"]
    return out


def bitwise_equal(a: Sequence[float], b: Sequence[float]) -> bool:
    """Equal as doubles, element by element (0.0 and -0.0 differ, as bits)."""
    import struct
    return len(a) == len(b) and all(struct.pack("<d", x) == struct.pack("<d", y)
                                    for x, y in zip(a, b))


def same_steps(states: Dict[Tuple[str, str], List[float]], a: str, b: str) -> List[str]:
    """The cases where methods a and b end in different states (empty: bit for bit the same)."""
    cases = sorted({c for c, _ in states})
    return [c for c in cases if not bitwise_equal(states[(c, a)], states[(c, b)])]


# ---- running dampsym ------------------------------------------------------------------------

class InputFailure(Exception):
    """dampsym refused an input (exit 2) or failed (exit 3 or a crash): the script's error."""


@dataclass
class Dampsym:
    binary: str
    cases_dir: str

    def call(self, args: Sequence[str], ok: Sequence[int] = (0, 1)) -> Tuple[int, str]:
        code, out, _ = self.call3(args, ok)
        return code, out

    def call3(self, args: Sequence[str], ok: Sequence[int]) -> Tuple[int, str, str]:
        """Exit status, stdout and stderr; InputFailure on any other status than `ok`."""
        p = subprocess.run([self.binary, "--cases", self.cases_dir] + list(args),
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if p.returncode not in ok:
            raise InputFailure("dampsym %s: exit %d: %s" % (" ".join(args), p.returncode,
                                                            p.stderr.strip()[-2000:]))
        return p.returncode, p.stdout, p.stderr

    def builtin_ids(self) -> List[str]:
        _, out = self.call(["methods", "--json"], ok=(0,))
        return [m["id"] for m in json.loads(out)["methods"]]

    def export(self, method: str, new_id: str) -> Tuple[Optional[Json], str]:
        """The method file of a built-in, or None and dampsym's reason if it has none."""
        code, out, err = self.call3(["methods", "--export", method, "--as", new_id], ok=(0, 2))
        return (json.loads(out), "") if code == 0 else (None, err.strip())

    def check_failures(self, path: str) -> List[str]:
        """Names of the coefficient checks that disagree with the declarations."""
        _, out = self.call(["methods", "--check", "--json", "--methods", path])
        rows = json.loads(out)["methods"]
        return sorted(c["name"] for r in rows for c in (r["checks"] or []) if not c["passed"])

    def matrix(self, path: str, method_id: str, out_dir: str) -> int:
        return self.call(["matrix", "--methods", path, "--method", method_id, "--out", out_dir,
                          "--quiet", "--jobs", "1"])[0]

    def cases(self, path: str, old: str, new: str, case_ids: Sequence[str], out_dir: str) -> int:
        return self.call(["run"] + list(case_ids) +
                         ["--methods", path, "--substitute", old + "=" + new, "--out", out_dir,
                          "--quiet", "--jobs", "1", "--time-budget", "0", "--shard", "none"])[0]

    def final_states(self, files: Sequence[str], ids: Sequence[str], tmp: str,
                     seed: int) -> Dict[Tuple[str, str], List[float]]:
        case_dir = os.path.join(tmp, "cases")
        os.makedirs(case_dir, exist_ok=True)
        paths = []
        for c in step_cases(ids, seed):
            paths.append(os.path.join(case_dir, c["id"] + ".json"))
            write_json(paths[-1], c)
        args = ["run"] + paths + ["--out", os.path.join(tmp, "out"), "--quiet", "--jobs", "1",
                                  "--time-budget", "0", "--shard", "none"]
        for path in files:
            args += ["--methods", path]
        self.call(args, ok=(0,))
        with open(os.path.join(tmp, "out", "report.json")) as f:
            return final_states(json.load(f))


def default_cases(cases_dir: str, method: str) -> List[str]:
    """Ids of the default-suite cases that name the method."""
    out = []
    for name in sorted(os.listdir(cases_dir)):
        if name.endswith(".json"):
            with open(os.path.join(cases_dir, name)) as f:
                c = json.load(f)
            if "default" in c.get("suites", []) and method in c.get("methods", []):
                out.append(c["id"])
    return out


# ---- one method: export, baseline, mutants --------------------------------------------------

@dataclass
class Mutant:
    method: str
    path: Path
    kind: str
    mid: str
    file: str
    killed_by: List[str] = field(default_factory=list)
    seconds: float = 0.0
    equivalent: Optional[str] = None  # the proof, if an equivalent mutant
    differs_in: List[str] = field(default_factory=list)


@dataclass
class Method:
    id: str
    family: str
    export_id: str
    export_file: str
    cases: List[str]
    baseline_checks: List[str] = field(default_factory=list)
    stages: List[str] = field(default_factory=list)  # the stages the baseline passes
    skipped_stages: Dict[str, str] = field(default_factory=dict)
    zero_sites: int = 0
    mutants: List[Mutant] = field(default_factory=list)


def write_json(path: str, doc: Json) -> None:
    with open(path, "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")


def prepare(d: Dampsym, method: str, doc: Json, out: str) -> Method:
    """The export on disk and its mutants' files; zero coefficients are counted, not mutated
    (0 x (1 + 1e-6) = 0: the file would be the export itself)."""
    export_id = doc["id"]
    m = Method(method, doc["family"], export_id, os.path.join(out, export_id + ".json"),
               default_cases(d.cases_dir, method))
    write_json(m.export_file, doc)
    for path, kind in sites(doc):
        if float(get_at(doc, path)) == 0.0:
            m.zero_sites += 1
            continue
        mid = mutant_id(export_id, path)
        mdoc = mutate(doc, path)
        mdoc["id"] = mid
        mdoc["citation"] = "mutant of %s: %s x (1 + 1e-6)" % (method, path_name(path))
        mfile = os.path.join(out, mid + ".json")
        write_json(mfile, mdoc)
        m.mutants.append(Mutant(method, path, kind, mid, mfile))
    return m


def run_stages(d: Dampsym, m: Method, file: str, mid: str, tmp: str,
               stages: Sequence[str], first_kill: bool) -> List[str]:
    """The stages (of `stages`) in which the method file `file` (method id `mid`) fails."""
    failed = []
    for stage in stages:
        if stage == "check":
            bad = d.check_failures(file)
            if set(bad) - set(m.baseline_checks):
                failed.append(stage)
        elif stage == "matrix":
            if d.matrix(file, mid, os.path.join(tmp, "matrix")) == 1:
                failed.append(stage)
        elif stage == "cases" and m.cases:
            if d.cases(file, m.id, mid, m.cases, os.path.join(tmp, "cases")) == 1:
                failed.append(stage)
        if failed and first_kill:
            break
    return failed


def baseline(d: Dampsym, m: Method, stages: Sequence[str]) -> None:
    """The stages the unmutated export passes; the others cannot kill its mutants."""
    m.baseline_checks = d.check_failures(m.export_file)
    with tempfile.TemporaryDirectory() as tmp:
        for stage in stages:
            if stage == "cases" and not m.cases:
                m.skipped_stages[stage] = "no default-suite case names the method"
                continue
            failed = run_stages(d, m, m.export_file, m.export_id, tmp, [stage], False)
            if failed:
                m.skipped_stages[stage] = "the unmutated export fails it"
            else:
                m.stages.append(stage)


def run_mutant(d: Dampsym, m: Method, mu: Mutant, first_kill: bool) -> Mutant:
    start = time.monotonic()
    with tempfile.TemporaryDirectory() as tmp:
        mu.killed_by = run_stages(d, m, mu.file, mu.mid, tmp, m.stages, first_kill)
    mu.seconds = time.monotonic() - start
    return mu


def prove_equivalent(d: Dampsym, m: Method, survivors: Sequence[Mutant], seed: int) -> None:
    """For each survivor: the cases where its steps differ from the export's (bit for bit on
    random states), and, if none and a rule says why the coefficient is unread, the proof."""
    if not survivors:
        return
    with tempfile.TemporaryDirectory() as tmp:
        files = [m.export_file] + [s.file for s in survivors]
        states = d.final_states(files, [m.export_id] + [s.mid for s in survivors], tmp, seed)
    for s in survivors:
        s.differs_in = same_steps(states, m.export_id, s.mid)
        reason = unread_reason(m.family, s.path)
        if not s.differs_in and reason:
            s.equivalent = ("steps bit for bit equal to the export's on %d random states, and %s"
                            % (len({c for c, _ in states}), reason))


# ---- scores and the report ------------------------------------------------------------------

def scores(methods: Sequence[Method]) -> Json:
    """Per kind: mutants, killed, proven equivalent, survivors, score = killed / (mutants -
    equivalent); per stage (coefficient mutants of the methods whose baseline passes it):
    killed by that stage / those mutants."""
    out: Json = {"kinds": {}, "stages": {}}
    all_mutants = [(m, mu) for m in methods for mu in m.mutants]
    for kind in ("coefficient", "argument", "certificate"):
        ms = [mu for _, mu in all_mutants if mu.kind == kind]
        killed = sum(1 for mu in ms if mu.killed_by)
        equiv = sum(1 for mu in ms if not mu.killed_by and mu.equivalent)
        denom = len(ms) - equiv
        out["kinds"][kind] = {"mutants": len(ms), "killed": killed, "equivalent": equiv,
                              "survivors": denom - killed,
                              "score": killed / denom if denom else 1.0}
    for stage in STAGES:
        ms = [mu for m, mu in all_mutants
              if mu.kind == "coefficient" and stage in m.stages and not mu.equivalent]
        killed = sum(1 for mu in ms if stage in mu.killed_by)
        out["stages"][stage] = {"mutants": len(ms), "killed": killed,
                                "score": killed / len(ms) if ms else None}
    return out


def exit_status(sc: Json) -> int:
    """1 if a coefficient mutant survives without a proof of equivalence, else 0."""
    return 0 if sc["kinds"]["coefficient"]["survivors"] == 0 else 1


def render(methods: Sequence[Method], sc: Json, unexportable: Dict[str, str]) -> str:
    lines = ["method  mutants  killed (check/matrix/cases)  equivalent  survivors  stages"]
    for m in methods:
        k = {s: sum(1 for mu in m.mutants if s in mu.killed_by) for s in STAGES}
        killed = sum(1 for mu in m.mutants if mu.killed_by)
        eq = sum(1 for mu in m.mutants if mu.equivalent)
        lines.append("%-26s %3d  %3d (%d/%d/%d)  %d  %d  %s%s" % (
            m.id, len(m.mutants), killed, k["check"], k["matrix"], k["cases"], eq,
            len(m.mutants) - killed - eq, ",".join(m.stages),
            "".join("; %s skipped: %s" % kv for kv in m.skipped_stages.items())))
    for kind, s in sc["kinds"].items():
        lines.append("%s mutants: %d, killed %d, proven equivalent %d, survivors %d: score "
                     "%.1f %%" % (kind, s["mutants"], s["killed"], s["equivalent"],
                                  s["survivors"], 100.0 * s["score"]))
    for stage, s in sc["stages"].items():
        lines.append("stage %s: kills %d of %d coefficient mutants%s" % (
            stage, s["killed"], s["mutants"],
            "" if s["score"] is None else " (%.1f %%)" % (100.0 * s["score"])))
    for m in methods:
        for mu in m.mutants:
            if mu.equivalent:
                lines.append("equivalent %s: %s" % (mu.mid, mu.equivalent))
            elif not mu.killed_by:
                lines.append("SURVIVOR %s (%s): steps %s" % (
                    mu.mid, mu.kind, "differ in " + ", ".join(mu.differs_in[:3]) + " ..."
                    if mu.differs_in else "bit for bit equal, but no rule proves it unread"))
    for method, why in sorted(unexportable.items()):
        lines.append("not exported: %s (%s)" % (method, why))
    return "\n".join(lines) + "\n"


def as_json(methods: Sequence[Method], sc: Json, unexportable: Dict[str, str]) -> Json:
    return {"factor": FACTOR, "scores": sc, "unexportable": unexportable,
            "methods": [{"id": m.id, "family": m.family, "cases": m.cases, "stages": m.stages,
                         "skipped_stages": m.skipped_stages, "zero_coefficients": m.zero_sites,
                         "baseline_check_failures": m.baseline_checks,
                         "mutants": [{"id": mu.mid, "site": path_name(mu.path), "kind": mu.kind,
                                      "killed_by": mu.killed_by, "equivalent": mu.equivalent,
                                      "differs_in": mu.differs_in,
                                      "seconds": round(mu.seconds, 3)} for mu in m.mutants]}
                        for m in methods]}


# ---- main -----------------------------------------------------------------------------------

def parallel(fn: Callable[[Any], Any], items: Sequence[Any], jobs: int) -> List[Any]:
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        return list(pool.map(fn, items))


def exports(d: Dampsym, only: Sequence[str]) -> Tuple[Dict[str, Json], Dict[str, str]]:
    """The method files of the built-ins (all, or `only`), and the built-ins that have none."""
    ids = d.builtin_ids()
    for m in only:
        if m not in ids:
            raise InputFailure("--method: '%s' is not a built-in method" % m)
    docs, unexportable = {}, {}
    for m in (only or ids):
        doc, why = d.export(m, m + ".x")
        if doc is None:
            unexportable[m] = why
        else:
            docs[m] = doc
    return docs, unexportable


def roundtrip(d: Dampsym, docs: Dict[str, Json], out: str, seed: int) -> int:
    """Every export steps bit for bit like its built-in on random states; 1 if one does not.
    Negative control: each export with its first non-zero coefficient x (1 + 1e-6) must differ
    (otherwise the comparison could not fail, e.g. on empty final states)."""
    files, controls = [], {}
    for m, doc in docs.items():
        site = next(p for p, k in sites(doc) if k == "coefficient" and get_at(doc, p) != 0.0)
        control = mutate(doc, site)
        control["id"] = controls[m] = doc["id"] + ".control"
        for d_ in (doc, control):
            files.append(os.path.join(out, d_["id"] + ".json"))
            write_json(files[-1], d_)
    ids = list(docs) + [doc["id"] for doc in docs.values()] + list(controls.values())
    with tempfile.TemporaryDirectory() as tmp:
        states = d.final_states(files, ids, tmp, seed)
    status = 0
    for m, doc in docs.items():
        bad = same_steps(states, m, doc["id"])
        seen = same_steps(states, m, controls[m])
        print("%-26s %s; control x (1 + 1e-6) differs in %d of %d cases" % (
            m, "bit for bit" if not bad else "DIFFERS in " + ", ".join(bad), len(seen),
            len({c for c, _ in states})))
        status = status or (1 if bad or not seen else 0)
    return status


def mutation_run(d: Dampsym, docs: Dict[str, Json], args: argparse.Namespace) -> List[Method]:
    methods = [prepare(d, m, doc, args.out) for m, doc in docs.items()]
    stages = [s for s in STAGES if s not in args.skip_stage]
    parallel(lambda m: baseline(d, m, stages), methods, args.jobs)
    work = [(m, mu) for m in methods for mu in m.mutants]
    done = [0]

    def one(item: Tuple[Method, Mutant]) -> Mutant:
        mu = run_mutant(d, item[0], item[1], args.first_kill)
        done[0] += 1
        if not args.quiet:
            print("[%d/%d] %s: %s (%.1f s)" % (done[0], len(work), mu.mid,
                                              ",".join(mu.killed_by) or "survived", mu.seconds),
                  file=sys.stderr)
        return mu

    parallel(one, work, args.jobs)
    for m in methods:
        prove_equivalent(d, m, [mu for mu in m.mutants if not mu.killed_by], args.seed)
    return methods


def parse_args(argv: Sequence[str]) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--dampsym", default=os.path.join(ROOT, "build", "dampsym"))
    p.add_argument("--cases", default=os.path.join(ROOT, "verify", "cases"))
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--method", action="append", default=[], help="only this built-in")
    p.add_argument("--out", default=os.path.join(ROOT, "build", "mutants"))
    p.add_argument("--seed", type=int, default=20261127)
    p.add_argument("--skip-stage", action="append", default=[], choices=STAGES)
    p.add_argument("--first-kill", action="store_true",
                   help="stop at a mutant's first killing stage (faster; per-stage scores then "
                        "count first kills only)")
    p.add_argument("--roundtrip", action="store_true",
                   help="only check that every export steps bit for bit like its built-in")
    p.add_argument("--quiet", action="store_true")
    a = p.parse_args(argv)
    if a.jobs < 1:
        p.error("--jobs: must be at least 1")
    if not os.access(a.dampsym, os.X_OK):
        p.error("--dampsym: %s is not an executable" % a.dampsym)
    return a


def main(argv: Sequence[str]) -> int:
    args = parse_args(argv)
    d = Dampsym(args.dampsym, args.cases)
    os.makedirs(args.out, exist_ok=True)
    start = time.monotonic()
    try:
        docs, unexportable = exports(d, args.method)
        if args.roundtrip:
            return roundtrip(d, docs, args.out, args.seed)
        methods = mutation_run(d, docs, args)
    except InputFailure as e:
        print("ci/mutants.py: " + str(e), file=sys.stderr)
        return 2
    sc = scores(methods)
    doc = as_json(methods, sc, unexportable)
    doc["seconds"] = round(time.monotonic() - start, 1)
    write_json(os.path.join(args.out, "results.json"), doc)
    print(render(methods, sc, unexportable) + "%.0f s, %d jobs; details: %s" % (
        doc["seconds"], args.jobs, os.path.join(args.out, "results.json")))
    return exit_status(sc)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
