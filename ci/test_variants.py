#!/usr/bin/python3
"""Unit tests of ci/variants.py's logic (no dampsym binary): which variants a case gets, their ids
and shapes, the divisibility rule, and the verdict (a planted disagreement or not-reproduced item
is exit 1). Runs in well under a second (unittest; pytest collects it too)."""

from __future__ import annotations

import os
import sys
import unittest
from typing import Any, Dict

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import variants as vr  # noqa: E402

CASE: Dict[str, Any] = {"id": "c", "suites": ["default"], "problem": {"id": "pendulum"}, "methods": ["cimp"],
                        "t_end": 2.0, "dt": 0.1, "diagnostics": ["error"]}


def summary(**bad: int) -> Dict[str, Any]:
    out = {k: {"agree": 3, "disagree": 0, "not comparable": 1, "not reproduced": 0}
           for k in ("structure", "runs", "orders", "checks")}
    for k, n in bad.items():
        group, kind = k.split("__")
        out[group][kind.replace("_", " ")] = n
    return out


class Variants(unittest.TestCase):
    def test_three_shapes(self) -> None:
        v = {x["id"]: x for x in vr.variants(CASE, 200000)}
        self.assertEqual(sorted(v), ["c-ladder", "c-odt", "c-t0"])
        self.assertEqual(v["c-ladder"]["dt_ladder"], [0.2, 0.1])
        self.assertNotIn("dt", v["c-ladder"])
        self.assertEqual(v["c-odt"]["output_dt"], 0.2)
        self.assertEqual((v["c-t0"]["t0"], v["c-t0"]["t_end"]), (0.5, 2.5))
        self.assertTrue(all(x["suites"] == ["variants"] for x in v.values()))
        self.assertEqual(CASE["dt"], 0.1)  # the case itself is not changed

    def test_left_out(self) -> None:
        odd = dict(CASE, t_end=2.1)        # 2 dt = 0.2 does not divide 2.1
        self.assertEqual([x["id"] for x in vr.variants(odd, 200000)], ["c-t0"])
        self.assertEqual([x["id"] for x in vr.variants(CASE, 10)], ["c-t0"])   # too many steps
        graded = dict(CASE, output_dt=0.5)
        self.assertEqual([x["id"] for x in vr.variants(graded, 200000)], ["c-t0"])
        self.assertEqual(vr.variants(dict(CASE, method_files=["m.json"]), 200000), [])
        self.assertEqual(vr.variants(dict(CASE, stability_sweep={}), 200000), [])

    def test_divides(self) -> None:
        self.assertTrue(vr.divides(2.0, 0.2) and vr.divides(100.0, 0.125))
        self.assertFalse(vr.divides(2.1, 0.2))

    def test_verdict(self) -> None:
        self.assertEqual(vr.verdict(summary()), 0)
        self.assertEqual(vr.verdict(summary(runs__disagree=1)), 1)
        self.assertEqual(vr.verdict(summary(checks__not_reproduced=1)), 1)


if __name__ == "__main__":
    unittest.main()
