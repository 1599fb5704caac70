#!/usr/bin/env python3
"""What a user meets (docs/ci.md, docs/reports.md, README): the command line's console lines,
compare's order, case and method file errors, the README's commands as written, JUnit attributes
and "did you mean". Each mode runs the dampsym binary on small cases (a second or two).

Usage: test_ux.py MODE DAMPSYM WORKDIR   (MODE: lines, compare, files, readme, junit, suggest)
Exit 0 when every expectation holds; 1 naming each that does not.
"""
import json
import os
import re
import shutil
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
from typing import Callable, Dict, List, Optional, Sequence, Tuple

SOURCE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FAILED: List[str] = []


def expect(ok: bool, what: str, detail: str = "") -> None:
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        FAILED.append(what)
        if detail:
            print("     " + detail[:2000].replace("\n", "\n     "))


def run(args: Sequence[str], env: Optional[Dict[str, str]] = None,
        cwd: Optional[str] = None) -> Tuple[int, str, str]:
    e = dict(os.environ)
    for k in ("TEST_TOTAL_SHARDS", "TEST_SHARD_INDEX", "CI_NODE_TOTAL", "CI_NODE_INDEX",
              "SLURM_ARRAY_TASK_COUNT", "SLURM_ARRAY_TASK_ID", "GITHUB_STEP_SUMMARY"):
        e.pop(k, None)
    e.update(env or {})
    p = subprocess.run(list(args), capture_output=True, text=True, env=e, cwd=cwd, timeout=120)
    return p.returncode, p.stdout, p.stderr


def case(cid: str, t_end: float, dt: float, methods: List[str], check: Dict,
         diagnostics: Sequence[str] = ("invariants", "cost")) -> Dict:
    return {"id": cid, "title": "test case", "source": "test", "suites": ["ux"],
            "problem": {"id": "oscillator", "omega": 1.0, "gamma": 0.025, "q0": 1.0, "p0": 0.0},
            "methods": methods, "t_end": t_end, "dt": dt,
            "diagnostics": list(diagnostics), "expect": check}


LAW = {"H_gamma law": {"metric": "invariants.H_gamma.max_step_res", "methods": ["cimp"],
                       "le": 1e-12}}


def write_cases(d: str, cases: List[Dict]) -> None:
    os.makedirs(d, exist_ok=True)
    for c in cases:
        with open(os.path.join(d, c["id"] + ".json"), "w") as f:
            json.dump(c, f)


