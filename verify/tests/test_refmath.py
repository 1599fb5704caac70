"""Unit tests of refmath.fit_order, the order fit of docs/conventions.md §5."""
from __future__ import annotations

import math

import pytest

from verify.refmath import fit_order

DTS = [0.1, 0.05, 0.025, 0.0125, 0.00625]


def test_exact_power_law() -> None:
    fit = fit_order(DTS, [3.0 * d ** 2 for d in DTS], floor=0.0)
    assert fit["ok"] and fit["status"] == "ok"
    assert fit["slope"] == pytest.approx(2.0, abs=1e-12)
    assert fit["r2"] == pytest.approx(1.0, abs=1e-12)
    assert fit["window_dt"] == DTS


def test_a_planted_defect_moves_the_slope() -> None:
    """Negative control: one error x (1 + 1e-6) moves the slope off 2 by more than 1e-8."""
    errs = [3.0 * d ** 2 for d in DTS]
    errs[0] *= 1 + 1e-6
    assert abs(fit_order(DTS, errs, floor=0.0)["slope"] - 2.0) > 1e-8


def test_points_at_the_floor_are_dropped() -> None:
    errs = [d ** 4 for d in DTS[:3]] + [1e-16, 1e-16]
    fit = fit_order(DTS, errs, floor=1e-15)
    assert fit["ok"] and fit["window_dt"] == DTS[:3]
    assert fit["slope"] == pytest.approx(4.0, abs=1e-9)


def test_too_few_points() -> None:
    fit = fit_order(DTS[:2], [1e-2, 2.5e-3], floor=0.0)
    assert not fit["ok"] and fit["status"] == "too few points"


def test_errors_not_small_against_the_solution() -> None:
    errs = [0.5, 0.3] + [d ** 2 for d in DTS[2:]]
    fit = fit_order(DTS, errs, floor=0.0, solution_scale=1.0)
    assert fit["window_dt"] == DTS[2:]


def test_order_drop_at_small_h() -> None:
    """The finest steps converge at order 1 after order 2: the window ends at the finest point."""
    errs = [d ** 2 for d in DTS[:3]] + [DTS[2] ** 2 * 0.5, DTS[2] ** 2 * 0.25 * 1.0]
    fit = fit_order(DTS, errs, floor=0.0)
    assert fit["finest_local_order"] == pytest.approx(1.0)
    assert not fit["ok"] or fit["window_dt"][-1] == DTS[-1]


def test_no_convergence() -> None:
    fit = fit_order(DTS, [1.0, 0.9, 1.1, 1.0, 1.05], floor=0.0)
    assert not fit["ok"] and fit["status"] == "no convergence at the finest steps"


def test_non_finite_errors_are_dropped() -> None:
    fit = fit_order(DTS, [math.inf, math.nan] + [d ** 3 for d in DTS[2:]], floor=0.0)
    assert fit["points"] == 3 and fit["slope"] == pytest.approx(3.0, abs=1e-9)
