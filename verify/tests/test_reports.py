#!/usr/bin/python3
"""Tests of dampsym's reports as CI tools read them (ctest label "reports").

    /usr/bin/python3 -m pytest verify/tests/test_reports.py::test_MODE --bin DAMPSYM [options]
    /usr/bin/python3 -m verify.tests.test_reports MODE --bin DAMPSYM [options]

MODE schema  --report DIR... : every report.json validates against schema/report.schema.json;
             every case file in verify/cases and tests/data/cases validates against
             schema/case.schema.json and is accepted by the parser (`dampsym list`); every file in
             tests/data/bad fails the schema or the parser (exit 2), and a report with a clock
             value moved back into a run fails the report schema (negative control).
MODE junit   --report DIR --work DIR [--ctest-build DIR] : DIR/junit.xml (dampsym run --junit),
             the JUnit of a run with a failing and a diverged check, and ctest --output-junit on
             two per-case tests validate as JUnit (python3-junitparser, plus the element and
             attribute structure of the Jenkins/GitLab JUnit schema); the failing check appears by
             name as a <failure>, the diverged run as an <error>.
MODE shards  --report DIR --work DIR : the default suite in 3 shards run in parallel (without
             work-precision timing, which only the timings section holds), merged; the
             merged report.json is byte-identical to DIR/report.json before "provenance", and
             `dampsym compare` exits 0 on them; the Bazel, GitLab and Slurm variables select the
             same shards as --shard; the estimated shard costs are within 1.5x.
MODE compare --report DIR --work DIR : `dampsym compare` on the report itself (exit 0), on a
             perturbed final state, a flipped check and a removed case (exit 1, the right rows),
             with --rtol absorbing the perturbation (exit 0), and on bad input (exit 2).
MODE stable  --report DIR --work DIR : a second run of the same cases gives a report.json that
             is byte-identical before "provenance" (covered by shards for the default suite; this
             mode is for a quick manual check).
"""
import argparse
import copy
import glob
import json
import os
import subprocess
import sys
import xml.etree.ElementTree as ET
from typing import Any, Dict, List, Optional

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
failures = []


def check(cond: Any, msg: str) -> Any:
    if not cond:
        failures.append(msg)
        print("FAIL: " + msg)
    return cond


def run(cmd: Any, env: Any = None, **kw: Any) -> Any:
    e = dict(os.environ)
    for k in ("TEST_TOTAL_SHARDS", "TEST_SHARD_INDEX", "CI_NODE_TOTAL", "CI_NODE_INDEX",
              "SLURM_ARRAY_TASK_COUNT", "SLURM_ARRAY_TASK_ID", "SLURM_ARRAY_TASK_MIN",
              "GITHUB_STEP_SUMMARY", "TEST_SHARD_STATUS_FILE"):
        e.pop(k, None)
    e.update(env or {})
    return subprocess.run(cmd, capture_output=True, text=True, env=e, **kw)


def stable_part(path: str) -> Any:
    """report.json's text before the "provenance" section (written last but for timings)."""
    with open(path, "rb") as fh:
        text = fh.read()
    i = text.find(b'\n  "provenance": {')
    check(i > 0, "%s: no provenance section" % path)
    return text[:i]


# --- schema -------------------------------------------------------------------------------

