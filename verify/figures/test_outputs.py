#!/usr/bin/python3
"""Outputs confined to their directory, nothing deleted that dampsym did not write, signals and
bounded inputs while figures are involved (docs/reports.md "Figures"), through the dampsym binary
and tools/figures/plot.py:

1. a report's case ids are validated before anything is drawn (an id "../../../ESCAPED" or an
   absolute one: exit 2 naming report.json and the key, nothing written outside DIR); a user's
   files in DIR/series/ and DIR/figures/ survive `run --figures` and `plot`, while the files of an
   earlier run that dampsym listed in its manifest are removed (the positive control); a symbolic
   link in place of an output (--junit, report.md, a figure, DIR/series) is refused with exit 3
   naming it and left as it was; --junit equal to report.json, an empty --junit, --out or
   REPORT_DIR exit 2;
4. SIGINT/SIGTERM during the runs of `run --figures`, during its drawing, to `plot`, twice, and to
   the whole process group: exit 130/143, no traceback, no figure script left running or writing;
8. plot.py's inputs: a series file one byte over the limit (sparse) or a symbolic link, a `{}`
   report, a report whose case is malformed, a `figures` that is a file: exit 2 with one line
   naming the file, never a traceback; safeio's bounds are tight (a file of exactly the limit is
   read, one byte more is not).

    test_outputs.py DAMPSYM WORKDIR [WORD...]   (ctest figures.outputs; WORDs: only the tests
                                                 whose names contain one; or pytest with the
                                                 environment variables DAMPSYM and WORK)

24 s of CPU (62 s wall on the shared 2-core machine at load 10): most of it matplotlib's import
in each of the 16 starts of plot.py."""

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple

HERE = os.path.dirname(os.path.abspath(__file__))
from tools.figures.dampfig import safeio as sio

DAMPSYM = os.environ.get("DAMPSYM", sys.argv[1] if len(sys.argv) > 2 else "")
WORK = os.environ.get("WORK", sys.argv[2] if len(sys.argv) > 2 else "")
if WORK:
    os.makedirs(WORK, exist_ok=True)


def case(cid: str, t_end: float = 2.0, **extra: object) -> Dict[str, object]:
    c: Dict[str, object] = {
        "id": cid, "title": "outputs test",
        "problem": {"id": "oscillator", "omega": 1.0, "gamma": 0.1, "q0": 1.0, "p0": 0.0},
        "methods": ["csv1"], "t_end": t_end, "dt_ladder": [0.02, 0.01], "output_dt": 0.02,
        "diagnostics": ["error", "energy"],
        "expect": {"small final error": {"metric": "error.final_abs", "methods": "all",
                                         "le": 1.0}}}
    c.update(extra)
    return c


def write_case(c: Dict[str, object]) -> str:
    d = os.path.join(WORK, "cases")
    os.makedirs(d, exist_ok=True)
    p = os.path.join(d, f"{c['id']}.json")
    with open(p, "w") as f:
        json.dump(c, f)
    return p


def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([DAMPSYM, *args], capture_output=True, text=True, timeout=120)


def fresh(name: str) -> str:
    d = os.path.join(WORK, name)
    shutil.rmtree(d, ignore_errors=True)
    return d


def one_line(r: subprocess.CompletedProcess, code: int, *words: str) -> Optional[str]:
    """None if r exited `code` with one line of stderr containing every word, no traceback."""
    lines = r.stderr.strip().splitlines()
    if r.returncode != code or len(lines) != 1 or "Traceback" in r.stderr or \
            not all(w in r.stderr for w in words):
        return f"exit {r.returncode} (want {code}), stderr: {r.stderr.strip()[-400:]}"
    return None


def check(ok: Optional[str]) -> None:
    assert ok is None, ok


# ---- item 1: confined outputs, manifest, symbolic links, output paths ----------------------------

def figures_dir_with_user_files() -> str:
    """A `run --figures` of two cases into a directory holding a user's files."""
    out = fresh("user-files")
    for sub, name in (("series", "thesis-data.csv"), ("figures", "my-photo.png")):
        os.makedirs(os.path.join(out, sub))
        with open(os.path.join(out, sub, name), "w") as f:
            f.write("mine\n")
    r = run("run", write_case(case("out-a")), write_case(case("out-b")), "--figures", "--out",
            out, "-q", "--shard", "none")
    assert r.returncode == 0, r.stderr[-500:]
    return out


