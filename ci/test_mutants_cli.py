#!/usr/bin/python3
"""CLI tests of what ci/mutants.py stands on: `dampsym methods --export ID --as NEW` and
`dampsym run --substitute OLD=NEW` (docs/method-files.md, docs/case-keys.md). Bad values exit 2
naming the option; the export is a valid method file that passes the built-in's case, and the
same export with one coefficient multiplied by (1 + 1e-6) fails it (glifrk2's a_11 on
cs-oscillator: E_n about 1e-7 against the 1e-13 bound), so the substitution really runs the file's
method. A few seconds.

    test_mutants_cli.py DAMPSYM WORKDIR
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import unittest
from typing import List, Tuple

BINARY = ""
WORK = ""


def dampsym(*args: str) -> Tuple[int, str, str]:
    p = subprocess.run([BINARY] + list(args), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                       text=True)
    return p.returncode, p.stdout, p.stderr


def write(name: str, doc: object) -> str:
    path = os.path.join(WORK, name)
    with open(path, "w") as f:
        json.dump(doc, f)
    return path


class Export(unittest.TestCase):
    def test_bad_values_exit_2_naming_the_option(self) -> None:
        cases: List[Tuple[List[str], str]] = [
            (["--export", "no-such-method", "--as", "x"], "--export"),
            (["--export", "csv1", "--as", "x"], "--export"),          # hand-written
            (["--export", "csv2-perk", "--as", "x"], "--export"),     # no vocabulary term
            (["--export", "rk4"], "--as"),                            # id missing
            (["--export", "rk4", "--as", "rk3"], "--as"),             # a built-in id
            (["--export", "rk4", "--as", "bad id!"], "--as"),
        ]
        for args, option in cases:
            code, _, err = dampsym("methods", *args)
            self.assertEqual(code, 2, args)
            self.assertIn(option, err, args)

    def test_export_is_a_method_file_with_the_declarations(self) -> None:
        code, out, _ = dampsym("methods", "--export", "glm4", "--as", "glm4-e")
        self.assertEqual(code, 0)
        doc = json.loads(out)
        self.assertEqual((doc["id"], doc["family"], doc["order"]),
                         ("glm4-e", "general-linear", 4))
        self.assertEqual(doc["claims"], ["g-symplectic"])
        self.assertEqual(len(doc["starting"]["A"]), 2)
        path = write("glm4-e.json", doc)
        self.assertEqual(dampsym("methods", "--check", "--methods", path)[0], 0)


class Substitute(unittest.TestCase):
    def export_pair(self) -> Tuple[str, str]:
        code, out, _ = dampsym("methods", "--export", "glifrk2", "--as", "glifrk2-e")
        self.assertEqual(code, 0)
        doc = json.loads(out)
        good = write("glifrk2-e.json", doc)
        doc["id"] = "glifrk2-m"
        doc["tableau"]["A"][0][0] *= 1.0 + 1e-6
        return good, write("glifrk2-m.json", doc)

    def test_bad_values_exit_2_naming_the_option(self) -> None:
        good, _ = self.export_pair()
        for sub in ["glifrk2", "glifrk2=", "=glifrk2-e", "glifrk2=glifrk2", "glifrk2=nope",
                    "stormer-verlet=glifrk2-e"]:  # the last: cs-oscillator has no stormer-verlet
            code, _, err = dampsym("run", "cs-oscillator", "--methods", good, "--substitute",
                                   sub, "--out", os.path.join(WORK, "bad"), "-q")
            self.assertEqual(code, 2, sub)
            self.assertIn("--substitute", err, sub)

    def test_the_file_method_runs_the_case_and_a_mutant_fails_it(self) -> None:
        good, mutant = self.export_pair()
        out = os.path.join(WORK, "good")
        code, _, err = dampsym("run", "cs-oscillator", "--methods", good, "--substitute",
                               "glifrk2=glifrk2-e", "--out", out, "-q", "--time-budget", "0")
        self.assertEqual(code, 0, err)
        with open(os.path.join(out, "report.json")) as f:
            case = json.load(f)["cases"][0]
        self.assertEqual(case["overrides"], {"substitute": {"glifrk2": "glifrk2-e"}})
        self.assertIn("glifrk2-e", case["methods"])
        self.assertNotIn("glifrk2", case["methods"])
        self.assertTrue(any("glifrk2-e" in json.dumps(c) for c in case["checks"]))
        code, _, _ = dampsym("run", "cs-oscillator", "--methods", mutant, "--substitute",
                             "glifrk2=glifrk2-m", "--out", os.path.join(WORK, "mut"), "-q",
                             "--time-budget", "0")
        self.assertEqual(code, 1)


if __name__ == "__main__":
    BINARY, WORK = sys.argv[1], sys.argv[2]
    shutil.rmtree(WORK, ignore_errors=True)
    os.makedirs(WORK)
    unittest.main(argv=sys.argv[:1])