def mode_schema(a: Any) -> None:
    import jsonschema
    with open(os.path.join(ROOT, "schema", "report.schema.json")) as fh:
        rschema = json.load(fh)
    with open(os.path.join(ROOT, "schema", "case.schema.json")) as fh:
        cschema = json.load(fh)
    V = jsonschema.Draft202012Validator
    V.check_schema(rschema)
    V.check_schema(cschema)
    rv, cv = V(rschema), V(cschema)
    for d in a.report:
        path = os.path.join(d, "report.json")
        with open(path) as fh:
            rep = json.load(fh)
        errs = sorted(rv.iter_errors(rep), key=lambda e: list(e.path))
        check(not errs, "%s: %d schema errors, first: %s at %s" % (
            path, len(errs), errs[0].message if errs else "", list(errs[0].path) if errs else ""))
        print("%s: valid (%d cases)" % (path, len(rep["cases"])))
        # negative control: a field moved back into a run must fail
        bad = copy.deepcopy(rep)
        bad["cases"][0]["runs"][0]["wall_seconds"] = 0.1
        check(not rv.is_valid(bad), "report schema accepts runs[].wall_seconds")
        bad = copy.deepcopy(rep)
        del bad["summary"]["checks_failed"]
        check(not rv.is_valid(bad), "report schema accepts a summary without checks_failed")
    for d in (os.path.join(ROOT, "verify", "cases"), os.path.join(ROOT, "tests", "data", "cases")):
        files = sorted(glob.glob(os.path.join(d, "*.json")))
        for f in files:
            with open(f) as fh:
                errs = list(cv.iter_errors(json.load(fh)))
            check(not errs, "%s: schema rejects a valid case: %s" % (
                f, errs[0].message if errs else ""))
        p = run([a.bin, "--cases", d, "list", "--json"])
        check(p.returncode == 0, "parser rejects a case in %s: %s" % (d, p.stderr.strip()))
        print("%s: %d case files valid for schema and parser" % (d, len(files)))
    empty = os.path.join(a.work, "empty-cases")
    os.makedirs(empty, exist_ok=True)
    for f in sorted(glob.glob(os.path.join(ROOT, "tests", "data", "bad", "*.json"))):
        try:
            with open(f) as fh:
                doc = json.load(fh)
            schema_ok = cv.is_valid(doc)
        except ValueError:
            schema_ok = False
        p = run([a.bin, "--cases", empty, "run", f, "--out", os.path.join(a.work, "bad-out")])
        parser_ok = p.returncode != 2
        check(not (schema_ok and parser_ok),
              "%s: accepted by both the schema and the parser" % f)
        check(p.returncode == 2, "%s: parser exit %d, expected 2" % (f, p.returncode))
        print("%s: schema %s, parser %s" % (os.path.basename(f),
              "accepts" if schema_ok else "rejects", "accepts" if parser_ok else "rejects (2)"))


# --- junit --------------------------------------------------------------------------------

# The structure Jenkins (xunit junit-10) and GitLab read: elements, their allowed children and
# attributes, required attributes, and times without exponent.
STRUCTURE: Dict[str, Any] = {
    "testsuites": ({"testsuite"}, {"name", "time", "tests", "failures", "errors", "disabled"},
                   set()),
    "testsuite": ({"testsuite", "properties", "testcase", "system-out", "system-err"},
                  {"name", "tests", "failures", "errors", "group", "time", "skipped",
                   "timestamp", "hostname", "id", "package", "file", "log", "url", "disabled"},
                  {"name", "tests", "failures", "errors"}),
    "properties": ({"property"}, set(), set()),
    "property": (set(), {"name", "value"}, {"name", "value"}),
    "testcase": ({"skipped", "error", "failure", "system-out", "system-err", "properties"},
                 {"name", "time", "classname", "group", "status", "assertions", "file", "line"},
                 {"name"}),
    "failure": (set(), {"type", "message"}, set()),
    "error": (set(), {"type", "message"}, set()),
    "skipped": (set(), {"type", "message"}, set()),
    "system-out": (set(), set(), set()),
    "system-err": (set(), set(), set()),
}


