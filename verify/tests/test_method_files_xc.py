"""The user's own methods in the cross-check (verify/xmethodfile.py): a method file's tableau is
read from the file by the cross-check's own grammar and stepped by its own engines.

Unit tests (no dampsym needed): the coefficient grammar of docs/method-files.md (values, the
errors it names), an `rk` file registered as explicit, implicit or integrating-factor method, a
file of another family named with its reason.

With --bin (ctest crosscheck.heldout): a case with its own method files (an explicit SSP RK3, a
two-stage Radau IIA under the integrating factor) is run by dampsym and cross-checked with
--strict: every run reproduced and agreeing. Negative control: the same report against the
Radau file with one coefficient changed by 1e-6 (relative) disagrees. dampsym's own evaluation
of expression coefficients equals the cross-check's bit for bit. Partitioned pairs (Stormer-Verlet
and a coupled Lobatto IIIA-IIIB pair) and the exponential families (dampsym's exports of its
built-ins, read back) step as the cross-check's own methods do."""
from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from typing import Any, Dict, List

import mpmath
import pytest

from verify import xmethodfile as xf
from verify import xmethods as xm
from verify import xnewton

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
Json = Dict[str, Any]
EXPRESSIONS = ["1/2 - sqrt(3)/6", "(3 + 2*sqrt(3))/3", "1/6", "-1/12", "0.1", "2/3", "5/12",
               "sqrt(2) - 1", "1/7 + 1/11 - 1/13", "-(1 - sqrt(5))/10", "3.14159/2",
               # long double rounds these to another double than exact arithmetic would (and
               # double arithmetic the first three to yet another): the test tells them apart
               "536/61 - sqrt(922)/576", "14/441 - sqrt(813)/850", "775/869 - sqrt(928)/140"]


def _write(path: str, doc: Any) -> str:
    with open(path, "w") as fh:
        json.dump(doc, fh)
    return path


def test_coefficient_grammar() -> None:
    with mpmath.workdps(60):
        exact = float(mpmath.mpf(1) / 2 - mpmath.sqrt(3) / 6)
    assert xf.coefficient("1/2 - sqrt(3)/6") == exact
    assert xf.coefficient(" ( 3 + 2*sqrt(3) ) / 3") == xf.coefficient("(3 + 2*sqrt(3))/3")
    assert xf.coefficient("--1/4") == 0.25 and xf.coefficient(0.5) == 0.5 and xf.coefficient(2) == 2.0
    assert xf.coefficient("1/6") == 1 / 6
    for bad in ("1e-3", "sqrt(-1)", "1/0", "exp(1)", "1/", "(1", "1 2", "", True, None, [1]):
        with pytest.raises(xf.MethodFileError):
            xf.coefficient(bad)


def _method_files(d: str) -> List[str]:
    """An explicit SSP RK3, a two-stage Radau IIA under the integrating factor, a GLM file without
    its tableau (unreadable: named with its reason), Stormer-Verlet and a three-stage Lobatto
    IIIA-IIIB pair."""
    ssp = _write(os.path.join(d, "ssp.json"), {
        "id": "xc-ssprk3", "family": "rk", "order": 3,
        "tableau": {"A": [["0", "0", "0"], ["1", "0", "0"], ["1/4", "1/4", "0"]],
                    "b": ["1/6", "1/6", "2/3"], "c": ["0", "1", "1/2"]}})
    radau = _write(os.path.join(d, "radau.json"), {
        "id": "xc-radau-if", "family": "rk", "order": 3, "integrating_factor": True,
        "tableau": {"A": [["5/12", "-1/12"], ["3/4", "1/4"]], "b": ["3/4", "1/4"], "c": ["1/3", "1"]}})
    other = _write(os.path.join(d, "glm.json"), {"id": "xc-glm", "family": "general-linear", "order": 2})
    sv = _write(os.path.join(d, "sv.json"), {
        "id": "xc-sv-prk", "family": "partitioned-rk", "order": 2, "explicit": True,
        "q": {"A": [["0", "0"], ["1/2", "1/2"]], "b": ["1/2", "1/2"], "c": ["0", "1"]},
        "p": {"A": [["1/2", "0"], ["1/2", "0"]], "b": ["1/2", "1/2"], "c": ["1/2", "1/2"]}})
    lob = _write(os.path.join(d, "lobatto3.json"), {
        "id": "xc-lobatto3", "family": "partitioned-rk", "order": 4,
        "q": {"A": [["0", "0", "0"], ["5/24", "1/3", "-1/24"], ["1/6", "2/3", "1/6"]],
              "b": ["1/6", "2/3", "1/6"], "c": ["0", "1/2", "1"]},
        "p": {"A": [["1/6", "-1/6", "0"], ["1/6", "1/3", "0"], ["1/6", "5/6", "0"]],
              "b": ["1/6", "2/3", "1/6"], "c": ["0", "1/2", "1"]}})
    return [ssp, radau, other, sv, lob]