def test_user_files_survive_and_own_files_go() -> None:
    out = figures_dir_with_user_files()
    for f in ("series/thesis-data.csv", "figures/my-photo.png", "series/out-b.json",
              "figures/out-b-convergence.png"):
        assert os.path.exists(os.path.join(out, f)), f
    # the second run has only out-a: what the first run wrote for out-b goes, the user's stays
    r = run("run", write_case(case("out-a")), "--figures", "--out", out, "-q", "--shard", "none")
    assert r.returncode == 0, r.stderr[-500:]
    r = run("plot", out)
    assert r.returncode == 0, r.stderr[-500:]
    have = set(os.listdir(os.path.join(out, "series"))) | set(os.listdir(os.path.join(out, "figures")))
    assert {"thesis-data.csv", "my-photo.png", "out-a.json", "out-a-convergence.png"} <= have, have
    assert not {"out-b.json", "out-b-convergence.png", "out-b-series.png"} & have, have
    assert not [n for n in have if n.endswith(sio.TMP_SUFFIX)], have


def test_report_ids_are_validated_before_drawing() -> None:
    out = fresh("escape")
    r = run("run", write_case(case("out-a")), "--out", out, "-q", "--shard", "none")
    assert r.returncode == 0, r.stderr[-500:]
    with open(os.path.join(out, "report.json")) as f:
        good = json.load(f)
    outside = os.path.join(WORK, "ESCAPED-convergence.png")
    for bad in ("../../../ESCAPED", os.path.join(WORK, "ESCAPED"), ".hidden", "a/b", ""):
        rep = json.loads(json.dumps(good))
        rep["cases"][0]["id"] = bad
        with open(os.path.join(out, "report.json"), "w") as f:
            json.dump(rep, f)
        r = run("plot", out)
        check(one_line(r, 2, "report.json", "cases[0].id"))
        assert not os.path.exists(outside) and not os.path.exists(os.path.join(out, "figures"))
    with open(os.path.join(out, "report.json"), "w") as f:
        json.dump(good, f)
    check(None if run("plot", out).returncode == 0 else "the valid report must draw")


def test_symbolic_links_are_refused_not_replaced() -> None:
    out = figures_dir_with_user_files()
    target = os.path.join(WORK, "elsewhere.txt")
    with open(target, "w") as f:
        f.write("keep\n")
    link = os.path.join(WORK, "junit-link.xml")
    if os.path.lexists(link):
        os.unlink(link)
    os.symlink(target, link)
    cpath = write_case(case("out-a"))
    r = run("run", cpath, "--out", fresh("links"), "--junit", link, "-q", "--shard", "none")
    check(one_line(r, 3, link))
    fig = os.path.join(out, "figures", "out-a-convergence.png")
    os.unlink(fig)
    os.symlink(target, fig)
    r = run("plot", out)
    assert r.returncode == 3 and fig in r.stderr and "Traceback" not in r.stderr, r.stderr[-500:]
    os.unlink(fig)
    md = os.path.join(out, "report.md")
    os.unlink(md)
    os.symlink(target, md)
    check(one_line(run("run", cpath, "--out", out, "-q", "--shard", "none"), 3, md))
    os.unlink(md)
    shutil.rmtree(os.path.join(out, "series"))
    os.symlink(WORK, os.path.join(out, "series"))
    r = run("run", cpath, "--figures", "--out", out, "-q", "--shard", "none")
    check(one_line(r, 3, os.path.join(out, "series")))
    with open(target) as f:
        assert f.read() == "keep\n"
    assert os.path.islink(link) and os.path.islink(os.path.join(out, "series"))


def test_output_paths() -> None:
    out = fresh("paths")
    cpath = write_case(case("out-a"))
    for args, words in ((["--out", out, "--junit", os.path.join(out, "report.json")],
                         ["--junit", "report.json"]),
                        (["--out", out, "--junit", os.path.join(out, ".", "report.md")],
                         ["--junit", "report.md"]),
                        (["--out", out, "--junit", ""], ["--junit", "empty"]),
                        (["--out", ""], ["--out", "empty"])):
        r = run("run", cpath, *args, "-q", "--shard", "none")
        check(one_line(r, 2, *words))
        assert not os.path.exists(os.path.join(out, "report.json")), args
    check(one_line(run("plot", ""), 2, "empty"))
    # the negative control: a --junit beside the reports is written
    r = run("run", cpath, "--out", out, "--junit", os.path.join(out, "junit.xml"), "-q",
            "--shard", "none")
    assert r.returncode == 0 and os.path.isfile(os.path.join(out, "junit.xml")), r.stderr