def validate_junit(path: str, strict: Any = True) -> Any:
    """strict=False for CTest's own JUnit (CTest 3.25 writes no errors= attribute, which the
    Jenkins schema requires but Jenkins' junit plugin and GitLab do not)."""
    import re
    import junitparser
    tree = ET.parse(path)
    root = tree.getroot()
    ok = check(root.tag in ("testsuites", "testsuite"), "%s: root <%s>" % (path, root.tag))

    def walk(el: Any) -> None:
        nonlocal ok
        kids, attrs, required = STRUCTURE.get(el.tag, (None, None, None))
        if kids is None:
            ok = check(False, "%s: unknown element <%s>" % (path, el.tag)) and ok
            return
        for k in el.attrib:
            ok = check(k in attrs, "%s: <%s %s=...> not in the JUnit schema" % (path, el.tag, k)) and ok
        for k in required:
            if not strict and k == "errors":
                continue
            ok = check(k in el.attrib, "%s: <%s> without %s" % (path, el.tag, k)) and ok
        if "time" in el.attrib:
            ok = check(re.fullmatch(r"[0-9]*(\.[0-9]*)?", el.attrib["time"]) is not None,
                       "%s: <%s time=%r>" % (path, el.tag, el.attrib["time"])) and ok
        for c in el:
            ok = check(c.tag in kids, "%s: <%s> inside <%s>" % (path, c.tag, el.tag)) and ok
            walk(c)
    walk(root)
    # counts agree with the testcases (what dashboards sum)
    for ts in root.iter("testsuite"):
        cases = ts.findall("testcase")
        if ts.find("testsuite") is not None:
            continue
        nf = sum(1 for c in cases if c.find("failure") is not None)
        ne = sum(1 for c in cases if c.find("error") is not None)
        ok = check(int(str(ts.get("tests"))) == len(cases), "%s: %s tests=%s, %d testcases" % (
            path, ts.get("name"), ts.get("tests"), len(cases))) and ok
        ok = check(int(str(ts.get("failures"))) == nf and int(ts.get("errors", "0")) == ne,
                   "%s: %s failure/error counts" % (path, ts.get("name"))) and ok
    # and junitparser, as GitLab-like consumers read it
    xml = junitparser.JUnitXml.fromfile(path)
    n = 0
    for suite in (xml if isinstance(xml, junitparser.JUnitXml) else [xml]):
        for case in suite:
            n += 1
            check(bool(case.name), "%s: a testcase without name" % path)
    print("%s: valid JUnit, %d testcases" % (path, n))
    return root


def mode_junit(a: Any) -> None:
    root = validate_junit(os.path.join(a.report[0], "junit.xml"))
    with open(os.path.join(a.report[0], "report.json")) as fh:
        rep = json.load(fh)
    nchecks = sum(len(c["checks"]) for c in rep["cases"])
    check(len(list(root.iter("testcase"))) == nchecks, "one testcase per check")
    check(len(root.findall("testsuite")) == len(rep["cases"]), "one testsuite per case")
    # a failing check and a diverged run, by name
    data = os.path.join(ROOT, "tests", "data", "cases")
    out = os.path.join(a.work, "junit-fail")
    p = run([a.bin, "--cases", data, "run", "cli-wrong-order", "cli-diverged", "--out", out,
             "--junit", os.path.join(out, "junit.xml"), "--time-budget", "0", "--quiet"])
    check(p.returncode == 1, "failing run: exit %d (%s)" % (p.returncode, p.stderr))
    root = validate_junit(os.path.join(out, "junit.xml"))
    with open(os.path.join(out, "report.json")) as fh:
        rep = json.load(fh)
    failed = [(c["id"], ck) for c in rep["cases"] for ck in c["checks"] if not ck["passed"]]
    check(failed, "the failing run has failing checks")
    for cid, ck in failed:
        name = "%s [%s" % (ck["name"], ck["method"])
        tc = [t for t in root.iter("testcase") if t.get("classname") == cid
              and t.get("name", "").startswith(name)]
        check(len(tc) >= 1, "failing check %s / %s not in the JUnit" % (cid, name))
        if tc:
            kind = "error" if str(ck.get("message", "")).startswith("run ") else "failure"
            el = tc[0].find(kind)
            check(el is not None, "%s / %s: no <%s>" % (cid, name, kind))
            if el is not None and kind == "failure":
                check("expected" in el.get("message", "") and "value" in el.get("message", ""),
                      "failure message carries value and expected: %r" % el.get("message"))
    check(any(t.find("error") is not None for t in root.iter("testcase")),
          "the diverged runs are <error>s")
    for ts in root.iter("testsuite"):
        props = {p.get("name"): p.get("value") for p in ts.iter("property")}
        check("source" in props and "file" in props, "testsuite %s properties" % ts.get("name"))
    # ctest --output-junit on two per-case tests
    if a.ctest_build:
        cj = os.path.join(a.work, "ctest-junit.xml")
        # a test directory of its own that includes the build's tests, so that this ctest's
        # logs do not overwrite those of the ctest running this test
        top = os.path.join(a.work, "ctest")
        os.makedirs(top, exist_ok=True)
        with open(os.path.join(top, "CTestTestfile.cmake"), "w") as fh:
            fh.write('subdirs("%s")\n' % os.path.join(os.path.abspath(a.ctest_build), "tests"))
        p = run(["ctest", "--test-dir", top, "-R",
                 r"^case\.(osc-fig31-k1|osc-stability-det)$", "--output-junit", cj])
        check(p.returncode == 0, "ctest per-case tests: exit %d\n%s" % (p.returncode, p.stdout))
        root = validate_junit(cj, strict=False)
        names = {t.get("name") for t in root.iter("testcase")}
        check(names == {"case.osc-fig31-k1", "case.osc-stability-det"},
              "ctest JUnit testcases: %s" % sorted(names))