def test_rk_files_join_the_engines(tmp_path: Any) -> None:
    files = _method_files(str(tmp_path))
    assert [xf.load(p) for p in files] == ["xc-ssprk3", "xc-radau-if", "xc-glm", "xc-sv-prk", "xc-lobatto3"]
    assert xm.EXPLICIT_RK["xc-ssprk3"][1] == [1 / 6, 1 / 6, 2 / 3] and xm.EXPLICIT_EVALS["xc-ssprk3"] == 3
    assert xm.FILE_RK["xc-radau-if"][0] == "if" and "xc-radau-if" in xm.IMPLICIT
    assert xnewton.supported("xc-radau-if") and "xc-radau-if" in xm.NEEDS_CONFORMAL
    assert "xc-glm" not in xm.METHODS and "general-linear: needs A" in xf.UNSUPPORTED["xc-glm"]
    assert xf.load(str(tmp_path / "none.json")) is None
    assert xm.EXPLICIT_EVALS["xc-sv-prk"] == 2 and "xc-lobatto3" in xm.IMPLICIT


def test_partitioned_pairs(tmp_path: Any) -> None:
    """Lobatto IIIA-IIIB as a file: stage by stage it is the cross-check's own Stormer-Verlet
    (HLW (3.7)) to round-off, damped and time-dependent alike; the three-stage pair, whose stages
    are coupled, is solved by Newton and converges at order 4 (a p weight moved by 1e-6 does
    not: below order 1.5 at small steps)."""
    import numpy as np
    from verify import xproblems
    for f in _method_files(str(tmp_path)):
        xf.load(f)
    assert xm.prk_schedule([[0, 0], [0.5, 0.5]], [[0.5, 0], [0.5, 0]]) == [("q", 0), ("p", 0), ("p", 1), ("q", 1)]
    assert xm.prk_schedule([[0, 0, 0], [5 / 24, 1 / 3, -1 / 24], [1 / 6, 2 / 3, 1 / 6]],
                           [[1 / 6, -1 / 6, 0], [1 / 6, 1 / 3, 0], [1 / 6, 5 / 6, 0]]) is None
    prob = xproblems.make_problem("driven-pendulum", {"f": 1.2, "gamma": 0.1, "lambda": 1.0, "q0": 0.7, "p0": -0.4})
    z = np.array([0.7, -0.4])
    for t in (0.0, 1.3):
        ours = xm.make_stepper("xc-sv-prk", prob, 0.05)(t, z)[0]
        sv = xm.make_stepper("stormer-verlet", prob, 0.05)(t, z)[0]
        assert np.max(np.abs(ours - sv)) <= 4 * xm.EPS * np.max(np.abs(sv))

    def err(method: str, h: float) -> float:
        st, zz = xm.make_stepper(method, prob, h), z.copy()
        for k in range(int(round(0.8 / h))):
            zz = st(k * h, zz)[0]
        return float(np.max(np.abs(zz - ref)))
    ref = z.copy()
    st = xm.make_stepper("xc-lobatto3", prob, 0.8 / 512)
    for k in range(512):
        ref = st(k * 0.8 / 512, ref)[0]
    e = [err("xc-lobatto3", 0.8 / n) for n in (8, 16)]
    assert 3.8 < math.log2(e[0] / e[1]) < 4.2, e
    q, p = xm.FILE_PRK["xc-lobatto3"]
    bad = list(p[1])
    bad[1] *= 1 + 1e-6
    xm.FILE_PRK["xc-lobatto3-planted"] = (q, (p[0], bad, p[2]))
    xm.IMPLICIT.add("xc-lobatto3-planted")
    e = [err("xc-lobatto3-planted", 0.8 / n) for n in (32, 64)]
    assert math.log2(e[0] / e[1]) < 1.5, e   # the weights' 1e-6 inconsistency dominates


