"""Methods from Python: a callable csv1 run through the plugin kernel equals the built-in csv1 to
round-off and is conformal symplectic (E_n by central differences, said so in the report); the
same callable with one coefficient perturbed by 1e-6 is not. A tableau is a method file: its
checks, its messages, and the matrix's order and E_n verdicts."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import dampsym

Array = np.ndarray[Any, np.dtype[np.float64]]


def csv1_step(eps: float = 0.0) -> Any:
    """Conformal Stormer-Verlet (F (2.12), B (2.20)) on q' = grad T(p), p' = F(q, t) - 2 gamma p;
    eps perturbs the first damping half-step's factor by (1 + eps)."""

    def step(t: float, z: Array, h: float, problem: Any) -> Array:
        n = z.size // 2
        q, p = z[:n], z[n:]
        hh = 0.5 * h
        d1 = problem.damping_factor(t, hh) * (1.0 + eps)
        d2 = problem.damping_factor(t + hh, hh)
        p1 = d1 * p + hh * problem.force(t, q)
        q1 = q + h * problem.grad_T(p1)
        p1 = d2 * (p1 + hh * problem.force(t + h, q1))
        return np.concatenate([q1, p1])

    return step


PY = dampsym.Step(csv1_step(), id="py-csv1", order=2, claims=["conformal-symplectic"],
                  description="csv1 as a Python callable")
PERTURBED = dampsym.Step(csv1_step(1e-6), id="py-csv1-perturbed", order=2,
                         claims=["conformal-symplectic"])

CASE: dict[str, Any] = {
    "id": "py-csv1-vs-csv1", "title": "a Python csv1 against the built-in", "source": "tests",
    "problem": {"id": "pendulum", "gamma": 0.1, "q0": 1.0, "p0": 0.5},
    "methods": ["py-csv1", "csv1", "py-csv1-perturbed"], "t_end": 5.0, "dt_ladder": [0.1, 0.05],
    "diagnostics": ["error", "conformal-symplectic"],
    "expect": {"E_n": {"metric": "conformal-symplectic.max_rel", "methods": ["py-csv1"],
                       "le": 1e-8}},
}


def without_checks(case_id: str, method: str) -> dict[str, Any]:
    case = {k: v for k, v in CASE.items() if k != "expect"}
    return {**case, "id": case_id, "methods": [method], "diagnostics": ["error"],
            "no_checks_because": "the run's status is what the test reads"}


def runs_of(report: dict[str, Any], method: str) -> list[dict[str, Any]]:
    return [r for r in report["cases"][0]["runs"] if r["method"] == method]


def test_callable_csv1_is_the_builtin_to_round_off() -> None:
    report = dampsym.run(CASE, time_budget=0)
    for mine, builtin in zip(runs_of(report, "py-csv1"), runs_of(report, "csv1")):
        assert mine["status"] == "ok"
        diff = np.max(np.abs(mine["final_state"] - builtin["final_state"]))
        assert diff <= 1e-14 * np.max(np.abs(builtin["final_state"]))
    perturbed = runs_of(report, "py-csv1-perturbed")[0]["final_state"]
    assert np.max(np.abs(perturbed - runs_of(report, "csv1")[0]["final_state"])) > 1e-9
    # where E_n came from, in the report: the step's central differences, the built-in's exact
    for mine, builtin in zip(runs_of(report, "py-csv1"), runs_of(report, "csv1")):
        assert mine["metrics"]["conformal-symplectic"]["jacobian"] == "central-differences"
        assert builtin["metrics"]["conformal-symplectic"]["jacobian"] == "exact"
    assert report["summary"]["checks_failed"] == 0


def test_the_same_with_two_worker_threads() -> None:
    one = dampsym.run(CASE, time_budget=0, jobs=1)
    two = dampsym.run(CASE, time_budget=0, jobs=2)  # the callable from the runner's threads
    assert [r["final_state"].tobytes() for r in one["cases"][0]["runs"]] == \
        [r["final_state"].tobytes() for r in two["cases"][0]["runs"]]


def test_matrix_finds_csv1_conformal_symplectic_and_the_perturbed_not() -> None:
    m = dampsym.matrix(methods=[PY, PERTURBED])
    cells = {row["id"]: row["cells"] for row in m["methods"]}
    assert cells["py-csv1"]["en-pendulum"]["verdict"] == "holds"
    assert cells["py-csv1"]["order"]["verdict"] == "holds"
    assert cells["py-csv1-perturbed"]["en-pendulum"]["verdict"] == "fails"
    assert cells["py-csv1-perturbed"]["en-pendulum"]["value"] > 1e-8
    assert m.exit_status == 1  # the perturbed one claims what it does not have