# --- shards -------------------------------------------------------------------------------

def mode_shards(a: Any) -> None:
    base = os.path.join(a.report[0], "report.json")
    p: Any
    procs: List[Any] = []
    dirs: List[str] = []
    for k in (1, 2, 3):
        d = os.path.join(a.work, "shard%d" % k)
        dirs.append(d)
        procs.append(subprocess.Popen(
            # --time-budget 0: the work-precision timings live in "timings" only, so the stable
            # part must equal the unsharded run's (made with the default budget) all the same
            [a.bin, "run", "--shard", "%d/3" % k, "--out", d, "--jobs", "1", "--quiet",
             "--time-budget", "0"],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True))
    for k, p in enumerate(procs, 1):
        out, err = p.communicate()
        check(p.returncode in (0, 1), "shard %d/3: exit %d: %s" % (k, p.returncode, err))
    merged = os.path.join(a.work, "merged")
    p = run([a.bin, "merge", merged] + dirs + ["--quiet"])
    check(p.returncode in (0, 1), "merge: exit %d: %s" % (p.returncode, p.stderr))
    check(stable_part(os.path.join(merged, "report.json")) == stable_part(base),
          "merged report.json differs from the unsharded one before \"provenance\"")
    p = run([a.bin, "compare", base, os.path.join(merged, "report.json")])
    check(p.returncode == 0, "compare unsharded merged: exit %d\n%s" % (p.returncode, p.stdout))
    validate_junit(os.path.join(merged, "junit.xml"))
    import jsonschema
    with open(os.path.join(ROOT, "schema", "report.schema.json")) as fh:
        rv = jsonschema.Draft202012Validator(json.load(fh))
    for d in dirs + [merged]:
        with open(os.path.join(d, "report.json")) as fh:
            errs = list(rv.iter_errors(json.load(fh)))
        check(not errs, "%s/report.json: schema: %s" % (d, errs[0].message if errs else ""))
    walls, ids = [], []
    for d in dirs:
        with open(os.path.join(d, "report.json")) as fh:
            r = json.load(fh)
        walls.append(r["timings"]["wall_seconds"])
        ids.append([c["id"] for c in r["cases"]])
    print("shard wall seconds (3 processes on this machine at once): %s" %
          ", ".join("%.2f" % w for w in walls))
    all_ids = [i for s in ids for i in s]
    check(len(all_ids) == len(set(all_ids)), "a case in two shards")
    # the estimate balance (deterministic): from `dampsym list --shard`, with the committed costs
    with open(os.path.join(ROOT, "verify", "case_costs.json")) as fh:
        costs = json.load(fh)["cases"]
    est = []
    for k in (1, 2, 3):
        p = run([a.bin, "list", "--json", "--suite", "default", "--shard", "%d/3" % k])
        listed = [c["id"] for c in json.loads(p.stdout)["cases"]]
        check(listed == ids[k - 1], "list --shard %d/3 lists the cases run by shard %d" % (k, k))
        est.append(sum(costs.get(i, 0.0) for i in listed))
    print("estimated shard costs: %s s" % ", ".join("%.2f" % e for e in est))
    check(max(est) <= 1.5 * min(est), "estimated shard costs not within 1.5x: %s" % est)
    # the engines' variables select the same shards (a small selection, run for real)
    sel = ["--filter", "osc-*", "--time-budget", "0", "--quiet"]
    expect = {}
    for k in (1, 2, 3):
        p = run([a.bin, "list", "--json", "--shard", "%d/3" % k, "--suite", "default",
                 "--filter", "osc-*"])
        expect[k] = [c["id"] for c in json.loads(p.stdout)["cases"]]
    conventions = [
        ("bazel", lambda k: {"TEST_TOTAL_SHARDS": "3", "TEST_SHARD_INDEX": str(k - 1),
                             "TEST_SHARD_STATUS_FILE": os.path.join(a.work, "bazel-status")}),
        ("gitlab", lambda k: {"CI_NODE_TOTAL": "3", "CI_NODE_INDEX": str(k)}),
        ("slurm", lambda k: {"SLURM_ARRAY_TASK_COUNT": "3", "SLURM_ARRAY_TASK_ID": str(k + 9),
                             "SLURM_ARRAY_TASK_MIN": "10"}),
    ]
    for name, env in conventions:
        for k in (1, 2, 3):
            d = os.path.join(a.work, "%s%d" % (name, k))
            p = run([a.bin, "run", "--out", d] + sel, env=env(k))
            check(p.returncode in (0, 1), "%s shard %d: exit %d %s" % (name, k, p.returncode, p.stderr))
            with open(os.path.join(d, "report.json")) as fh:
                r = json.load(fh)
            got = [c["id"] for c in r["cases"]]
            check(got == expect[k], "%s shard %d runs %s, --shard %d/3 %s" % (
                name, k, got, k, expect[k]))
            check(r["provenance"]["shard"]["index"] == k, "%s shard index" % name)
    check(os.path.exists(os.path.join(a.work, "bazel-status")), "TEST_SHARD_STATUS_FILE touched")


