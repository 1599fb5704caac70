"""dampsym.run against `dampsym run`: the same report before its provenance, byte for byte; the
command line's messages as exceptions; numpy arrays; the GIL released while C++ runs."""

from __future__ import annotations

import json
import pathlib
import threading
import time

import numpy as np
import pytest

import dampsym
from conftest import ROOT, before_provenance, run_cli

CASE = "verify/cases/osc-orders.json"


def test_report_is_the_cli_report_byte_for_byte(dampsym_bin: str, tmp_path: pathlib.Path,
                                                monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)
    done = run_cli(dampsym_bin, "run", CASE, "--out", str(tmp_path), "--quiet")
    assert done.returncode == 0, done.stderr
    cli_text = (tmp_path / "report.json").read_text()
    report = dampsym.run(CASE)
    assert before_provenance(report.text) == before_provenance(cli_text)
    # the dict is that text: every number the same double
    assert json.loads(cli_text)["cases"][0]["runs"][3]["final_state"] == \
        report["cases"][0]["runs"][3]["final_state"].tolist()
    assert report.exit_status == 0 and report["summary"]["checks_failed"] == 0


def test_a_changed_case_changes_the_report(monkeypatch: pytest.MonkeyPatch) -> None:
    # the comparison above can fail: the same case with another gamma differs before provenance
    monkeypatch.chdir(ROOT)
    case = json.loads((ROOT / CASE).read_text())
    a = dampsym.run(case, time_budget=0)
    case["problem"]["gamma"] = case["problem"]["gamma"] * (1 + 1e-12)
    b = dampsym.run(case, time_budget=0)
    assert before_provenance(a.text) != before_provenance(b.text)


def test_a_dict_case_runs_as_its_file(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)
    from_file = dampsym.run(CASE, time_budget=0)
    from_dict = dampsym.run(json.loads((ROOT / CASE).read_text()), time_budget=0)
    assert from_dict["cases"][0]["file"] == "<case json>"
    for a, b in zip(from_file["cases"][0]["runs"], from_dict["cases"][0]["runs"]):
        assert isinstance(a["final_state"], np.ndarray)
        assert a["final_state"].tobytes() == b["final_state"].tobytes()


def test_bad_input_is_the_cli_message(dampsym_bin: str, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)
    bad = "tests/data/bad/bad-dt-negative.json"
    done = run_cli(dampsym_bin, "run", bad)
    assert done.returncode == 2
    with pytest.raises(dampsym.InputError) as e:
        dampsym.run(bad)
    assert isinstance(e.value, ValueError)
    assert "dampsym: " + str(e.value) + "\n" == done.stderr
    with pytest.raises(dampsym.InputError, match="unknown method 'no-such-method'"):
        dampsym.run({**json.loads((ROOT / CASE).read_text()), "methods": ["no-such-method"]})
    with pytest.raises(dampsym.InputError, match="--jobs"):
        dampsym.run(CASE, jobs=0)


def test_figures_keep_the_series_as_arrays(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)
    report = dampsym.run("verify/cases/osc-drift-fig47.json", figures=True, time_budget=0)
    series = report["series"]["osc-drift-fig47"]
    kept = [s for r in series["runs"] for s in r["series"].values() if "same_as_run" not in s]
    assert kept and all(isinstance(s["t"], np.ndarray) for s in kept)
    assert all(s["y"].size == s["t"].size for s in kept if "y" in s)
    orbits = [s["states"] for s in kept if "states" in s]
    assert orbits and all(o.ndim == 2 and o.shape[1] == 2 for o in orbits)
    assert "series" not in dampsym.run("verify/cases/osc-drift-fig47.json", time_budget=0)


def test_the_gil_is_released_while_cpp_runs(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)
    done = threading.Event()

    def work() -> None:
        dampsym.run(CASE)  # about 0.5 s of C++ (its work-precision timing)
        done.set()

    t = threading.Thread(target=work)
    gap = 0.0
    start = last = time.perf_counter()
    t.start()
    while not done.is_set():
        now = time.perf_counter()
        gap, last = max(gap, now - last), now
    t.join()
    # the main thread kept running throughout: a GIL held by the C++ run would stop it for nearly
    # the whole run (at least 24 x 0.02 s of work-precision timing); the Python parts of work()
    # take a few ms
    assert last - start > 0.4 and gap < 0.5 * (last - start), (last - start, gap)


def test_list_and_cli() -> None:
    ids = [c["id"] for c in dampsym.list("--filter", "osc-*")]
    assert "osc-orders" in ids and all(i.startswith("osc-") for i in ids)
    assert dampsym.cli(["--version"]).stdout.startswith("dampsym ")
    assert dampsym.version().startswith("dampsym ")
    assert dampsym.cli(["run", "no-such-case"]).returncode == 2
    with pytest.raises(dampsym.InputError):
        dampsym.list("--filter", "no-such-*")


def test_runs_from_several_threads_at_once(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)
    cases = []
    for k in range(3):
        case = json.loads((ROOT / CASE).read_text())
        case["id"] = f"osc-orders-thread-{k}"
        case["problem"]["gamma"] = 0.01 * (k + 1)
        cases.append(case)
    alone = [dampsym.run(c, time_budget=0) for c in cases]
    together: list[dampsym.Report] = [dampsym.Report()] * 3

    def work(k: int) -> None:
        together[k] = dampsym.run(cases[k], time_budget=0)

    threads = [threading.Thread(target=work, args=(k,)) for k in range(3)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for a, b in zip(alone, together):
        assert before_provenance(a.text) == before_provenance(b.text)
