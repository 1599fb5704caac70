"""The error measure and the raw-data reading of bench/work_precision.py (ctest
bench.work_precision, about 2 s): a planted 1e-7 state error moves the reported error by exactly
1e-7/|z_ref|, whichever component and whichever solver (C++ counters or scipy); the final state is
read from the counters z0 ... z{d-1} in order; the time is the minimum over the repetitions; a
scipy vector field that differs from dampsym's by 1e-7 is refused; malformed raw data exits 2."""

import json
import math
import os
import sys
from typing import Any, Dict, List

import numpy as np
import pytest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import work_precision as wpr  # noqa: E402

REF = [3.568849169087172, 2.675979501040735, -0.029206393396237876]  # rb-orders' z(10)


@pytest.mark.parametrize("component", [0, 1, 2])
def test_planted_state_error_is_reported(component: int) -> None:
    z = list(REF)
    assert wpr.final_error(z, REF) == 0.0
    z[component] += 1e-7
    e = wpr.final_error(z, REF)
    # 1e-8: z[i] + 1e-7 is rounded to the ulp of z[i] (4e-16), 4e-9 of the planted error
    assert e == pytest.approx(1e-7 / math.hypot(*REF), rel=1e-8)
    # the Euclidean norm: a second planted 1e-7 moves it by sqrt(2), not 2 (max- or 1-norm)
    z[(component + 1) % 3] += 1e-7
    assert wpr.final_error(z, REF) == pytest.approx(math.sqrt(2) * e, rel=1e-8)
    with pytest.raises(ValueError):
        wpr.final_error(z[:2], REF)


def raw(runs: List[Dict[str, Any]]) -> Dict[str, Any]:
    spec = {"case": "rb-orders", "problem": "rigid-body", "params": {
        "epsilon": 0.5, "I1": 4.0, "I2": 3.0, "I3": 2.0}, "t0": 0.0, "t_end": 10.0,
        "initial_state": [4.0, 3.0, 0.0], "atol_over_rtol": 1e-3, "rtol_exponents": [3, 3],
        "rhs_samples": [{"t": 0.0, "z": [4.0, 3.0, 0.0], "f": [-1.0, -0.75, 1.0]}],
        "reference": {"name": "exact", "kind": "exact", "error_estimate": 0.0,
                      "final_state": REF}}
    return {"context": {"date": "now", "dampsym.wp.rigid-body": json.dumps(spec)},
            "benchmarks": runs}


def run(k: int, z: List[float], cpu_ms: float) -> Dict[str, Any]:
    b: Dict[str, Any] = {"run_name": f"wp/rigid-body/cimp/{k}/min_time:0.020/repeats:3",
                         "run_type": "iteration", "cpu_time": cpu_ms, "time_unit": "ms",
                         "force_evals": 300.0, "jac_evals": 0.0, "steps": 100.0, "h": 0.1}
    b.update({f"z{i}": v for i, v in enumerate(z)})
    return b


def test_cpp_runs_error_and_min_time(tmp_path: Any) -> None:
    planted = [REF[0], REF[1], REF[2] + 1e-7]  # in the last component: an index shift shows
    runs = [run(1, REF, 2.0), run(0, planted, 3.0), run(0, planted, 1.5),
            {"run_name": "wp/rigid-body/cimp/0/min_time:0.020/repeats:3", "run_type": "aggregate",
             "aggregate_name": "min", "cpu_time": 0.1, "time_unit": "ms"}]
    path = tmp_path / "raw.json"
    path.write_text(json.dumps(raw(runs)))
    _, problems, by_name = wpr.load_raw(str(path))
    (series,) = wpr.cpp_series("rigid-body", by_name, REF, str(path))
    assert series["solver"] == "cimp" and series["library"] == "dampsym"
    p0, p1 = series["points"]
    assert p0["error"] == pytest.approx(1e-7 / math.hypot(*REF), rel=1e-6)
    assert p0["cpu_seconds"] == 1.5e-3  # the minimum of the repetitions, not the aggregate
    assert p1["error"] == 0.0 and p0["force_evals"] == 300


def test_scipy_error_uses_the_same_measure() -> None:
    spec = json.loads(raw([])["context"]["dampsym.wp.rigid-body"])
    f, jac = wpr.SYSTEMS["rigid-body"](spec["params"])
    pt = wpr.timed_solve("DOP853", f, jac, spec, 1e-10, 1e-13)
    assert pt["error"] == wpr.final_error(pt["final_state"], REF) and pt["error"] < 1e-8
    assert pt["force_evals"] > 0 and pt["cpu_seconds"] > 0


def test_scipy_vector_field_checked_against_dampsyms() -> None:
    spec = json.loads(raw([])["context"]["dampsym.wp.rigid-body"])
    f, _ = wpr.SYSTEMS["rigid-body"](spec["params"])
    assert wpr.check_rhs("rigid-body", f, spec["rhs_samples"]) is None
    bad = [dict(spec["rhs_samples"][0], f=[-1.0, -0.75 + 1e-7, 1.0])]
    assert "differs" in str(wpr.check_rhs("rigid-body", f, bad))
    # the Jacobian given to Radau is the derivative of f (central differences)
    z, t, d = np.array([1.0, -2.0, 0.5]), 0.7, 1e-6
    fd = np.column_stack([(f(t, z + d * e) - f(t, z - d * e)) / (2 * d) for e in np.eye(3)])
    assert np.max(np.abs(fd - wpr.SYSTEMS["rigid-body"](spec["params"])[1](t, z))) < 1e-8


@pytest.mark.parametrize("text,key", [
    ("{", "raw.json"), (json.dumps({"benchmarks": []}), "'context'"),
    (json.dumps({"context": {}, "benchmarks": []}), "no dampsym.wp"),
    (json.dumps({"context": {"dampsym.wp.x": "{"}, "benchmarks": []}), "context.dampsym.wp.x"),
])
def test_malformed_raw_exits_2(tmp_path: Any, capsys: Any, text: str, key: str) -> None:
    path = tmp_path / "raw.json"
    path.write_text(text)
    assert wpr.main([str(path), "--out-json", str(tmp_path / "out.json")]) == 2
    assert key in capsys.readouterr().err


def test_missing_counter_exits_2(tmp_path: Any, capsys: Any) -> None:
    r = run(0, REF, 1.0)
    del r["z2"]
    path = tmp_path / "raw.json"
    path.write_text(json.dumps(raw([r])))
    assert wpr.main([str(path), "--out-json", str(tmp_path / "out.json")]) == 2
    assert "'z2'" in capsys.readouterr().err
