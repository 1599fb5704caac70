#!/usr/bin/python3
"""Unit tests of ci/mutants.py's logic (no dampsym binary): mutation sites of every family,
mutate, ids, the bitwise comparison (a planted 1-ulp difference and -0.0 are seen), the kill
decision against the baseline's check failures, the unread rules, the scores and the exit status.
Runs in well under a second (unittest; pytest collects it too)."""

from __future__ import annotations

import math
import os
import sys
import unittest
from typing import Any, Dict, List, Sequence

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mutants as mt  # noqa: E402

RK: Dict[str, Any] = {"id": "rk.x", "family": "rk", "order": 2,
      "tableau": {"A": [[0.0, 0.0], [1.0, 0.0]], "b": [0.5, 0.5], "c": [0.0, 1.0]}}
PERK: Dict[str, Any] = {"id": "p.x", "family": "partitioned-exponential-rk", "order": 1,
        "q": {"c": [0], "A": [[0]], "phi": [1], "b": [1], "phi0": 1},
        "p": {"c": [1], "A": [[{"phi": "phi1", "arg": -1}]],
              "phi": [{"phi": "exp", "arg": -1}],
              "b": [[{"coef": 0.5, "phi": "exp", "arg": -0.5}, 0.25]],
              "phi0": {"phi": "exp", "arg": -1}}}
GLM: Dict[str, Any] = {"id": "g.x", "family": "general-linear", "order": 1, "A": [[0.5]], "U": [[1.0]],
       "B": [[1.0]], "V": [[1.0]], "c": [0.5], "G": [[1.0]], "D": [[0.5]],
       "starting": {"V": [1.0]}}


class Sites(unittest.TestCase):
    def test_rk(self) -> None:
        s = mt.sites(RK)
        self.assertEqual(len(s), 8)  # 4 + 2 + 2
        self.assertIn((("tableau", "A", 1, 0), "coefficient"), s)
        self.assertTrue(all(k == "coefficient" for _, k in s))

    def test_exponential_terms(self) -> None:
        s = dict(mt.sites(PERK))
        self.assertEqual(s[("p", "A", 0, 0, "coef")], "coefficient")  # coef absent: 1
        self.assertEqual(s[("p", "A", 0, 0, "arg")], "argument")
        self.assertEqual(s[("p", "b", 0, 0, "coef")], "coefficient")  # a sum of two terms
        self.assertEqual(s[("p", "b", 0, 1)], "coefficient")           # its constant term
        self.assertEqual(s[("p", "phi0", "coef")], "coefficient")
        self.assertEqual(s[("q", "phi0",)], "coefficient")              # a constant
        self.assertEqual(s[("p", "c", 0)], "coefficient")
        self.assertEqual(len(s), 5 + 10)

    def test_glm_certificate_and_starting(self) -> None:
        s = dict(mt.sites(GLM))
        self.assertEqual(s[("G", 0, 0)], "certificate")
        self.assertEqual(s[("D", 0, 0)], "certificate")
        self.assertEqual(s[("starting", "V", 0)], "coefficient")
        self.assertEqual(len(s), 8)

    def test_unknown_family(self) -> None:
        with self.assertRaises(ValueError):
            mt.sites({"family": "hand-written"})


class Mutate(unittest.TestCase):
    def test_one_number_changes(self) -> None:
        m = mt.mutate(RK, ("tableau", "b", 1))
        self.assertEqual(m["tableau"]["b"], [0.5, 0.5 * (1 + 1e-6)])
        self.assertEqual(RK["tableau"]["b"], [0.5, 0.5])  # the original is untouched
        self.assertEqual(m["tableau"]["A"], RK["tableau"]["A"])

    def test_absent_coef_is_one(self) -> None:
        m = mt.mutate(PERK, ("p", "A", 0, 0, "coef"))
        self.assertEqual(m["p"]["A"][0][0], {"phi": "phi1", "arg": -1, "coef": 1 + 1e-6})
        self.assertEqual(mt.get_at(PERK, ("p", "A", 0, 0, "coef")), 1.0)

    def test_ids_are_method_ids(self) -> None:
        i = mt.mutant_id("csv1-perk.x", ("p", "b", 0, "coef"))
        self.assertEqual(i, "csv1-perk.x.m.p.b.0.coef")
        self.assertTrue(all(ch.isalnum() or ch in "._-" for ch in i))


class Bitwise(unittest.TestCase):
    def test_planted_ulp_and_signed_zero(self) -> None:
        a = [0.1, -2.5, 0.0]
        self.assertTrue(mt.bitwise_equal(a, list(a)))
        self.assertFalse(mt.bitwise_equal(a, [math.nextafter(0.1, 1.0), -2.5, 0.0]))
        self.assertFalse(mt.bitwise_equal(a, [0.1, -2.5, -0.0]))
        self.assertFalse(mt.bitwise_equal(a, a[:2]))

    def test_same_steps_names_the_cases(self) -> None:
        st = {("c1", "a"): [1.0], ("c1", "b"): [1.0], ("c2", "a"): [2.0],
              ("c2", "b"): [2.0 + 4e-16]}
        self.assertEqual(mt.same_steps(st, "a", "b"), ["c2"])

    def test_step_cases(self) -> None:
        cs = mt.step_cases(["x", "y"], seed=1, count=2)
        self.assertEqual(len(cs), 6)
        self.assertEqual({c["problem"]["id"] for c in cs}, {"pendulum", "driven-pendulum", "hill"})
        self.assertEqual(cs, mt.step_cases(["x", "y"], seed=1, count=2))  # reproducible
        self.assertNotEqual(cs, mt.step_cases(["x", "y"], seed=2, count=2))
        self.assertTrue(all(c["t_end"] > c["t0"] for c in cs))