GLM_FILES: Dict[str, Json] = {
    # Gauss2 as a one-value GLM (coupled stages, no starting stages)
    "gauss2-glm.json": {"id": "xc-gauss2-glm", "family": "general-linear", "order": 4,
                        "A": [["1/4", "1/4 - sqrt(3)/6"], ["1/4 + sqrt(3)/6", "1/4"]],
                        "U": [["1"], ["1"]], "B": [["1/2", "1/2"]], "V": [["1"]],
                        "c": ["1/2 - sqrt(3)/6", "1/2 + sqrt(3)/6"]},
    # the trapezoidal rule (Lobatto IIIA, two stages) as a one-value GLM: an explicit first stage
    "trapezoid-glm.json": {"id": "xc-trapezoid-glm", "family": "general-linear", "order": 2,
                           "A": [["0", "0"], ["1/2", "1/2"]], "U": [["1"], ["1"]], "B": [["1/2", "1/2"]],
                           "V": [["1"]], "c": ["0", "1"], "starting": {"V": ["1"]}},
}


def _glm_files(d: str) -> List[str]:
    """The GLM files above and Butcher's glm4 as a file (examples/methods/glm4.json)."""
    out = [_write(os.path.join(d, name), doc) for name, doc in GLM_FILES.items()]
    with open(os.path.join(ROOT, "examples", "methods", "glm4.json")) as fh:
        out.append(_write(os.path.join(d, "glm4.json"), json.load(fh)))
    return out


def test_glm_files_step_as_ours(tmp_path: Any) -> None:
    """`general-linear` files step by the cross-check's GLM (xmethods.GLM): glm4's file as the
    built-in glm4 (its starting method, then its two values), Gauss2 as a one-value GLM (coupled
    stages, solved together) as gauss2, the trapezoidal rule (an explicit stage) as its tableau
    from an `rk` file, each to round-off on the driven pendulum (time-dependent forcing: the stage
    times matter); a weight moved by 1e-6 moves the step."""
    import numpy as np
    from verify import xproblems
    assert [xf.load(p) for p in _glm_files(str(tmp_path))] == ["xc-gauss2-glm", "xc-trapezoid-glm", "glm4-file"]
    trap = _write(str(tmp_path / "trap-rk.json"), {"id": "xc-trapezoid-rk", "family": "rk", "order": 2,
                                                  "tableau": {"A": [["0", "0"], ["1/2", "1/2"]],
                                                              "b": ["1/2", "1/2"], "c": ["0", "1"]}})
    assert xf.load(trap) == "xc-trapezoid-rk"
    assert {"xc-gauss2-glm", "xc-trapezoid-glm", "glm4-file"} <= xm.MULTIVALUE
    prob = xproblems.make_problem("driven-pendulum", {"f": 1.2, "gamma": 0.1, "lambda": 1.0, "q0": 0.7, "p0": -0.4})
    z, h = np.array(prob.z0, float), 0.1

    def run(glm: Any, n: int) -> Any:
        y = glm.start(0.3, z)
        for k in range(n):
            y = glm.step(0.3 + k * h, y)[0]
        return y

    ours = run(xm.GLM(prob, h), 5)
    via_file = run(xm.GLM(prob, h, xm.FILE_GLM["glm4-file"]), 5)
    assert np.max(np.abs(ours - via_file)) <= 8 * xm.EPS * np.max(np.abs(ours))
    for glm_id, rk_id in (("xc-gauss2-glm", "gauss2"), ("xc-trapezoid-glm", "xc-trapezoid-rk")):
        one = run(xm.GLM(prob, h, xm.FILE_GLM[glm_id]), 1)[0]
        ref = xm.make_stepper(rk_id, prob, h)(0.3, z)[0]
        assert np.max(np.abs(one - ref)) <= 8 * xm.EPS * np.max(np.abs(ref)), glm_id
    planted = dict(xm.FILE_GLM["xc-gauss2-glm"])
    planted["B"] = planted["B"] * np.array([[1.0, 1.0 + 1e-6]])
    bad = run(xm.GLM(prob, h, planted), 1)[0]
    good = run(xm.GLM(prob, h, xm.FILE_GLM["xc-gauss2-glm"]), 1)[0]
    assert np.max(np.abs(bad - good)) > 1e-9 * np.max(np.abs(good))