# ---- item 8: plot.py's inputs --------------------------------------------------------------------

def plotted_dir() -> str:
    out = fresh("inputs")
    r = run("run", write_case(case("out-a")), "--figures", "--out", out, "-q", "--shard", "none")
    assert r.returncode == 0, r.stderr[-500:]
    return out


def test_bad_inputs_exit_2_with_one_line() -> None:
    out = plotted_dir()
    series = os.path.join(out, "series", "out-a.json")
    os.rename(series, series + ".orig")
    with open(series, "wb") as f:  # sparse: one byte over the limit, no disk used
        f.truncate(sio.SERIES_LIMIT + 1)
    t0 = time.monotonic()
    check(one_line(run("plot", out), 2, series, "too large"))
    assert time.monotonic() - t0 < 20
    os.unlink(series)
    os.symlink(series + ".orig", series)
    check(one_line(run("plot", out), 2, series, "symbolic link"))
    os.unlink(series)
    os.rename(series + ".orig", series)
    report = os.path.join(out, "report.json")
    with open(report) as f:
        good = json.load(f)
    bad = json.loads(json.dumps(good))
    bad["cases"][0]["checks"] = 5
    for text, key in (("{}", "cases"), ("[1, 2", "malformed JSON"), (json.dumps(bad), "checks")):
        with open(report, "w") as f:
            f.write(text)
        check(one_line(run("plot", out), 2, report, key))
    with open(report, "w") as f:
        json.dump(good, f)
    shutil.rmtree(os.path.join(out, "figures"))
    with open(os.path.join(out, "figures"), "w") as f:
        f.write("a file\n")
    check(one_line(run("plot", out), 2, os.path.join(out, "figures"), "not a directory"))
    os.unlink(os.path.join(out, "figures"))
    r = run("plot", out)  # the negative control: the same directory, repaired, draws
    assert r.returncode == 0, r.stderr[-500:]


def test_safeio_bounds_are_tight() -> None:
    d = fresh("safeio")
    os.makedirs(d)
    p = os.path.join(d, "x.json")
    with open(p, "w") as f:
        f.write("[1, 2, 3]")
    assert sio.load_json(p, 9) == [1, 2, 3]
    try:
        sio.load_json(p, 8)
        raise AssertionError("a file one byte over the limit was read")
    except sio.InputProblem as e:
        assert "too large" in str(e)
    for good in ("a", "osc-orders", "A.b_c-9", "x" * 100):
        assert sio.output_name(good, ".json") == good + ".json"
    for bad in ("", "../x", "/abs", ".hidden", "-x", "a/b", "x" * 101, None, 3):
        try:
            sio.output_name(bad, ".json")
            raise AssertionError(f"{bad!r} was taken as a file name")
        except sio.InputProblem:
            pass
    # the report's keys: a valid minimal case passes, one flipped type (a verdict 1 for true, a
    # step size "0.1") is refused naming its key
    minimal: Any = {"cases": [{"id": "a", "title": "", "source": "", "dt_ladder": [0.1],
                               "checks": [{"name": "c", "passed": True}],
                               "runs": [{"method": "m", "dt": 0.1}], "method_metrics": {}}]}
    assert sio.validate_report(minimal, "r") is None
    edits: List[Tuple[Tuple[Any, ...], Any, str]] = [
        (("checks", 0, "passed"), 1, "cases[0].checks[0].passed"),
        (("dt_ladder", 0), "0.1", "cases[0].dt_ladder[0]"),
        (("runs", 0, "method"), None, "cases[0].runs[0].method"),
        (("figures",), True, "cases[0].figures")]
    for path, value, key in edits:
        broken: Any = json.loads(json.dumps(minimal))
        obj = broken["cases"][0]
        for k in path[:-1]:
            obj = obj[k]
        obj[path[-1]] = value
        problem = sio.validate_report(broken, "r")
        assert problem is not None and problem.startswith(f"r: {key}:"), (path, problem)
    # a manifest naming anything but a plain name removes nothing outside
    victim = os.path.join(WORK, "victim.txt")
    with open(victim, "w") as f:
        f.write("keep\n")
    sub = os.path.join(d, "figures")
    os.makedirs(sub)
    with open(os.path.join(sub, sio.MANIFEST), "w") as f:
        f.write(sio.MANIFEST_HEADER + "../../victim.txt\n" + victim + "\nown.png\n")
    with open(os.path.join(sub, "own.png"), "w") as f:
        f.write("x")
    sio.remove_listed(sub)
    assert os.path.exists(victim) and not os.path.exists(os.path.join(sub, "own.png"))