class FakeDampsym(mt.Dampsym):
    """check_failures from a table; matrix and cases exit 1 for ids in `fail`."""

    def __init__(self, checks: Dict[str, List[str]], fail: Dict[str, Sequence[str]]) -> None:
        super().__init__("true", ".")
        self.checks, self.fail = checks, fail

    def check_failures(self, path: str) -> List[str]:
        return self.checks[os.path.basename(path)]

    def matrix(self, path: str, method_id: str, out_dir: str) -> int:
        return 1 if "matrix" in self.fail.get(method_id, ()) else 0

    def cases(self, path: str, old: str, new: str, case_ids: Sequence[str], out_dir: str) -> int:
        return 1 if "cases" in self.fail.get(new, ()) else 0


class Kill(unittest.TestCase):
    def method(self) -> mt.Method:
        m = mt.Method("cse-etd", "partitioned-exponential-rk", "e.x", "e.x.json", ["cs-pendulum"])
        m.baseline_checks = ["conformal-condition"]  # B(2.23) is sufficient, not necessary
        m.stages = list(mt.STAGES)
        return m

    def test_only_a_new_check_failure_kills(self) -> None:
        d = FakeDampsym({"same.json": ["conformal-condition"],
                         "new.json": ["conformal-condition", "conformal-factor"]}, {})
        m = self.method()
        self.assertEqual(mt.run_stages(d, m, "same.json", "same", "/tmp", ["check"], False), [])
        self.assertEqual(mt.run_stages(d, m, "new.json", "new", "/tmp", ["check"], False),
                         ["check"])

    def test_every_stage_or_first_kill(self) -> None:
        d = FakeDampsym({"k.json": ["order-3"]}, {"k": ["matrix", "cases"]})
        m = self.method()
        self.assertEqual(mt.run_stages(d, m, "k.json", "k", "/tmp", mt.STAGES, False),
                         ["check", "matrix", "cases"])
        self.assertEqual(mt.run_stages(d, m, "k.json", "k", "/tmp", mt.STAGES, True), ["check"])

    def test_baseline_skips_a_failing_stage(self) -> None:
        d = FakeDampsym({"e.x.json": []}, {"e.x": ["matrix"]})
        m = mt.Method("cse-etd", "partitioned-exponential-rk", "e.x", "e.x.json", [])
        mt.baseline(d, m, mt.STAGES)
        self.assertEqual(m.stages, ["check"])
        self.assertIn("matrix", m.skipped_stages)
        self.assertIn("cases", m.skipped_stages)  # no case names it


class Scores(unittest.TestCase):
    def test_scores_and_survivors(self) -> None:
        m = mt.Method("r", "partitioned-rk", "r.x", "r.x.json", [])
        m.stages = ["check", "matrix"]
        m.mutants = [mt.Mutant("r", ("q", "b", 0), "coefficient", "a", "a", ["check", "matrix"]),
                     mt.Mutant("r", ("q", "b", 1), "coefficient", "b", "b", ["matrix"]),
                     mt.Mutant("r", ("p", "c", 0), "coefficient", "c", "c", [], 0.0, "proof"),
                     mt.Mutant("r", ("q", "c", 0), "coefficient", "d", "d", [])]
        sc = mt.scores([m])
        k = sc["kinds"]["coefficient"]
        self.assertEqual((k["mutants"], k["killed"], k["equivalent"], k["survivors"]),
                         (4, 2, 1, 1))
        self.assertAlmostEqual(k["score"], 2 / 3)
        self.assertEqual(sc["stages"]["check"], {"mutants": 3, "killed": 1, "score": 1 / 3})
        self.assertEqual(sc["stages"]["cases"]["score"], None)  # no case: stage not used
        text = mt.render([m], sc, {"csv1": "hand-written"})
        self.assertIn("SURVIVOR d", text)
        self.assertIn("equivalent c: proof", text)
        self.assertIn("not exported: csv1", text)

    def test_unread_rules(self) -> None:
        self.assertIsNotNone(mt.unread_reason("partitioned-rk", ("p", "c", 0)))
        self.assertIsNotNone(mt.unread_reason("partitioned-exponential-rk", ("p", "c", 1)))
        self.assertIsNone(mt.unread_reason("partitioned-rk", ("q", "c", 0)))  # read: stage times
        self.assertIsNone(mt.unread_reason("rk", ("tableau", "c", 0)))


def _status_with(kind: str, killed: bool, equivalent: bool = False) -> int:
    m = mt.Method("r", "rk", "r.x", "r.x.json", [])
    m.mutants = [mt.Mutant("r", ("tableau", "b", 0), kind, "a", "a", ["check"] if killed else [],
                           0.0, "proof" if equivalent else None)]
    return mt.exit_status(mt.scores([m]))


class ExitStatus(unittest.TestCase):
    def test_survivor_fails(self) -> None:
        self.assertEqual(_status_with("coefficient", killed=True), 0)
        self.assertEqual(_status_with("coefficient", killed=False), 1)
        self.assertEqual(_status_with("coefficient", killed=False, equivalent=True), 0)
        self.assertEqual(_status_with("argument", killed=False), 0)  # reported, not failed

    def test_bad_binary_is_usage_error(self) -> None:
        with self.assertRaises(SystemExit) as e:
            mt.parse_args(["--dampsym", "/nonexistent/dampsym"])
        self.assertEqual(e.exception.code, 2)


if __name__ == "__main__":
    unittest.main()