def test_user_glm_files_reproduced(dampsym_bin: str, workdir: str) -> None:
    """A case with three `general-linear` files (coupled stages, an explicit stage, glm4's two
    values) beside the built-in glm4, with the cost diagnostic: every run reproduced by the
    cross-check (--strict) and agreeing, Newton counts included; Gauss2's file with one weight
    moved by 1e-6 after the run disagrees, on its runs only."""
    work = os.path.join(workdir, "user-glms")
    mdir = os.path.join(work, "methods")
    os.makedirs(mdir, exist_ok=True)
    files = _glm_files(mdir)
    glms = ["xc-gauss2-glm", "xc-trapezoid-glm", "glm4-file"]
    case = _write(os.path.join(work, "glm-files.json"), {
        "id": "hill-user-glms", "title": "GLM files on Hill's problem", "source": "test", "suites": ["heldout"],
        "method_files": [os.path.relpath(f, work) for f in files],
        "problem": {"id": "hill", "epsilon": 0.4, "kappa": 1.0, "q0": 1.0, "p0": 0.0},
        "methods": glms + ["glm4"], "t_end": 4.0, "dt_ladder": [0.2, 0.1, 0.05],
        "diagnostics": ["error", "order", "cost"],
        "expect": {"fourth order": {"metric": "order.slope", "methods": ["xc-gauss2-glm", "glm4-file"],
                                    "near": 4.0, "tol": 0.3},
                   "second order": {"metric": "order.slope", "methods": ["xc-trapezoid-glm"], "near": 2.0,
                                    "tol": 0.1}}})
    out = os.path.join(work, "report")
    run = subprocess.run([os.path.abspath(dampsym_bin), "run", case, "--out", out, "-q"],
                         capture_output=True, text=True)
    assert run.returncode == 0 and "REFUTED" not in run.stderr, run.stderr
    report = os.path.join(out, "report.json")
    good = _crosscheck(report, os.path.join(work, "good"))
    s = good["summary"]
    assert s["runs"]["not reproduced"] == 0 and s["runs"]["agree"] == 12, s
    assert s["comparisons"]["disagree"] == 0 and s["checks"]["agree"] == 3, s
    counted = {r["method"] for r in good["runs"] for c in r["comparisons"]
               if c["quantity"] == "newton_iters" and c["status"] == "agree"}
    assert set(glms) <= counted
    doc = dict(GLM_FILES["gauss2-glm.json"], B=[["1/2", "1/2 * (1 + 1/1000000)"]])
    _write(os.path.join(mdir, "gauss2-glm.json"), doc)
    bad = _crosscheck(report, os.path.join(work, "planted"))
    assert bad["summary"]["comparisons"]["disagree"] >= 1
    assert {r["method"] for r in bad["runs"] if r["verdict"] == "disagree"} == {"xc-gauss2-glm"}


def _case(work: str, methods_dir: str) -> str:
    with open(os.path.join(ROOT, "verify", "cases", "hill-orders.json")) as fh:
        spec = json.load(fh)
    spec.update(id="hill-user-methods", suites=["heldout"], methods=["xc-ssprk3", "xc-radau-if", "xc-sv-prk"],
                method_files=[os.path.relpath(os.path.join(methods_dir, f), work)
                              for f in ("ssp.json", "radau.json", "sv.json")],
                expect={"both converge at order 3": {"metric": "order.slope", "methods": ["xc-ssprk3", "xc-radau-if"],
                                                      "near": 3.0, "tol": 0.2}})
    spec.pop("figures", None)
    return _write(os.path.join(work, "hill-user-methods.json"), spec)


