"""Cases the cross-check has never seen: a case file outside verify/cases (the user's own, a copy
with other parameters), and the tolerances such cases exposed.

Unit tests (no dampsym needed): the case file the report names is read (and a hostile `file` is
not), the relative error's band sits at the maximum's point, the energy's halves are the C++ ones,
the ratio deviation's band is as wide as its round-off where r_n is resolved to a per cent.

With --bin (ctest crosscheck.heldout, ~10 s): four default-suite cases copied under new ids with
other parameters into a directory of their own and named relative to it (the pendulum of HLW Fig 1.2 near its separatrix, the over-damped oscillator's
H_gamma law, the driven pendulum's orders, B Fig 3.4's energy balance on a ladder) are run by
dampsym and cross-checked with --strict; every comparison agrees or is not comparable (before the
fixes the pendulum's energy metrics were compared on two output points instead of 1001, 0.0298
against 0.235, and the energy-balance residual of the fine step on the coarse step's grid, 93
points against 193). Negative controls: a 3e-6
relative change of one energy metric is a disagreement, and so is a check's threshold changed in
the report (the file's is read); with the files moved away the inputs come from the report, and
the structure records say so."""
from __future__ import annotations

import copy
import json
import math
import os
import subprocess
import sys
from typing import Any, Dict, List

import numpy as np
import pytest

from verify import xcase, xmetrics
from verify.diagnostics.error import max_rel_band

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
Json = Dict[str, Any]


def _write(path: str, doc: Any) -> str:
    with open(path, "w") as fh:
        json.dump(doc, fh)
    return path


def test_recorded_case_file(tmp_path: Any) -> None:
    good = _write(str(tmp_path / "mine.json"), {"id": "mine", "t_end": 1.0})
    assert xcase.recorded_case_file({"id": "mine", "file": good}) == good
    # another id, a directory, a missing file, not JSON, no file, too large: not read
    assert xcase.recorded_case_file({"id": "other", "file": good}) is None
    assert xcase.recorded_case_file({"id": "mine", "file": str(tmp_path)}) is None
    assert xcase.recorded_case_file({"id": "mine", "file": str(tmp_path / "none.json")}) is None
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    assert xcase.recorded_case_file({"id": "mine", "file": str(bad)}) is None
    assert xcase.recorded_case_file({"id": "mine"}) is None
    assert xcase.recorded_case_file({"id": "mine", "file": 3}) is None
    limit = xcase.CASE_FILE_LIMIT
    try:
        xcase.CASE_FILE_LIMIT = 8
        assert xcase.recorded_case_file({"id": "mine", "file": good}) is None
    finally:
        xcase.CASE_FILE_LIMIT = limit


def test_recorded_file_wins_over_verify_cases(tmp_path: Any) -> None:
    """A user's copy of a suite case under the same id, with another gamma: its own numbers."""
    with open(xcase.case_index()["pend-fig48"]) as fh:
        spec = json.load(fh)
    spec["problem"]["gamma"] = 0.05
    mine = _write(str(tmp_path / "pend-fig48.json"), spec)
    got = xcase.load_spec("pend-fig48", {}, xcase.recorded_case_file({"id": "pend-fig48", "file": mine}))
    assert got is not None and got["_file"] == mine and got["problem"]["gamma"] == 0.05
    suite = xcase.load_spec("pend-fig48", {}, None)
    assert suite is not None and suite["problem"]["gamma"] == 0.025


def test_max_rel_band_at_the_maximum() -> None:
    """The band of max_n e_n/|z_n|: w at the maximum, not bound / min |z| (a point where |z| is
    100x smaller and the ratio far below the maximum); a rival point within reach widens it."""
    e = np.array([1e-6, 1e-9, 0.9e-6])
    rn = np.array([1.0, 1e-2, 1.0])
    assert max_rel_band(e, rn, 1e-12) == pytest.approx(1e-12, rel=1e-9)
    assert max_rel_band(e, rn, 1e-12) < 1e-12 / 1e-2
    # a rival within reach: its ratio plus its band above the maximum's ratio
    e2 = np.array([1e-6, 0.99995e-8, 0.0])
    rn2 = np.array([1.0, 1e-2, 1.0])
    assert max_rel_band(e2, rn2, 1e-12) == pytest.approx(0.99995e-6 + 1e-10 - 1e-6, rel=1e-6)
    # the band holds: every e_n moved by at most the bound moves the maximum by at most the band
    rng = np.random.default_rng(5)
    for _ in range(200):
        e3, rn3 = rng.uniform(0, 1e-6, 8), rng.uniform(1e-3, 1.0, 8)
        b = max_rel_band(e3, rn3, 1e-9)
        moved = np.max((e3 + rng.uniform(-1e-9, 1e-9, 8)) / rn3)
        assert abs(moved - np.max(e3 / rn3)) <= b * (1 + 1e-12)