def mode_lines(bin_: str, work: str) -> None:
    """One line per finished case, flushed while the run goes on (stdout not a terminal); the
    FAIL line's count, first three checks with method and dt, and "(+N more)"; -q names each
    failing check; a long case announced with its estimate; the shard in use printed."""
    cases = os.path.join(work, "cases")
    evals = {"two evaluations": {"metric": "cost.rhs_evals_per_step", "methods": ["csv1"],
                                 "near": 2, "tol": 0}}
    # ux-slow: 4e7 explicit steps, about 0.35 s of CPU
    write_cases(cases, [case("ux-fast", 1.0, 0.1, ["cimp"], LAW),
                        case("ux-slow", 40000.0, 0.001, ["csv1"], evals, ["cost"])])
    p = subprocess.Popen([bin_, "--cases", cases, "run", "ux-fast", "ux-slow", "--jobs", "1",
                          "--shard", "none", "--out", os.path.join(work, "r1")],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert p.stdout is not None
    first = p.stdout.readline()
    t_first = time.monotonic()
    rest, err = p.communicate(timeout=120)
    gap = time.monotonic() - t_first  # the slow case's run, if the line came when ux-fast ended
    expect(first.startswith("ok   ux-fast") and gap > 0.1,
           "a finished case's line is printed (and flushed) while the run goes on",
           f"first line {first!r}, {gap:.3f} s before the end of the output")
    expect("ok   ux-slow" in rest and "1 checks" in first, "every case gets its line",
           first + rest + err)
    # the example: 24 of 38 checks fail
    rc, out, err = run([bin_, "run", "osc-orders", "--set", "problem.omega=100", "--shard",
                        "none", "--out", os.path.join(work, "r2")])
    line = next((ln for ln in out.splitlines() if ln.startswith("FAIL osc-orders")), "")
    want = (r"^FAIL osc-orders +24 of 38 checks failed: H_gamma law broken \[rk3, dt=0\.2\]; "
            r"H_gamma law broken \[rk3, dt=0\.1\]; H_gamma law broken \[rk3, dt=0\.05\] "
            r"\(\+21 more\)")
    expect(rc == 1 and re.match(want, line) is not None,
           "FAIL line: count of failed and of all checks, first three with method and dt, "
           "(+21 more)", out + err)
    rc, out, err = run([bin_, "run", "osc-orders", "--set", "problem.omega=100", "-q",
                        "--shard", "none", "--out", os.path.join(work, "r3")])
    failed = [ln for ln in out.splitlines() if ln.startswith("FAILED osc-orders: ")]
    expect(rc == 1 and len(failed) == 24 and "[rk3, dt=0.025]" in out
           and out.rstrip().endswith("14 checks passed, 24 failed, " + out.rstrip().split(", ")[-1])
           and "FAIL osc-orders" in out,
           "-q names the failing case and each of its 24 failing checks, then the totals", out)
    # a long case is announced, with its estimate, before it runs (cut short by --case-timeout)
    write_cases(cases, [case("ux-long", 1e6, 1e-3, ["cimp", "csv1"], LAW)])
    t0 = time.time()
    rc, out, err = run([bin_, "--cases", cases, "run", "ux-long", "--case-timeout", "0.3",
                        "--shard", "none", "--out", os.path.join(work, "r4")])
    expect(re.search(r"note: case 'ux-long' runs 2e\+09 steps; predicted duration about \d+ s",
                     err) is not None and time.time() - t0 < 30,
           "a long case is announced with its step count and estimate", err)
    # ... from the case's measured run time when the costs file has it and no --set changes it
    costs = os.path.join(work, "costs.json")
    with open(costs, "w") as f:
        json.dump({"cases": {"ux-fast": 42.5}}, f)
    rc, out, err = run([bin_, "--cases", cases, "run", "ux-fast", "--costs", costs, "--shard",
                        "none", "-q", "--out", os.path.join(work, "r5")])
    expect(rc == 0 and "predicted duration about 42 s (its measured run time" in err,
           "a case announced from its measured run time (case_costs.json)", err)
    rc, out, err = run([bin_, "--cases", cases, "run", "ux-fast", "--costs", costs, "--set",
                        "t_end=2", "--shard", "none", "-q", "--out", os.path.join(work, "r6")])
    expect(rc == 0 and "predicted duration" not in err,
           "with a --set the measured time no longer applies (the rough estimate: short)", err)
    # --figures into a pipe: dampsym's lines come before the figure script's, each whole
    rc, out, err = run([bin_, "--cases", cases, "run", "ux-fast", "--figures", "--shard", "none",
                        "--out", os.path.join(work, "r7")])
    lines = out.splitlines()
    at = [i for i, ln in enumerate(lines) if "plot.py:" in ln]
    expect(rc == 0 and len(at) == 1
           and re.match(r"plot.py: \d+ figures, each as png, in ", lines[at[0]]) is not None
           and lines[0].startswith("ok   ux-fast") and at[0] > 0,
           "run --figures: the figure script's line after dampsym's, on a line of its own",
           out + err)
    # the shard from CI_NODE_TOTAL/CI_NODE_INDEX, on the console and in the -q totals
    env = {"CI_NODE_TOTAL": "2", "CI_NODE_INDEX": "1"}
    rc, out, err = run([bin_, "run", "--filter", "cs-*", "--out", os.path.join(work, "r5")], env)
    expect(re.search(r"^shard 1/2 \(from CI_NODE_TOTAL/CI_NODE_INDEX\): \d+ of \d+ selected "
                     r"cases$", out, re.M) is not None, "the shard in use is printed", out + err)
    rc, out, err = run([bin_, "run", "--filter", "cs-*", "-q", "--out", os.path.join(work, "r6")],
                       env)
    expect("(shard 1/2 from CI_NODE_TOTAL/CI_NODE_INDEX)" in out,
           "-q: the totals line names the shard", out + err)


def mode_compare(bin_: str, work: str) -> None:
    """Flips first (pass -> fail, then fail -> pass), then added/removed, then values by relative
    change, 6 significant digits with the relative change; slowdowns and speed-ups apart; another
    schema_version or tool refused (exit 2)."""
    base = os.path.join(work, "base")
    rc, out, err = run([bin_, "run", "osc-orders", "cs-oscillator", "--shard", "none", "-q",
                        "--out", base])
    with open(os.path.join(base, "report.json")) as f:
        r = json.load(f)
    n = json.loads(json.dumps(r))
    c = [x for x in n["cases"] if x["id"] == "osc-orders"][0]
    c["checks"][0]["passed"] = not c["checks"][0]["passed"]  # pass -> fail
    failing = [k for k in n["cases"][1]["checks"] if k["passed"]][0]
    failing["passed"] = False  # another pass -> fail
    c["runs"][0]["metrics"]["error"]["final_abs"] *= 1.001  # rel 1e-3
    c["runs"][1]["final_state"][0] *= 1 + 1e-7  # rel 1e-7
    c["runs"][2]["status"] = "diverged"
    c["checks"].pop()  # removed
    n["timings"]["cases"][0]["runs_wall_seconds"] *= 3  # slowdown
    n["timings"]["cases"][1]["runs_wall_seconds"] *= 0.25  # speed-up
    newp = os.path.join(work, "new.json")
    with open(newp, "w") as f:
        json.dump(n, f)
    # and the other direction for fail -> pass
    rc, out, err = run([bin_, "compare", newp, os.path.join(base, "report.json")])
    back = out
    rc, out, err = run([bin_, "compare", os.path.join(base, "report.json"), newp])
    order = [out.find(s) for s in ("pass → fail", "## Added or removed", "## Values changed")]
    expect(rc == 1 and all(o >= 0 for o in order) and order == sorted(order)
           and out.find("## Checks that now fail") < out.find("## Added or removed"),
           "compare: flips first, then added/removed, then values", out)
    expect(back.find("## Checks that now pass (fail → pass)") > back.find(
        "## Checks that now fail") >= 0 or "## Checks that now fail" not in back,
        "compare: pass → fail before fail → pass", back)
    vals = out[out.find("## Values changed"):]
    i_status, i_3, i_7 = (vals.find('"diverged"'), vals.find("+0.001"), vals.find("1e-07"))
    expect(0 <= i_status < i_3 < i_7, "values: a status change, then by relative change", vals)
    expect(re.search(r"\d\.\d{8,}", out) is None, "numbers to 6 significant digits", out)
    slow, fast = out.find("Largest slowdowns"), out.find("Largest speed-ups")
    expect(0 <= slow < fast and "| 3 |" in out[slow:fast] and "| 0.25 |" in out[fast:],
           "slowdowns (ratio 3) and speed-ups (ratio 0.25) apart", out)
    for version in (0, 99):
        m = json.loads(json.dumps(r))
        m["schema_version"] = version
        p = os.path.join(work, f"v{version}.json")
        with open(p, "w") as f:
            json.dump(m, f)
        rc, out, err = run([bin_, "compare", os.path.join(base, "report.json"), p])
        expect(rc == 2 and "schema_version" in err, f"schema_version {version} refused", err)
    m = json.loads(json.dumps(r))
    m["tool"] = {"name": "other"}
    p = os.path.join(work, "tool.json")
    with open(p, "w") as f:
        json.dump(m, f)
    rc, out, err = run([bin_, "compare", os.path.join(base, "report.json"), p])
    expect(rc == 2 and "tool" in err, "another tool refused", err)


def readme_case() -> str:
    with open(os.path.join(SOURCE, "README.md"), encoding="utf-8") as f:
        text = f.read()
    block = text[text.index("## Adding a case"):]
    start = block.index("\n    {")
    lines = []
    for ln in block[start + 1:].split("\n"):
        if not ln.startswith("    "):
            break
        lines.append(ln[4:])
    return "\n".join(lines)


def mode_files(bin_: str, work: str) -> None:
    """The README's case example parses and runs; "$schema" is accepted; a comment is named as
    such; a method file is named as a method file."""
    os.makedirs(work, exist_ok=True)
    example = os.path.join(work, "example.json")
    with open(example, "w") as f:
        f.write(readme_case())
    rc, out, err = run([bin_, "run", example, "--shard", "none", "-q",
                        "--out", os.path.join(work, "r1")])
    expect(rc in (0, 1) and "1 cases" in out, "the README's case example runs", out + err)
    doc = json.loads(readme_case())
    doc = {"$schema": "../schema/case.schema.json", **doc}
    with open(example, "w") as f:
        json.dump(doc, f)
    rc, out, err = run([bin_, "run", example, "--shard", "none", "-q",
                        "--out", os.path.join(work, "r2")])
    expect(rc in (0, 1), "a \"$schema\" key is accepted", out + err)
    with open(example, "w") as f:
        f.write(readme_case().replace('"t_end": 10.0,', '"t_end": 10.0, // ten time units'))
    rc, out, err = run([bin_, "run", example, "--shard", "none", "--out", os.path.join(work, "r3")])
    expect(rc == 2 and "example.json" in err and "comments (// or /* */) are not JSON" in err,
           "a comment: exit 2, the file named, and 'comments are not JSON'", err)
    with open(example, "w") as f:
        f.write(readme_case().replace('"t_end": 10.0,', '"t_end": 10.0 /* ten */,'))
    rc, out, err = run([bin_, "run", example, "--shard", "none", "--out", os.path.join(work, "r4")])
    expect(rc == 2 and "are not JSON" in err, "a /* */ comment too", err)
    with open(example, "w") as f:
        f.write(readme_case().replace('"t_end": 10.0,', '"t_end": 10.0 ,,'))
    rc, out, err = run([bin_, "run", example, "--shard", "none", "--out", os.path.join(work, "r5")])
    expect(rc == 2 and "malformed JSON" in err and "comments" not in err,
           "another syntax error does not blame comments", err)
    rc, out, err = run([bin_, "run", "osc-orders", "--methods", os.path.join(work, "nothere.json"),
                        "--shard", "none", "--out", os.path.join(work, "r6")])
    expect(rc == 2 and "cannot open method file" in err and "case file" not in err,
           "a missing --methods file is named a method file", err)


def mode_readme(bin_: str, work: str) -> None:
    """The README's "Using it in CI" commands, as written (./build/dampsym from the directory
    above build/), on a few small cases (DAMPSYM_CASES): run, compare, the shard loop and merge."""
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(os.path.join(work, "build"))
    os.symlink(bin_, os.path.join(work, "build", "dampsym"))
    cases = os.path.join(work, "cases")
    os.makedirs(cases)
    for cid in ("cs-oscillator", "cs-pendulum", "cs-hill", "osc-orders", "cs-driven-pendulum"):
        shutil.copy(os.path.join(SOURCE, "verify", "cases", cid + ".json"), cases)
    with open(os.path.join(SOURCE, "README.md"), encoding="utf-8") as f:
        text = f.read()
    block = text[text.index("## Using it in CI"):]
    cmds = [ln[4:].split("   #")[0].strip() for ln in block.split("\n\n")[1].split("\n")]
    env = {"DAMPSYM_CASES": cases}
    for cmd in cmds:
        if cmd.startswith("ctest"):
            continue  # the build's own ctest: not a dampsym command
        if "compare base/" in cmd:
            shutil.copytree(os.path.join(work, "reports"), os.path.join(work, "base"))
        rc, out, err = run(["/bin/bash", "-c", cmd], env, cwd=work)
        expect(rc == 0, f"README: {cmd}", out[-1500:] + err)
    with open(os.path.join(work, "reports", "report.json")) as f:
        merged = json.load(f)
    expect(len(merged["cases"]) == 5 and len(merged["provenance"]["merged_from"]) == 4,
           "the merged report has the 5 cases of 4 shards")
    expect(merged["provenance"]["merged_from"][0].get("cases_dir") == cases,
           "the provenance names the case directory used (DAMPSYM_CASES)")


def mode_junit(bin_: str, work: str) -> None:
    """JUnit: time per testcase, timestamp and hostname per testsuite, skipped for checks not
    run."""
    junit = os.path.join(work, "junit.xml")
    # --method cimp leaves a ratio check of cimp against csv1 without its partner: skipped
    rc, out, err = run([bin_, "run", "osc-energy-g1e-4", "--method", "cimp", "--shard", "none",
                        "-q", "--out", os.path.join(work, "r"), "--junit", junit])
    root = ET.parse(junit).getroot()
    suite = root.find("testsuite")
    assert suite is not None
    cases = suite.findall("testcase")
    expect(all(re.match(r"^\d+\.\d{6}$", c.get("time", "")) for c in cases)
           and any(float(c.get("time", "0")) > 0 for c in cases), "a time on every testcase")
    expect(re.match(r"^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d$", suite.get("timestamp", "")) is not None
           and bool(suite.get("hostname")), "timestamp and hostname on the testsuite",
           str(suite.attrib))
    skipped = [c for c in cases if c.find("skipped") is not None]
    expect(int(suite.get("skipped", "0")) == len(skipped) > 0,
           "checks of methods not selected are skipped testcases", str(suite.attrib))


def mode_suggest(bin_: str, work: str) -> None:
    """"did you mean" for subcommands, case ids, method ids, problem ids and keys; `help`."""
    rc, out, err = run([bin_, "runn"])
    expect(rc == 2 and "did you mean 'run'?" in err, "runn: did you mean 'run'?", err)
    rc, out, err = run([bin_, "help"])
    expect(rc == 0 and "Subcommands" in out or "SUBCOMMANDS" in out, "dampsym help", out + err)
    rc, out, err = run([bin_, "help", "run"])
    expect(rc == 0 and "--shard" in out, "dampsym help run", out + err)
    rc, out, err = run([bin_, "run", "osc-order", "--out", os.path.join(work, "r")])
    expect(rc == 2 and "did you mean 'osc-orders'?" in err, "a case id", err)
    c = case("ux-typo", 1.0, 0.1, ["cimpp"], LAW)
    os.makedirs(work, exist_ok=True)
    for name, doc, want in (
            ("method", c, "did you mean 'cimp'?"),
            ("key", {**case("ux-typo", 1.0, 0.1, ["cimp"], LAW), "t_ned": 1},
             "did you mean 't_end'?"),
            ("problem key", {**case("ux-typo", 1.0, 0.1, ["cimp"], LAW),
                             "problem": {"id": "oscillator", "gama": 0.1}},
             "did you mean 'gamma'?"),
            ("problem id", {**case("ux-typo", 1.0, 0.1, ["cimp"], LAW),
                            "problem": {"id": "oscilator"}}, "did you mean 'oscillator'?")):
        p = os.path.join(work, "typo.json")
        with open(p, "w") as f:
            json.dump(doc, f)
        rc, out, err = run([bin_, "run", p, "--out", os.path.join(work, "r")])
        expect(rc == 2 and want in err, f"a mistyped {name}: {want}", err)
    rc, out, err = run([bin_, "run", "frobnicate-the-world", "--out", os.path.join(work, "r")])
    expect(rc == 2 and "did you mean" not in err, "no suggestion when nothing is close", err)


MODES: Dict[str, Callable[[str, str], None]] = {
    "lines": mode_lines, "compare": mode_compare, "files": mode_files, "readme": mode_readme,
    "junit": mode_junit, "suggest": mode_suggest}


def main(argv: List[str]) -> int:
    if len(argv) != 4 or argv[1] not in MODES:
        print(__doc__, file=sys.stderr)
        return 2
    shutil.rmtree(argv[3], ignore_errors=True)
    os.makedirs(argv[3])
    MODES[argv[1]](os.path.abspath(argv[2]), os.path.abspath(argv[3]))
    print(f"{argv[1]}: {len(FAILED)} failed" if FAILED else f"{argv[1]}: all ok")
    return 1 if FAILED else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