# ---- item 4: signals -----------------------------------------------------------------------------

def many_cases(n: int) -> List[str]:
    """n small cases: their runs take little, their 2n figures a few seconds."""
    return [write_case(case(f"sig-{i:03d}")) for i in range(n)]


def figure_script_groups(pid: int) -> List[int]:
    """The process groups of pid's children (the figure script runs in its own)."""
    groups = []
    for p in os.listdir("/proc"):
        try:
            with open(f"/proc/{p}/stat") as f:
                fields = f.read().rsplit(")", 1)[1].split()
        except (OSError, IndexError):
            continue
        if p.isdigit() and int(fields[1]) == pid:
            groups.append(int(fields[2]))
    return groups


def group_members(pgid: int) -> List[str]:
    """The processes of group pgid that are not zombies: "pid state command"."""
    out = []
    for p in os.listdir("/proc"):
        try:
            with open(f"/proc/{p}/stat") as f:
                head, tail = f.read().rsplit(")", 1)
        except (OSError, ValueError):
            continue
        fields = tail.split()
        if p.isdigit() and int(fields[2]) == pgid and fields[0] != "Z":
            out.append(f"{p} {fields[0]} {head.split('(', 1)[-1]}")
    return out


def group_alive(pgid: int) -> bool:
    """Whether group pgid still has a live process 2 s from now (dampsym waits for the script
    itself; after a second signal it kills the group and exits at once, so the kernel may take a
    moment to end the workers)."""
    deadline = time.monotonic() + 2.0
    while group_members(pgid) and time.monotonic() < deadline:
        time.sleep(0.05)
    return bool(group_members(pgid))


def drawing(out: str) -> Callable[[], bool]:
    """Whether the figure script has written its first figure into out/figures."""
    def started() -> bool:
        try:
            return any(n.endswith(".png") for n in os.listdir(os.path.join(out, "figures")))
        except FileNotFoundError:
            return False
    return started


STDERR = "stderr.txt"  # under WORK: dampsym's stderr in signal_when


def stderr_says(text: str) -> Callable[[], bool]:
    def said() -> bool:
        with open(os.path.join(WORK, STDERR)) as f:
            return text in f.read()
    return said


def signal_when(args: List[str], ready: Callable[[], bool], sigs: Sequence[int],
                to_group: bool = False,
                with_script: bool = False) -> Tuple[int, str, List[int]]:
    """Starts dampsym (in a session of its own), sends sigs once ready() (10 ms apart, to its
    process group if to_group) and, with_script, once the figure script has been seen (dampsym
    starts it after its last note, so the note alone can come first), and returns its exit
    status, stderr and the figure script's process groups seen."""
    with open(os.path.join(WORK, STDERR), "w") as err_file:
        p = subprocess.Popen([DAMPSYM, *args], stdout=subprocess.DEVNULL, stderr=err_file,
                             start_new_session=True)
    groups: List[int] = []
    deadline = time.monotonic() + 60
    while (not ready() or (with_script and not groups)) and p.poll() is None \
            and time.monotonic() < deadline:
        groups += [g for g in figure_script_groups(p.pid) if g not in groups]
        time.sleep(0.01)
    groups += [g for g in figure_script_groups(p.pid) if g not in groups]
    assert p.poll() is None, "finished before the signal"
    for s in sigs:
        (os.killpg if to_group else os.kill)(p.pid, s)
        time.sleep(0.01)
    try:
        p.wait(timeout=30)
    except subprocess.TimeoutExpired:  # still running 30 s after the signal: a failure
        for g in [p.pid, *groups]:
            try:
                os.killpg(g, signal.SIGKILL)
            except ProcessLookupError:
                pass
        p.wait()
        return -1, "still running 30 s after the signal", groups
    with open(os.path.join(WORK, STDERR)) as f:
        return p.returncode, f.read(), groups