class _Line:
    """H = q on a state [q]: metric_energy's |H_n - H_0| is |q_n - q_0|."""
    energy_scale = None

    @staticmethod
    def energy(traj: Any) -> Any:
        return np.asarray(traj)[:, 0]


def test_energy_halves_as_the_cpp() -> None:
    """Points 0..P/2 are the first half, the rest the second (energy_diagnostic.cpp): with the
    largest change at the middle point the ratio is 2/3, not 1 (the middle in both halves)."""
    traj = np.array([[0.0], [1.0], [3.0], [2.0], [1.0]])
    out = xmetrics.metric_energy(_Line(), traj, np.arange(5.0))
    assert out["growth_ratio"] == pytest.approx(2.0 / 3.0, rel=1e-15)
    one = xmetrics.metric_energy(_Line(), np.array([[0.0], [1.0]]), np.arange(2.0))
    assert one["growth_ratio"] == 0.0


def test_ratio_band_where_resolved_to_a_per_cent() -> None:
    """The over-damped oscillator's H_gamma (gamma 1.75 > omega 1.15): at t = 10 the terms of
    H_gamma outgrow it by e^{2 beta t} ~ 3e11, so u_n ~ 6e-5 where r_n is still resolved by
    u_n <= 1e-2 |r_n|; the band must say so (it was capped at 1e-8)."""
    prob, why = xmetrics.make_problem({"problem": {"id": "oscillator", "params": {
        "omega": 1.15, "gamma": 1.75, "q0": 0.7, "p0": 0.0}}})
    assert prob is not None, why
    times = np.linspace(0.0, 10.0, 51)
    traj = prob.exact(0.0, times) * (1.0 + 0.3 * times[:, None] / 10.0)  # r_n up to ~0.7
    d = xmetrics.metric_invariants(prob, traj, times)["H_gamma"]
    assert not isinstance(d["max_global_ratio_dev"], xmetrics.Undef)
    assert d["_ratio_u"] > 1e-6


def _heldout_cases(work: str) -> List[str]:
    """Four suite cases under new ids with other parameters, in a directory of their own; B Fig
    3.4's energy balance on a ladder of two step sizes without output_dt (its output grid is the
    coarse step's, its residual over each run's own steps)."""
    changes = {"pendulum-hlw-fig12": {"p0": 1.82},
               "osc-overdamped-hgamma-law": {"omega": 1.15, "gamma": 1.75, "q0": 0.7},
               "driven-pendulum-orders": None,
               "pend-fig34-energy-balance": {"gamma": 0.8}}
    ladders = {"pend-fig34-energy-balance": {"t_end": 4.0, "dt_ladder": [0.04, 0.02]}}
    paths = []
    for cid, params in changes.items():
        with open(xcase.case_index()[cid]) as fh:
            spec = json.load(fh)
        spec["id"], spec["suites"] = cid + "-heldout", ["heldout"]
        if cid in ladders:
            spec.pop("dt", None)
            spec.update(ladders[cid])
        for k, v in (params or {k: v * 1.15 for k, v in spec["problem"].items()
                                if isinstance(v, float) and v != 0.0}).items():
            spec["problem"][k] = v
        paths.append(_write(os.path.join(work, spec["id"] + ".json"), spec))
    return paths