# --- compare ------------------------------------------------------------------------------

def mode_compare(a: Any) -> None:
    base = os.path.join(a.report[0], "report.json")
    with open(base) as fh:
        rep = json.load(fh)

    def cmp(doc: Any, name: Any, extra: Any = ()) -> Any:
        path = os.path.join(a.work, name + ".json")
        with open(path, "w") as fh:
            json.dump(doc, fh, indent=1)
        p = run([a.bin, "compare", base, path, "--json"] + list(extra))
        res = json.loads(p.stdout) if p.stdout.strip().startswith("{") else None
        return p.returncode, res

    rc, res = cmp(rep, "same")
    check(rc == 0 and res and res["equal"] and not res["rows"], "compare with itself: %d" % rc)
    # (1) a perturbed final state
    doc = copy.deepcopy(rep)
    case = next(c for c in doc["cases"] if any(r["status"] == "ok" for r in c["runs"]))
    r0 = next(r for r in case["runs"] if r["status"] == "ok")
    r0["final_state"][0] = r0["final_state"][0] * (1 + 1e-9) + 1e-300
    rc, res = cmp(doc, "perturbed")
    rows = res["rows"] if res else []
    check(rc == 1, "perturbed final state: exit %d" % rc)
    check(len(rows) == 1 and rows[0]["kind"] == "final state" and rows[0]["case"] == case["id"]
          and rows[0]["path"] == "final_state[0]" and rows[0]["run"].startswith(r0["method"] + " dt="),
          "perturbed final state rows: %s" % rows)
    rc, res = cmp(doc, "perturbed-rtol", ["--rtol", "1e-6"])
    check(rc == 0, "perturbation within --rtol 1e-6: exit %d" % rc)
    # (2) a flipped check
    doc = copy.deepcopy(rep)
    c2 = doc["cases"][1]
    ck = c2["checks"][0]
    ck["passed"] = not ck["passed"]
    rc, res = cmp(doc, "flipped")
    rows = res["rows"] if res else []
    check(rc == 1, "flipped check: exit %d" % rc)
    check(len(rows) == 1 and rows[0]["kind"] == "check flipped" and rows[0]["case"] == c2["id"]
          and rows[0]["path"].startswith(ck["name"] + " [" + ck["method"]),
          "flipped check rows: %s" % rows)
    # (3) a removed case
    doc = copy.deepcopy(rep)
    gone = doc["cases"].pop(2)
    rc, res = cmp(doc, "removed")
    rows = res["rows"] if res else []
    check(rc == 1, "removed case: exit %d" % rc)
    check(len(rows) == 1 and rows[0]["kind"] == "case removed" and rows[0]["case"] == gone["id"],
          "removed case rows: %s" % rows)
    # Markdown names the case
    p = run([a.bin, "compare", base, os.path.join(a.work, "removed.json")])
    check(p.returncode == 1 and gone["id"] in p.stdout and "case removed" in p.stdout,
          "Markdown output names the removed case")
    # bad input
    bad = os.path.join(a.work, "bad.json")
    with open(bad, "w") as fh:
        fh.write("{not json")
    p = run([a.bin, "compare", base, bad])
    check(p.returncode == 2 and "bad.json" in p.stderr, "malformed report: exit %d" % p.returncode)
    with open(bad, "w") as fh:
        json.dump({"schema_version": 2}, fh)
    p = run([a.bin, "compare", bad, base])
    check(p.returncode == 2, "not a report: exit %d" % p.returncode)
    p = run([a.bin, "compare", base, os.path.join(a.work, "missing.json")])
    check(p.returncode == 2, "missing report: exit %d" % p.returncode)


