#!/usr/bin/python3
"""Unit tests of ci/source_mutants.py's logic (no build, no dampsym binary): the mutant list
(every find of ci/source_mutants.json occurs exactly once in the sources, so the list fails here
as soon as the code it mutates changes), bad input naming the file and key, apply and revert,
what killed a mutant (failed checks of a report, disagreements of a cross-check), the scores and
the table. Runs in well under a second (unittest; pytest collects it too)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import unittest
from typing import Any, Dict, List

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import source_mutants as sm  # noqa: E402

GOOD: Dict[str, str] = {"id": "m1", "file": "a.cpp", "find": "x <= y", "replace": "x < y",
                        "class": "check operator", "breaks": "ties fail"}


def _write(d: str, name: str, doc: Any) -> str:
    path = os.path.join(d, name)
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(doc if isinstance(doc, str) else json.dumps(doc))
    return path


class TheList(unittest.TestCase):
    def test_every_find_exactly_once_in_the_sources(self) -> None:
        mutants = sm.load_mutants(os.path.join(sm.ROOT, "ci", "source_mutants.json"))
        self.assertGreaterEqual(len(mutants), 15)
        sm.check_finds(sm.ROOT, mutants)          # raises BadInput on 0 or >= 2 occurrences
        kinds = {m.kind for m in mutants}
        self.assertEqual(kinds, {"cpp", "python"})
        # headers (a full rebuild each, ~10 min) are few and come last
        headers = [k for k, m in enumerate(mutants) if m.header]
        self.assertLessEqual(len(headers), 6)
        self.assertEqual(headers, list(range(len(mutants) - len(headers), len(mutants))))


class BadInputs(unittest.TestCase):
    def _bad(self, doc: Any, words: List[str]) -> None:
        with tempfile.TemporaryDirectory() as d:
            path = _write(d, "list.json", doc)
            with self.assertRaises(sm.BadInput) as e:
                sm.load_mutants(path)
            for w in [path] + words:
                self.assertIn(w, str(e.exception))

    def test_keys(self) -> None:
        self._bad("{", [])
        self._bad({"mutant": []}, ["'mutants'"])
        self._bad({"mutants": [dict(GOOD, find="")]}, ["mutants[0].find"])
        self._bad({"mutants": [{k: v for k, v in GOOD.items() if k != "class"}]},
                  ["mutants[0].class"])
        self._bad({"mutants": [dict(GOOD, extra="1")]}, ["'extra'"])
        self._bad({"mutants": [GOOD, GOOD]}, ["mutants[1].id", "twice"])
        self._bad({"mutants": [dict(GOOD, replace=GOOD["find"])]}, ["mutants[0].replace"])

    def test_find_must_occur_exactly_once(self) -> None:
        with tempfile.TemporaryDirectory() as d:
            m = sm.load_mutants(_write(d, "l.json", {"mutants": [GOOD]}))
            for text, n in (("nothing", 0), ("x <= y; x <= y", 2)):
                _write(d, "a.cpp", text)
                with self.assertRaises(sm.BadInput) as e:
                    sm.check_finds(d, m)
                self.assertIn("occurs %d times in a.cpp" % n, str(e.exception))
            _write(d, "a.cpp", "return x <= y;")
            sm.check_finds(d, m)

    def test_unknown_only_is_exit_2(self) -> None:
        self.assertEqual(sm.main(["--only", "no-such-mutant", "--check-only"]), 2)


class ApplyRevert(unittest.TestCase):
    def test_round_trip(self) -> None:
        with tempfile.TemporaryDirectory() as d:
            m = sm.Mutant("m1", "a.cpp", "x <= y", "x < y", "op", "ties")
            _write(d, "a.cpp", "if (x <= y) return;\n")
            original = sm.apply(d, m)
            with open(os.path.join(d, "a.cpp"), encoding="utf-8") as fh:
                self.assertEqual(fh.read(), "if (x < y) return;\n")
            sm.revert(d, m, original)
            with open(os.path.join(d, "a.cpp"), encoding="utf-8") as fh:
                self.assertEqual(fh.read(), "if (x <= y) return;\n")
            self.assertEqual(m.kind, "cpp")
            self.assertFalse(m.header)
            self.assertEqual(sm.Mutant("p", "verify/x.py", "a", "b", "c", "d").kind, "python")


class WhatKilled(unittest.TestCase):
    def test_failed_checks(self) -> None:
        report = {"cases": [{"id": "c1", "checks": [
            {"name": "ok", "method": "rk4", "dt": 0.1, "passed": True},
            {"name": "bad", "method": "rk4", "dt": 0.1, "passed": False},
            {"name": "not run", "method": "csv1", "dt": None, "passed": None}]}]}
        with tempfile.TemporaryDirectory() as d:
            self.assertEqual(sm.failed_checks(_write(d, "r.json", report)),
                             ["c1: bad [rk4, dt=0.1]"])
            report["cases"].append({"id": "c2: x", "checks": [
                {"name": "bad", "method": "rk3", "dt": 0.2, "passed": False},
                {"name": "worse [sic]", "method": "rk3", "dt": 0.2, "passed": False}]})
            self.assertEqual(sm.failed_names(_write(d, "r.json", report)),
                             ["bad ×2", "worse [sic] ×1"])
            self.assertEqual(sm.failed_checks(os.path.join(d, "missing.json")), [])

    def test_disagreements(self) -> None:
        cmp_ok = {"quantity": "dt", "status": "agree"}
        xc = {"structure": [], "orders": [], "checks": [],
              "runs": [{"case": "c", "method": "m", "dt": 0.1, "verdict": "agree",
                        "comparisons": [cmp_ok]},
                       {"case": "c", "method": "m", "dt": 0.2, "verdict": "disagree",
                        "comparisons": [cmp_ok, {"quantity": "final_state",
                                                 "status": "disagree"}]},
                       {"case": "d", "method": "m", "verdict": "not reproduced",
                        "comparisons": []}]}
        with tempfile.TemporaryDirectory() as d:
            self.assertEqual(sm.disagreements(_write(d, "x.json", xc)),
                             ["runs c/m/0.2: final_state", "runs d/m: not reproduced"])
            self.assertEqual(sm.disagree_quantities(os.path.join(d, "x.json")), ["final_state ×1"])


def _git(d: str, *args: str) -> str:
    env = dict(os.environ, GIT_AUTHOR_NAME="t", GIT_AUTHOR_EMAIL="t@t", GIT_COMMITTER_NAME="t",
               GIT_COMMITTER_EMAIL="t@t")
    return subprocess.run(["git", "-C", d] + list(args), env=env, check=True,
                          capture_output=True, text=True).stdout.strip()


class KeptBaseline(unittest.TestCase):
    def test_only_ci_and_docs_may_differ(self) -> None:
        with tempfile.TemporaryDirectory() as d:
            repo, out = os.path.join(d, "r"), os.path.join(d, "out")
            for sub in ("r/src", "r/ci", "out"):
                os.makedirs(os.path.join(d, sub))
            _git(d, "init", "-q", repo)
            _write(repo, "src/a.cpp", "1")
            _write(repo, "ci/m.json", "1")
            _git(repo, "add", "-A")
            _git(repo, "commit", "-qm", "a")
            a = _git(repo, "rev-parse", "HEAD")
            self.assertFalse(sm.kept_baseline(repo, out, a))       # no marker, no report
            _write(out, "report.json", "{}")
            _write(out, "clean", a + "\n")
            self.assertTrue(sm.kept_baseline(repo, out, a))
            _write(repo, "ci/m.json", "2")
            _git(repo, "commit", "-qam", "b")
            self.assertTrue(sm.kept_baseline(repo, out, _git(repo, "rev-parse", "HEAD")))
            _write(repo, "src/a.cpp", "2")
            _git(repo, "commit", "-qam", "c")
            self.assertFalse(sm.kept_baseline(repo, out, _git(repo, "rev-parse", "HEAD")))


def _o(i: str, kind: str = "cpp", suite: bool = True, xc: bool = True,
       valid: bool = True) -> sm.Outcome:
    return sm.Outcome(i, kind, "k", "f", "b", valid=valid,
                      suite_killed=None if kind == "python" else suite, xc_killed=xc)


class Scores(unittest.TestCase):
    def test_denominators_and_survivors(self) -> None:
        out = [_o("a"), _o("b", suite=False), _o("c", xc=False), _o("d", valid=False),
               _o("p1", "python"), _o("p2", "python", xc=False)]
        s = sm.scores(out)
        self.assertEqual(s["valid_cpp"], 3)                    # invalid and Python excluded
        self.assertEqual((s["suite_killed"], s["crosscheck_killed"]), (2, 2))
        self.assertAlmostEqual(s["suite_score"], 2 / 3)
        self.assertEqual(s["either_killed"], 3)
        self.assertEqual(s["invalid"], ["d"])
        self.assertEqual(s["suite_survivors"], ["b"])
        self.assertEqual(s["crosscheck_survivors"], ["c", "p2"])
        self.assertEqual((s["python_mutants"], s["python_crosscheck_killed"]), (2, 1))
        md = sm.markdown(out, s, "0123456789abcdef")
        self.assertIn("Default suite: 2 of 3 valid C++ mutants killed (66.7 %)", md)
        self.assertIn("## Cross-check mutants (Python)", md)
        self.assertIn("| b | k | f | **survived** |", md)

    def test_equivalent_on_the_suite(self) -> None:
        e = _o("e", suite=False, xc=False)
        e.same_as_baseline = True
        k = _o("k")
        k.same_as_baseline = False
        s = sm.scores([e, k])
        self.assertEqual((s["valid_cpp"], s["equivalent_on_suite"]), (1, ["e"]))
        self.assertEqual((s["suite_survivors"], s["crosscheck_survivors"]), ([], []))
        self.assertIn("| e | k | f | equivalent on the suite | — | equivalent on the "
                      "suite |", sm.markdown([e, k], s, "x"))

    def test_same_results_ignores_only_clocks(self) -> None:
        base = {"cases": [{"id": "c", "runs": [{"final_state": [0.1, 0.2]}]}],
                "provenance": {"start_utc": "a"}, "timings": {"wall_seconds": 1.0}}
        with tempfile.TemporaryDirectory() as d:
            a = _write(d, "a.json", base)
            clocks = dict(base, provenance={"start_utc": "b"}, timings={"wall_seconds": 2.0})
            self.assertTrue(sm.same_results(a, _write(d, "b.json", clocks)))
            one_ulp = [0.1, 0.20000000000000004]                  # 0.2 + 1 ulp
            moved = dict(base, cases=[{"id": "c", "runs": [{"final_state": one_ulp}]}])
            self.assertFalse(sm.same_results(a, _write(d, "c.json", moved)))
            self.assertFalse(sm.same_results(a, os.path.join(d, "missing.json")))

    def test_empty_is_not_applicable(self) -> None:
        s = sm.scores([])
        self.assertIsNone(s["suite_score"])
        self.assertIn("(n/a)", sm.markdown([], s, "x"))


if __name__ == "__main__":
    unittest.main()