def settled(out: str) -> None:
    """No figure script left: nothing more appears in out/figures after dampsym has exited."""
    before = sorted(os.listdir(os.path.join(out, "figures")))
    time.sleep(0.5)
    assert sorted(os.listdir(os.path.join(out, "figures"))) == before


def test_signal_during_runs_of_run_figures() -> None:
    long = write_case(case("sig-long", t_end=1e6, dt_ladder=[2e-3, 1e-3], output_dt=1e5))
    for sig in (signal.SIGINT, signal.SIGTERM):
        out = fresh(f"sig-runs-{sig}")
        code, err, groups = signal_when(["run", long, "--figures", "--out", out, "--shard",
                                         "none", "--time-budget", "0"],
                                        stderr_says("predicted duration"), [sig],
                                        with_script=True)
        assert code == 128 + sig and "internal error" not in err, (code, err)
        # the figure script started with the run (to import matplotlib meanwhile) is gone too
        assert groups and not any(group_alive(g) for g in groups), \
            [group_members(g) for g in groups]
        with open(os.path.join(out, "report.json")) as f:
            rep = json.load(f)
        assert rep["interrupted"]["signal"] == signal.Signals(sig).name, rep.get("interrupted")


def test_signal_while_drawing() -> None:
    cases = many_cases(12)
    for sig, to_group, sigs in ((signal.SIGTERM, False, [signal.SIGTERM]),
                                (signal.SIGINT, True, [signal.SIGINT]),
                                (signal.SIGTERM, False, [signal.SIGTERM, signal.SIGTERM])):
        out = fresh(f"sig-draw-{sig}-{to_group}-{len(sigs)}")
        code, err, groups = signal_when(["run", *cases, "--figures", "--out", out, "--jobs", "1",
                                         "-q", "--shard", "none"], drawing(out), sigs, to_group)
        assert code == 128 + sig and "Traceback" not in err, (code, err)
        assert groups and not any(group_alive(g) for g in groups), \
            [group_members(g) for g in groups]
        settled(out)
        with open(os.path.join(out, "report.json")) as f:
            assert len(json.load(f)["cases"]) == 12  # the runs had finished: the report is whole


def test_signal_to_plot() -> None:
    out = fresh("sig-plot")
    r = run("run", *many_cases(12), "--out", out, "-q", "--shard", "none")  # 12 convergence figures
    assert r.returncode == 0, r.stderr[-500:]
    shutil.rmtree(os.path.join(out, "figures"), ignore_errors=True)
    code, err, groups = signal_when(["plot", out, "--jobs", "2"], drawing(out), [signal.SIGTERM])
    assert code == 143 and "Traceback" not in err, (code, err)
    assert groups and not any(group_alive(g) for g in groups), [group_members(g) for g in groups]
    settled(out)
    # plot.py itself, signalled alone while drawing (SIGINT: Ctrl-C): quiet, 130, workers gone
    shutil.rmtree(os.path.join(out, "figures"))
    script = os.path.join(HERE, "..", "..", "tools", "figures", "plot.py")
    p = subprocess.Popen(["/usr/bin/python3", script, out, "--jobs", "2"],
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                         start_new_session=True)
    while not drawing(out)() and p.poll() is None:
        time.sleep(0.01)
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=30)
    assert p.returncode == 130 and "Traceback" not in err, (p.returncode, err)
    assert not group_alive(p.pid), group_members(p.pid)


def main() -> int:
    if not DAMPSYM or not WORK:
        print(__doc__)
        return 2
    shutil.rmtree(WORK, ignore_errors=True)
    os.makedirs(WORK)
    failures = 0
    for name, fn in list(globals().items()):
        if name.startswith("test_") and callable(fn) and \
                (len(sys.argv) <= 3 or any(w in name for w in sys.argv[3:])):
            t0 = time.monotonic()
            try:
                fn()
                print(f"ok   {name} ({time.monotonic() - t0:.1f} s)")
            except AssertionError as e:
                failures += 1
                print(f"FAIL {name}: {e}")
    print(f"test_outputs: {failures} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