def mode_stable(a: Any) -> None:
    with open(os.path.join(a.report[0], "report.json")) as fh:
        rep = json.load(fh)
    ids = [c["id"] for c in rep["cases"]]
    d = os.path.join(a.work, "again")
    p = run([a.bin, "run"] + ids + ["--out", d, "--jobs", "2", "--quiet"])
    check(p.returncode in (0, 1), "second run: exit %d" % p.returncode)
    check(stable_part(os.path.join(d, "report.json")) ==
          stable_part(os.path.join(a.report[0], "report.json")),
          "two runs differ before \"provenance\"")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("mode", choices=["schema", "junit", "shards", "compare", "stable"])
    ap.add_argument("--bin", required=True)
    ap.add_argument("--report", action="append", default=[])
    ap.add_argument("--work", required=True)
    ap.add_argument("--ctest-build")
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    globals()["mode_" + a.mode](a)
    if failures:
        print("%d failures" % len(failures))
        sys.exit(1)
    print("ok")


def _mode(mode: str, dampsym_bin: str, reports: List[str], workdir: str, ctest_build: Optional[str]) -> None:
    failures.clear()
    globals()["mode_" + mode](argparse.Namespace(bin=dampsym_bin, report=reports, work=workdir,
                                                 ctest_build=ctest_build))
    assert failures == []


@pytest.mark.parametrize("mode", ["schema", "junit", "shards", "compare"])
def test_reports(mode: str, dampsym_bin: str, reports: List[str], workdir: str, ctest_build: Optional[str]) -> None:
    """The mode's checks (the module docstring) on the given reports."""
    _mode(mode, dampsym_bin, reports, workdir, ctest_build)


if __name__ == "__main__":
    main()