def test_an_exception_in_the_step_is_the_runs_error() -> None:
    def broken(t: float, z: Array, h: float) -> Array:
        if t > 1.0:
            raise ZeroDivisionError("the step's own bug")
        return z.copy()

    dampsym.Step(broken, id="py-broken", order=1, form="plain")
    report = dampsym.run(without_checks("broken", "py-broken"), time_budget=0)
    run = report["cases"][0]["runs"][0]
    assert run["status"] == "error"
    assert "py-broken" in report.text and "the step's own bug" in report.text


def test_a_wrong_shape_and_a_bad_declaration_are_errors() -> None:
    dampsym.Step(lambda t, z, h: np.zeros(z.size + 1), id="py-wrong-shape", order=1, form="plain")
    report = dampsym.run(without_checks("shape", "py-wrong-shape"), time_budget=0)
    assert report["cases"][0]["runs"][0]["status"] == "error"
    assert "expected (4,)" in report.text or "expected (2,)" in report.text
    with pytest.raises(dampsym.InputError, match="order 0"):
        dampsym.Step(csv1_step(), id="py-order-zero", order=0)
    with pytest.raises(dampsym.InputError, match="built-in method"):
        dampsym.Step(csv1_step(), id="csv1", order=2)
    with pytest.raises(dampsym.InputError, match="form"):
        dampsym.Step(csv1_step(), id="py-bad-form", order=2, form="symplectic")


GAUSS2_A = [["1/4", "1/4 - sqrt(3)/6"], ["1/4 + sqrt(3)/6", "1/4"]]
GAUSS2_C = ["1/2 - sqrt(3)/6", "1/2 + sqrt(3)/6"]


def test_tableau_checks_as_a_method_file() -> None:
    t = dampsym.Tableau(GAUSS2_A, [0.5, 0.5], GAUSS2_C, id="py-gauss2", order=4,
                        claims=["symplectic-if-undamped"])
    checks = {c["name"]: c for c in t.checks()}
    assert all(c["agrees"] for c in checks.values())
    assert checks["symplectic"]["holds"]
    again = dampsym.Tableau(GAUSS2_A, [0.5, 0.5], GAUSS2_C, id="py-gauss2", order=4,
                            claims=["symplectic-if-undamped"])  # a re-run cell: the same method
    assert again.id == t.id
    # one coefficient off by 1e-6: the order-4 conditions fail, so the declaration disagrees
    off = dampsym.Tableau(GAUSS2_A, [0.5 * (1 + 1e-6), 0.5 * (1 - 1e-6)], GAUSS2_C,
                          id="py-gauss2-off", order=4, claims=["symplectic-if-undamped"])
    assert not all(c["agrees"] for c in off.checks())


def test_tableau_messages_are_the_method_file_messages() -> None:
    with pytest.raises(dampsym.InputError, match=r"Tableau\(id='py-bad'\): tableau.A\[1\]"):
        dampsym.Tableau([[0, 0], [1]], [0.5, 0.5], [0, 1], id="py-bad", order=2)
    with pytest.raises(dampsym.InputError, match="tableau.b"):
        dampsym.Tableau(np.zeros((2, 2)), [1.0], [0.0, 0.0], id="py-bad-b", order=1)


def euler(t: float, z: Array, h: float, problem: Any) -> Array:
    return np.asarray(z + h * problem.rhs(t, z))


def euler_jacobian(t: float, z: Array, h: float, problem: Any) -> tuple[Array, Array]:
    """Explicit Euler and its step Jacobian I + h A on a linear problem (A's columns probed)."""
    d = z.size
    f0 = problem.rhs(t, np.zeros(d))
    a = np.column_stack([problem.rhs(t, np.eye(d)[j]) - f0 for j in range(d)])
    return euler(t, z, h, problem), np.eye(d) + h * a


def test_a_jacobian_callable_is_used_and_checked() -> None:
    dampsym.Step(euler, id="py-euler", order=1, form="plain", jacobian=euler_jacobian)
    dampsym.Step(euler, id="py-euler-wrong-jacobian", order=1, form="plain",
                 jacobian=lambda t, z, h, pr: (euler(t, z, h, pr),
                                               euler_jacobian(t, z, h, pr)[1] * (1 + 1e-6)))
    case = {"id": "py-jacobian", "title": "t", "source": "tests",
            "problem": {"id": "oscillator", "gamma": 0.1},
            "methods": ["py-euler", "euler", "py-euler-wrong-jacobian"], "t_end": 5.0, "dt": 0.1,
            "diagnostics": ["conformal-symplectic"], "no_checks_because": "the test reads them"}
    runs = dampsym.run(case, time_budget=0)["cases"][0]["runs"]
    mine, builtin, wrong = (r["metrics"]["conformal-symplectic"] for r in runs)
    assert mine["jacobian"] == "plugin-jacobian" and builtin["jacobian"] == "exact"
    assert mine["status"] == "ok" and abs(mine["max_rel"] - builtin["max_rel"]) <= 1e-15
    assert runs[0]["final_state"].tobytes() == runs[1]["final_state"].tobytes()
    assert wrong["status"] == "jacobian-mismatch"  # J off by 1e-6: the step's own check sees it