def _crosscheck(report: Json, work: str, tag: str) -> Json:
    path = _write(os.path.join(work, tag + ".json"), report)
    subprocess.run([sys.executable, "-m", "verify.crosscheck", path, "--out", os.path.join(work, tag),
                    "--strict", "--jobs", "2"], cwd=ROOT, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)
    with open(os.path.join(work, tag, "crosscheck.json")) as fh:
        return dict(json.load(fh))


def test_heldout_cases_agree(dampsym_bin: str, workdir: str) -> None:
    work = os.path.join(workdir, "heldout")
    os.makedirs(work, exist_ok=True)
    out = os.path.join(work, "report")
    # named relative to the directory dampsym runs in: the report records them absolute
    names = [os.path.basename(p) for p in _heldout_cases(work)]
    rc = subprocess.run([os.path.abspath(dampsym_bin), "run", *names, "--out", out, "--jobs", "2", "-q"],
                        cwd=work, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode
    assert rc in (0, 1)  # a check may fail at other parameters; that is not the question
    with open(os.path.join(out, "report.json")) as fh:
        report = json.load(fh)
    assert sorted(c["file"] for c in report["cases"]) == sorted(os.path.join(work, n) for n in names)
    s = _crosscheck(report, work, "good")["summary"]
    assert s["comparisons"]["disagree"] == 0 and s["checks"]["not reproduced"] == 0, s
    bad = copy.deepcopy(report)
    run = next(r for c in bad["cases"] if c["id"] == "pendulum-hlw-fig12-heldout"
               for r in c["runs"] if r["method"] == "symplectic-euler")
    run["metrics"]["energy"]["max_abs_change"] *= 1 + 3e-6  # the band is rel 1e-6 + round-off
    assert _crosscheck(bad, work, "planted")["summary"]["comparisons"]["disagree"] >= 1
    # the thresholds come from the held-out file, not the report: a report that lowers one
    # (the Euler negative control's 1 -> 40, which would then fail) is caught; without the file
    # (moved away) the inputs come from the report, and the cross-check says so
    moved = copy.deepcopy(report)
    chk = next(k for c in moved["cases"] if c["id"] == "pendulum-hlw-fig12-heldout"
               for k in c["checks"] if k["method"] == "euler" and k["op"] == "ge")
    chk["expected"] = 40.0
    xc = _crosscheck(moved, work, "threshold")
    assert xc["summary"]["checks"]["disagree"] + xc["summary"]["structure"]["disagree"] >= 1
    for c in moved["cases"]:
        c["file"] = os.path.join(work, "moved", os.path.basename(c["file"]))
    notes = [n for r in _crosscheck(moved, work, "lost")["structure"] for n in r["notes"]]
    assert notes.count("(no case file: inputs from the report)") == 4, notes


def test_unstable_ladder_runs(dampsym_bin: str, workdir: str) -> None:
    """B's Klein-Gordon cases to t = 20 on a ladder whose coarse step (0.1) is unstable for
    csv1/csv2 (their states grow by decades and two runs a round-off apart drift apart: our own
    ensemble spreads by D ~ 1) and makes Heun's d(t) sensitive (D ~ 1e-6): the invariants' and
    d(t)'s metrics of such runs get the bands of our ensemble (they were compared at rel 1e-6; at
    t = 50 the momentum residuals 2.5e105 and 7.9e105 disagreed, as did Heun's d(t) range, 1.4e-6
    apart; 4 disagreements here without the bands). Negative control: a stable run's metric moved
    by 3e-6 still disagrees."""
    work = os.path.join(workdir, "unstable")
    os.makedirs(work, exist_ok=True)
    names = []
    for cid in ("pde-kg-momentum", "pde-kg-fig52-drift"):
        with open(xcase.case_index()[cid]) as fh:
            spec = json.load(fh)
        spec["id"], spec["suites"] = cid + "-ladder", ["heldout"]
        spec.pop("dt")
        spec["dt_ladder"], spec["t_end"] = [0.1, 0.05], 20.0
        names.append(_write(os.path.join(work, spec["id"] + ".json"), spec))
    out = os.path.join(work, "report")
    rc = subprocess.run([os.path.abspath(dampsym_bin), "run", *names, "--out", out, "--jobs", "2", "-q"],
                        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode
    assert rc == 1  # csv1/csv2 at dt = 0.1 fail their accuracy checks: not the question
    with open(os.path.join(out, "report.json")) as fh:
        report = json.load(fh)
    xc = _crosscheck(report, work, "good")
    assert xc["summary"]["comparisons"]["disagree"] == 0, xc["summary"]
    assert any(r["verdict"] == "not comparable" and r["method"] == "csv1" for r in xc["runs"])
    bad = copy.deepcopy(report)
    run = next(r for c in bad["cases"] if c["id"] == "pde-kg-momentum-ladder"
               for r in c["runs"] if r["method"] == "rk4" and r["dt"] == 0.05)
    run["metrics"]["invariants"]["momentum"]["max_step_res"] *= 1 + 3e-6
    assert _crosscheck(bad, work, "planted")["summary"]["comparisons"]["disagree"] >= 1


def test_no_defined_step_residual(dampsym_bin: str, workdir: str) -> None:
    """HLW (1.8) on Lotka-Volterra at dt = 0.24 runs to a state (0, -3.6e56) at which the scale
    of I is undefined at every step: dampsym reported 0 for the numerator and the scale "at the
    maximum" of no step (the cross-check, computing none, called them not reproduced); both are
    undefined now, in dampsym and the cross-check, and the run is reproduced."""
    work = os.path.join(workdir, "no-defined-step")
    os.makedirs(work, exist_ok=True)
    with open(xcase.case_index()["lotka-volterra-fig11-symplectic-euler"]) as fh:
        spec = json.load(fh)
    spec.update(id="lv-se-coarse", suites=["heldout"], dt=0.24)
    case = _write(os.path.join(work, "lv-se-coarse.json"), spec)
    out = os.path.join(work, "report")
    subprocess.run([os.path.abspath(dampsym_bin), "run", case, "--out", out, "-q"],
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(os.path.join(out, "report.json")) as fh:
        report = json.load(fh)
    inv = next(r for r in report["cases"][0]["runs"]
               if r["method"] == "symplectic-euler-partitioned")["metrics"]["invariants"]["I"]
    assert inv["max_step_abs"] is None and inv["scale_at_max_step_res"] is None
    assert "scale not a positive normal number" in inv["undefined"]["max_step_abs"]
    s = _crosscheck(report, work, "xc")["summary"]
    assert s["runs"]["not reproduced"] == 0 and s["comparisons"]["disagree"] == 0, s


def _driven_at_h1() -> Any:
    from verify import xproblems
    return xproblems.make_problem("driven-pendulum", {"gamma": 0.375, "lambda": 1.5, "f": 3.375,
                                                      "q0": 0.0, "p0": 0.0})


def test_large_step_newton_falls_back_to_full_newton(monkeypatch: Any) -> None:
    """cs-driven-pendulum's problem at h = 1 (a held-out ladder [1, 0.5]): the simplified
    iteration with a matrix from an earlier step fails at step 7 where dampsym's full Newton
    converges (it reported 'solve-failed at 7' against dampsym's 'ok'); the step is then solved
    by full Newton, in the compiled and the plain loops alike. Controls: without the fallback the
    run fails at step 7; a step with no real solution (z' = z^2 + 1, z = 1, h = 2, implicit Euler)
    still fails."""
    from verify import xcache, xmethods as xm, xrun
    monkeypatch.setitem(xcache._state, "dir", None)    # computed here, never read back
    prob = _driven_at_h1()
    for m in ("cimp", "glifrk1", "etdrk2"):
        r = xrun.integrate(m, prob, 1.0, 50, 0.0)
        assert r["status"] == "ok" and r["steps"] == 50, (m, r["message"])

    def no_fallback(*_: Any) -> Any:
        raise xm.SolveFailed("Newton did not converge")
    with monkeypatch.context() as mp:
        mp.setattr(xm, "full_newton_step", no_fallback)
        mp.setattr(xm, "full_newton_fallback", no_fallback)
        r = xrun.integrate("cimp", prob, 1.0, 50, 0.0)
    assert r["status"] == "solve-failed" and r["steps"] == 7, r
    riccati = xm.rk_family_step(lambda t, z: z * z + 1.0, xm.plain_coef([[1.0]], [1.0], [1.0]), 2.0, True)
    with pytest.raises(xm.SolveFailed):
        riccati(0.0, np.array([1.0]))


def test_step_jacobian_converged_at_large_steps(monkeypatch: Any) -> None:
    """The complex-step Jacobian of a step whose simplified iteration contracts slowly (cimp at
    h = 1, step 5 of the run above): E_n = |det Psi - e^{-2 gamma h}| <= 1e-14 (dampsym's:
    1e-15). Control: under the round-off test that stopped at an update >= half the previous one
    below 1e-11, the unpolished step gives E_n = 1.1e-11 (the real part ~1e-11 off) and the
    polished one (two full Newton updates) still <= 1e-14."""
    from verify import xcache, xmethods as xm, xrun
    monkeypatch.setitem(xcache._state, "dir", None)
    prob = _driven_at_h1()
    z = xrun.integrate("cimp", prob, 1.0, 5, 0.0)["z"]
    en = lambda P: abs(np.linalg.det(P) - math.exp(-2 * 0.375))  # noqa: E731
    Z = np.asarray(z, float)[None, :] + 1e-30j * np.eye(2)

    def unpolished() -> float:
        return float(en((np.imag(xm.make_stepper("cimp", prob, 1.0)(5.0, Z)[0]) / 1e-30).T))
    assert en(xrun.step_jacobian("cimp", prob, 1.0, 5.0, z)) <= 1e-14 and unpolished() <= 1e-14
    old = xm.settled
    monkeypatch.setattr(xm, "settled", lambda m, last, it, zero=False: bool(
        old(m, last, it, zero) or (it >= 3 and m >= 0.5 * last and m <= 1e-11)))
    assert unpolished() >= 1e-12
    assert en(xrun.step_jacobian("cimp", prob, 1.0, 5.0, z)) <= 1e-14


def _csv2_by_hand(g: float, w: float, h: float, q: float, p: float) -> Any:
    """F (2.16) for the oscillator (V = w^2 q^2 / 2, T = p^2 / 2), written out."""
    a, b, e = 1 + g * h / 2, 1 - g * h / 2, np.exp(-g * h / 2)
    ph = (e * p - h / 2 * w * w * q) / a
    q1 = e * (a * e * q + h * ph) / b
    return q1, e * (b * ph - h / 2 * w * w * q1)


def test_csv2_beyond_gamma_h_2() -> None:
    """csv2 is defined for gamma h != 2 (F (3.22): its region reversed beyond 2; dampsym's
    csv2.hpp runs it): the cross-check's steps (array, scalar and refmath) run it too and agree
    with F (2.16) written out; at gamma h = 2 the q-update is inf (dampsym: diverged), where the
    cross-check used to stop with a traceback (a held-out stress case at gamma h = 2.15)."""
    from verify import refmath, xmethods, xproblems
    g, w, h = 1.44, 0.8, 1.4960609482320342
    prob = xproblems.make_problem("oscillator", {"omega": w, "gamma": g, "q0": 1.4, "p0": 0.0})
    z1, _ = xmethods.make_stepper("csv2", prob, h)(0.0, np.array([1.4, 0.3]))
    want = _csv2_by_hand(g, w, h, 1.4, 0.3)
    assert np.allclose(z1, want, rtol=1e-14, atol=0.0)
    q1, p1 = refmath.make_step("csv2", refmath.Oscillator(w, g, 1.4, 0.3), h)(1.4, 0.3)
    assert np.allclose([q1, p1], want, rtol=1e-14, atol=0.0)
    at2 = xproblems.make_problem("oscillator", {"omega": w, "gamma": 0.5, "q0": 1.4, "p0": 0.0})
    z2, _ = xmethods.make_stepper("csv2", at2, 4.0)(0.0, np.array([1.4, 0.3]))  # gamma h = 2 exactly
    assert np.isinf(z2).all()
    q2, _ = refmath.make_step("csv2", refmath.Oscillator(w, 0.5, 1.4, 0.3), 4.0)(1.4, 0.3)
    assert np.isinf(q2)


def test_det_band_where_the_products_cancel() -> None:
    """det M = M00 M11 - M01 M10 rounds like its products: where they nearly cancel (det
    e^{-4.3} of O(1) entries) the relative band is 8 eps x products / det, not 8 eps."""
    from verify import xfamilies
    from verify.xrunctx import RunCtx
    cx = RunCtx.__new__(RunCtx)
    M = [[0.9, 1.1], [0.8, 1.0]]          # products 0.9 and 0.88: det 0.02
    cx.mm = {"stability.matrix": M, "stability.det_expected": 0.02}
    cx.unc = {}
    band = 8 * np.finfo(float).eps * (0.9 + 0.88) / 0.02
    agree = xfamilies.f_det_err(cx, "stability.det_rel_err", 2.6e-15, 2.6e-15 + 0.9 * band)
    assert agree["status"] in ("agree", "not comparable")
    far = xfamilies.f_det_err(cx, "stability.det_rel_err", 2.6e-15, 2.6e-15 + 1.2 * band)
    assert far["status"] == "disagree"


def test_multivalue_one_step_matrix_not_reproduced() -> None:
    """glm4's one-step matrix acts on its multivalue state, which the cross-check does not build:
    a held-out stability sweep, h^4 trace or stability run of glm4 is "not reproduced" with the
    reason (it stopped the cross-check with KeyError 'glm4'); a one-value method still is."""
    from verify.diagnostics import MethodCtx, stability, stability_sweep, trace_taylor
    from verify import xproblems
    prob = xproblems.make_problem("oscillator", {"omega": 1.5, "gamma": 1.0, "q0": 1.0, "p0": 0.0})
    spec = {"stability_sweep": {"omega": 1.5, "gamma": [0.0, 0.5, 0.25], "h": [0.1, 0.2, 0.1]}}
    for mod in (stability_sweep, trace_taylor):
        rec = mod.method_record(MethodCtx({"id": "x"}, spec, prob, "glm4", {}, [], {}, {}))
        assert rec["verdict"] == "not reproduced" and "multivalue" in rec["reason"]
    ok = stability_sweep.method_record(MethodCtx({"id": "x"}, spec, prob, "csv1", {}, [], {}, {}))
    assert ok["verdict"] != "not reproduced"
    from verify.xrunctx import RunCtx
    cx = RunCtx.__new__(RunCtx)
    cx.prob, cx.method, cx.dt, cx.mm = prob, "glm4", 0.1, {}
    stability.recompute(cx)
    assert cx.mm == {}


def test_glm4_time_dependent_damping_order_4() -> None:
    """BS's GLM under the rigid body's gamma(t) = eps cos(2t)/2: its stages sit at t + c_i h,
    c = A e. The cross-check's plain-float and compiled GLM evaluated both stages at t (right
    only for constant gamma): at eps = 0.5, h = 0.1 it ended 1.6 from the solution (dampsym
    3.75e-4, a held-out method variant of rb-fig37-glifrk). Now fourth order, and the plain-float
    path equals the array path (xmethods.GLM, stage times from the start)."""
    from verify import xproblems, xrun
    prob = xproblems.make_problem("rigid-body", {"I1": 4.0, "I2": 3.0, "I3": 2.0, "epsilon": 0.5,
                                                 "z1": 4.0, "z2": 3.0, "z3": 0.0})
    exact = prob.exact(0.0, np.array([10.0]))[0]
    errs = [float(np.linalg.norm(xrun.integrate("glm4", prob, h, int(round(10.0 / h)), 0.0)["z"] - exact))
            for h in (0.1, 0.05)]
    assert np.log2(errs[0] / errs[1]) > 3.5, errs
    from verify import xmethods, xscalar
    small = xscalar.make("glm4", prob, 0.1)
    assert isinstance(small, xscalar.GLMScalar)
    arr = xmethods.GLM(prob, 0.1)
    ys, ya = small.start(0.0, list(prob.z0)), arr.start(0.0, prob.z0)
    for n in range(5):
        ys, _ = small.step(0.1 * n, ys)
        ya, _ = arr.step(0.1 * n, ya)
    assert np.allclose(np.array(ys), ya, rtol=1e-13, atol=1e-13)


def test_energy_error_band_carries_the_reference() -> None:
    """energy.max_abs_error = max |H(z_ref) - H(z_n)| moves with the reference and the state by
    |grad H| x (state bound + our estimate); its band was round-off alone (gauss3 on the pendulum:
    2.6e-14 against dampsym's 2.4e-13, band 1.1e-13). The gradient's scale is the pendulum's
    |grad H| = sqrt(sin^2 q + p^2); a difference ten times the band still disagrees."""
    from verify import xfamilies, xproblems
    from verify.diagnostics.energy import grad_norm_max
    from verify.xrunctx import RunCtx
    prob = xproblems.make_problem("pendulum", {"gamma": 0.0, "q0": 1.0, "p0": 0.5})
    Z = np.array([[1.0, 0.5], [0.3, -1.2]])
    want = float(np.max(np.hypot(np.sin(Z[:, 0]), Z[:, 1])))
    assert abs(grad_norm_max(prob, Z) - want) <= 1e-6 * want
    cx = RunCtx.__new__(RunCtx)
    cx.prob, cx.nsteps, cx.dt, cx.state_bound = prob, 4000, 0.025, 1e-12
    cx.priv, cx.unc, cx.metrics, cx.mm, cx.chaotic = {"energy.grad_max": want, "error.est": 1e-13}, {}, {}, {}, None
    cx.band, cx.D = {}, 0.0
    band = want * (1e-12 + 1e-13)
    near = xfamilies.f_energy(cx, "energy.max_abs_error", 2.6e-14, 2.6e-14 + 0.9 * band)
    assert near["status"] in ("agree", "not comparable")
    far = xfamilies.f_energy(cx, "energy.max_abs_error", 2.6e-14, 2.6e-14 + 10 * band)
    assert far["status"] == "disagree"
    # a change of H alone (no reference in it) keeps its round-off band
    alone = xfamilies.f_energy(cx, "energy.max_abs_change", 2.6e-14, 2.6e-14 + 0.9 * band)
    assert alone["status"] == "disagree"


def test_implicit_tableau_power_formula() -> None:
    """dampsym gives the power-boundary formula of every plain Runge-Kutta tableau (implicit
    midpoint, implicit Euler, Gauss), not only the explicit ones: the cross-check's R(z) =
    1 + z b^T (I - z A)^{-1} 1 against the closed forms, and a held-out sweep of implicit-midpoint
    now has the two metrics it lacked (power_mismatch_points, max_power_boundary_mismatch_cells)."""
    from verify import xsweep
    z = np.array([-0.5 + 0.3j, -1.0, -3.0 + 2.0j])
    cases = {"implicit-euler": 1 / (1 - z), "implicit-midpoint": (1 + z / 2) / (1 - z / 2),
             "gauss2": (1 + z / 2 + z * z / 12) / (1 - z / 2 + z * z / 12)}
    for m, want in cases.items():
        A, b = xsweep.PLAIN_IMPLICIT[m]
        assert np.allclose(xsweep.rational_r(A, b, z), want, rtol=1e-13, atol=0.0)
    out = xsweep.sweep("implicit-midpoint", {"omega": 3.51, "gamma": [0.0, 1.0, 0.5],
                                                          "h": [0.1, 1.0, 0.1]})
    assert "power_mismatch_points" in out and "max_power_boundary_mismatch_cells" in out


def _energy_ctx(prob: Any, nsteps: int, max_change: float) -> Any:
    from verify.xrunctx import RunCtx
    cx = RunCtx.__new__(RunCtx)
    cx.prob, cx.nsteps, cx.dt, cx.state_bound = prob, nsteps, 0.01, 0.0
    cx.priv, cx.unc, cx.metrics, cx.chaotic = {}, {}, {}, None
    cx.mm, cx.band, cx.D = {"energy.max_abs_change": max_change}, {}, 0.0
    return cx


def test_growth_ratio_band_from_the_halves() -> None:
    """energy.growth_ratio = a2/a1, each half's maximum known to the energy change's round-off
    u = 8 sqrt(n) eps S_H (energy.max_abs_change's band): a 4th-order Lobatto pair on Kepler (1e5
    steps, maxima 1.1e-9, u = 2.5e-12) gave 0.999989 against dampsym's 0.999951 under rel 1e-6.
    The band is r u (1/a1 + 1/a2): that difference agrees, ten times the band does not."""
    from verify import xfamilies, xproblems
    prob = xproblems.make_problem("kepler", {"e": 0.6})
    cx = _energy_ctx(prob, 100000, 1.148e-9)
    u = 8 * math.sqrt(1e5) * np.finfo(float).eps * abs(float(prob.energy(prob.z0)))
    band = 0.999989 * u * (1 / 1.148e-9 + 1 / (1.148e-9 * 0.999989))
    assert xfamilies.f_growth_ratio(cx, "energy.growth_ratio", 0.999989, 0.999951)["status"] == "agree"
    far = xfamilies.f_growth_ratio(cx, "energy.growth_ratio", 0.999989, 0.999989 + 10 * band)
    assert far["status"] == "disagree"


def test_decorrelated_temperature_extremes() -> None:
    """A chaotic run that decorrelates by its end (D > 1e-3): the extremes of T get 16 x the
    range of our T (argon with Stormer-Verlet as a method file: ours and four members 2.8819,
    dampsym 2.7819); T(t0) keeps its band; a run that stays correlated keeps all of them."""
    from verify.diagnostics import temperature
    from verify.xrunctx import RunCtx
    cx = RunCtx.__new__(RunCtx)
    cx.mm = {"temperature.min": 2.88, "temperature.max": 29.88, "temperature.initial": 22.72,
             "temperature.max_abs_dev_initial": 19.84}
    cx.band, cx.D = {"temperature.min": 3e-5}, 0.129
    temperature.member(cx, {})
    assert cx.band["temperature.min"] == cx.band["temperature.max"] == 16 * (29.88 - 2.88)
    assert "temperature.initial" not in cx.band
    cx.band, cx.D = {"temperature.min": 3e-5}, 1e-6
    temperature.member(cx, {})
    assert cx.band == {"temperature.min": 3e-5}


def test_order_fit_of_runs_that_all_failed() -> None:
    """Every run of a method diverged (an explicit RK3 on the Burgers box scheme's problem at the
    suite's steps), ours and dampsym's: both fits have no point, which is compared (it was "not
    reproduced: no errors of our own"); a report claiming a fit there disagrees; a method with no
    run of ours stays not reproduced."""
    from verify import xcaserec
    theirs = {"ok": False, "status": "too few points", "window_dt": []}
    assert xcaserec.order_fit("c", "m", theirs, {}, [0.1, 0.05], 1.0, "order", True)["verdict"] == "agree"
    claimed = {"ok": True, "status": "ok"}
    assert xcaserec.order_fit("c", "m", claimed, {}, [0.1, 0.05], 1.0, "order", True)["verdict"] == "disagree"
    assert xcaserec.order_fit("c", "m", theirs, {}, [0.1, 0.05], 1.0, "order")["verdict"] == "not reproduced"


def test_driven_nls_field_at_stage_times() -> None:
    """The driven NLS's field at the stages' times at once (an s-stage implicit step evaluates
    N(t + c h, Z) with t an (s, 1) array): it took math.sin of the array and stopped the
    cross-check of gauss2 / glifrk2 / a two-stage method file on nls-driven. Equal to the field
    stage by stage."""
    from verify import xmethods, xproblems
    # the parameters as pde-nls-driven-cs's report gives them ("initial" 2: the sech profile)
    prob = xproblems.make_problem("nls-driven", {"A": 3.0, "Gamma": 0.45, "L": 4.442882938158366, "M": 8.0,
                                                 "alpha": 0.0, "gamma": 0.2, "initial": 2.0, "k": 1.0,
                                                 "lambda": 2.0, "omega0": 1.0})
    z = np.asarray(prob.z0, float)
    tt = np.array([[0.1], [0.35]])
    Z = np.stack([z, 1.01 * z])
    both = prob.N(tt, Z)
    for i in range(2):
        assert np.array_equal(both[i], prob.N(float(tt[i, 0]), Z[i]))
    z1, _ = xmethods.make_stepper("gauss2", prob, 0.01)(0.0, z)
    assert np.all(np.isfinite(z1))