def _crosscheck(report_path: str, out: str) -> Json:
    subprocess.run([sys.executable, "-m", "verify.crosscheck", report_path, "--out", out, "--strict", "--jobs", "2"],
                   cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(os.path.join(out, "crosscheck.json")) as fh:
        return dict(json.load(fh))


def test_user_methods_reproduced(dampsym_bin: str, workdir: str) -> None:
    work = os.path.join(workdir, "user-methods")
    mdir = os.path.join(work, "methods")
    os.makedirs(mdir, exist_ok=True)
    _method_files(mdir)
    case = _case(work, mdir)
    out = os.path.join(work, "report")
    rc = subprocess.run([os.path.abspath(dampsym_bin), "run", case, "--out", out, "-q"],
                        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode
    assert rc == 0
    report = os.path.join(out, "report.json")
    s = _crosscheck(report, os.path.join(work, "good"))["summary"]
    assert s["runs"]["not reproduced"] == 0 and s["runs"]["agree"] > 0, s
    assert s["comparisons"]["disagree"] == 0 and s["checks"]["agree"] > 0, s
    # negative control: the Radau file's a_21 = 3/4 times (1 + 1e-6) after the run
    radau = os.path.join(mdir, "radau.json")
    with open(radau) as fh:
        doc = json.load(fh)
    doc["tableau"]["A"][1][0] = "3/4 * (1 + 1/1000000)"
    _write(radau, doc)
    bad = _crosscheck(report, os.path.join(work, "planted"))
    assert bad["summary"]["comparisons"]["disagree"] >= 1
    assert all(r["method"] == "xc-radau-if" for r in bad["runs"] if r["verdict"] == "disagree")


def test_coefficients_as_dampsym_evaluates_them(dampsym_bin: str, workdir: str) -> None:
    """One explicit step z1 = z + h e f(z) of a one-stage method with b = [e], on the oscillator
    from (q, p) = (0, 1) with h = 1: q1 = e exactly, so dampsym's final q is the double it
    evaluated e to. Equal to the cross-check's long-double evaluation bit for bit."""
    work = os.path.join(workdir, "coefficients")
    os.makedirs(work, exist_ok=True)
    files, ids = [], []
    for k, e in enumerate(EXPRESSIONS):
        ids.append("xc-coef-%d" % k)
        files.append(_write(os.path.join(work, ids[-1] + ".json"), {
            "id": ids[-1], "family": "rk", "order": 1, "explicit": True,
            "tableau": {"A": [["0"]], "b": [e], "c": ["0"]}}))
    case = _write(os.path.join(work, "coef.json"), {
        "id": "xc-coefficients", "title": "coefficients", "source": "test", "suites": ["heldout"],
        "problem": {"id": "oscillator", "omega": 1.0, "gamma": 0.0, "q0": 0.0, "p0": 1.0},
        "methods": ids, "method_files": [os.path.basename(f) for f in files], "t_end": 1.0, "dt": 1.0,
        "no_checks_because": "reads the coefficients back"})
    out = os.path.join(work, "report")
    subprocess.run([os.path.abspath(dampsym_bin), "run", case, "--out", out, "-q"], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(os.path.join(out, "report.json")) as fh:
        runs = {r["method"]: r["final_state"][0] for r in json.load(fh)["cases"][0]["runs"]}
    assert [runs[i] for i in ids] == [xf.coefficient(e) for e in EXPRESSIONS]


def test_exported_exponential_methods_step_as_ours(dampsym_bin: str, workdir: str) -> None:
    """The exponential families through their files: dampsym's exports of etdrk2 (exponential-rk),
    cse-etd, csv1-perk and etdprk2 (partitioned-exponential-rk, B's x_B = 2x) and glifrk2 (rk under
    the integrating factor), read by the cross-check, step as its own built-in steps do, to 2 ulps,
    on Hill's problem (time-dependent gamma) and the driven pendulum. A file's claims give its
    momentum factor (B Table 3.1); a planted 1e-6 in etdrk2's phi1 coefficient moves the step."""
    import numpy as np
    from verify import xmetrics, xproblems
    work = os.path.join(workdir, "exports")
    os.makedirs(work, exist_ok=True)
    methods = ["etdrk2", "cse-etd", "csv1-perk", "etdprk2", "glifrk2"]
    for m in methods:
        out = os.path.join(work, m + ".json")
        subprocess.run([os.path.abspath(dampsym_bin), "methods", "--export", m, "--as", "xc-" + m, "--out", out],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        assert xf.load(out) == "xc-" + m and "xc-" + m not in xf.UNSUPPORTED
    probs = [xproblems.make_problem("hill", {"epsilon": 0.5, "kappa": 0.3, "q0": 0.7, "p0": -0.4}),
             xproblems.make_problem("driven-pendulum", {"f": 1.2, "gamma": 0.1, "lambda": 1.0, "q0": 0.7, "p0": -0.4})]
    for prob in probs:
        z = np.array(prob.z0, float)
        for m in methods:
            for t in (0.0, 0.7):
                ours = xm.make_stepper(m, prob, 0.05)(t, z)[0]
                via_file = xm.make_stepper("xc-" + m, prob, 0.05)(t, z)[0]
                assert np.max(np.abs(ours - via_file)) <= 2 * xm.EPS * np.max(np.abs(ours)), (m, t)
    assert xmetrics.table_factor("xc-csv1-perk", 0.1, 0.05) == xmetrics.table_factor("csv1", 0.1, 0.05)
    assert xmetrics.table_factor("xc-etdprk2", 0.1, 0.05) is None       # it claims nothing
    c, A, phi, b, phi0 = xm.FILE_ERK["xc-etdrk2"]
    xm.FILE_ERK["xc-etdrk2-planted"] = (c, A, phi, [[(co * (1 + 1e-6), n, a) for co, n, a in b[0]]], phi0)
    xm.IMPLICIT.add("xc-etdrk2-planted")
    prob = probs[1]
    z = np.array(prob.z0, float)
    good = xm.make_stepper("xc-etdrk2", prob, 0.05)(0.0, z)[0]
    bad = xm.make_stepper("xc-etdrk2-planted", prob, 0.05)(0.0, z)[0]
    assert np.max(np.abs(good - bad)) > 1e-9 * np.max(np.abs(good))


def test_checks_of_a_method_not_stepped_are_not_reproduced() -> None:
    """A check on a method the cross-check does not step (a plugin's, a general-linear file's) is
    "not reproduced" like its runs; it was judged from an empty fit ("ours undefined, verdict
    False") and called a disagreement. Alone or in a comparison between methods."""
    from verify import xcaserec
    heads: List[Json] = [{"method": "plugin-csv1", "metric": "order.slope"},
                         {"method": "csv1 / plugin-csv1", "members": ["csv1", "plugin-csv1"], "form": "ratio",
                          "metric": "error.final_abs"}]
    for hd in heads:
        val = xcaserec._ours_for(hd, {}, {}, {}, {})
        assert isinstance(val, str) and "plugin-csv1" in val
    assert not isinstance(xcaserec._ours_for({"method": "csv1", "metric": "order.slope"}, {},
                                             {("csv1", None): {"order.slope": 2.0}}, {}, {}), str)


def test_file_methods_in_sweeps_and_cache_keys(tmp_path: Any) -> None:
    """A plain implicit tableau from a file has the stability sweep's power-boundary metrics (R(z)
    of its tableau, as dampsym gives them for every plain tableau; they were 'unknown to us'), and
    a file's definition is part of the key of our cached results: the same id with other
    coefficients is another computation."""
    from verify import xcache, xsweep
    _method_files(str(tmp_path))
    xf.load(os.path.join(str(tmp_path), "radau.json"))
    path = _write(os.path.join(str(tmp_path), "radau-plain.json"), {
        "id": "xc-radau-plain", "family": "rk", "order": 3,
        "tableau": {"A": [["5/12", "-1/12"], ["3/4", "1/4"]], "b": ["3/4", "1/4"], "c": ["1/3", "1"]}})
    assert xf.load(path) == "xc-radau-plain"
    out = xsweep.sweep("xc-radau-plain", {"omega": 3.51, "gamma": [0.0, 1.0, 0.5], "h": [0.1, 1.0, 0.1]})
    assert "power_mismatch_points" in out and "max_power_boundary_mismatch_cells" in out
    before = xcache.sources_digest()
    xm.FILE_DEFS["xc-radau-plain"] = xm.FILE_DEFS["xc-radau-plain"].replace("0.75", "0.7500001")
    xcache.sources_changed()
    assert xcache.sources_digest() != before
