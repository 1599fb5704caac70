"""The closed-form case verify/cases/osc-closed-form.json (verify/closed_form.py): its numbers are
the closed form's, its tolerances see a 1e-7 relative change, and dampsym fails every check of it
when the damping is planted 1e-7 off (problem.gamma x (1 + 1e-7))."""
from __future__ import annotations

import json
import os
import subprocess
from typing import Any, Dict

import pytest

from verify.closed_form import REL_TOL, expect_block, local_order_fit, metrics

CASE = os.path.join(os.path.dirname(__file__), "..", "cases", "osc-closed-form.json")


def _case() -> Dict[str, Any]:
    with open(CASE, encoding="utf-8") as f:
        case: Dict[str, Any] = json.load(f)
    return case


def test_the_case_checks_the_closed_form() -> None:
    """Every check of the case is a closed-form check, and its near is the closed form's value."""
    case = _case()
    block = expect_block(case)
    assert set(case["expect"]) == set(block)
    for name, chk in case["expect"].items():
        assert chk["metric"] == block[name]["metric"] and chk["methods"] == block[name]["methods"]
        assert chk["near"] == pytest.approx(block[name]["near"], rel=1e-14, abs=0.0), name
        assert chk["tol"] == block[name]["tol"], name


def test_every_tolerance_sees_a_1e7_change() -> None:
    """Tight: near x (1 + 1e-7) is outside near +- tol for every check (tol = 1e-9 of the value)."""
    for name, chk in _case()["expect"].items():
        assert chk["tol"] > 0.0
        assert abs(chk["near"] * 1e-7) > 10.0 * chk["tol"], name
        assert chk["tol"] <= 1.01 * REL_TOL * abs(chk["near"]), name


def test_the_closed_form_sees_its_own_defects() -> None:
    """Negative controls of the closed form itself: a mean over N + 1 points, a damping 1e-7 off."""
    case = _case()
    base = metrics(case, "cimp")
    n = round(case["t_end"] / case["output_dt"])
    assert base["measure.abs_mean"] * n / (n + 1) != pytest.approx(base["measure.abs_mean"],
                                                                   rel=REL_TOL)
    case["problem"]["gamma"] *= 1 + 1e-7
    moved = metrics(case, "cimp")
    for key, v in base.items():
        assert moved[key] != pytest.approx(v, rel=REL_TOL), key


def test_exact_flow_is_the_ode_solution() -> None:
    """The closed-form flow against a 40-digit Taylor series of e^{At} (a wrong flow would make
    every near of the case wrong in the same way as dampsym's exact solution could be)."""
    import mpmath

    from verify.closed_form import exact
    w, g, t = mpmath.mpf(1), mpmath.mpf("0.1"), mpmath.mpf(3)
    a = mpmath.matrix([[0, 1], [-w * w, -2 * g]])
    flow = mpmath.expm(a * t)
    x = exact(w, g, t, [mpmath.mpf(1), mpmath.mpf("0.5")])
    for i in range(2):
        assert abs(x[i] - (flow[i, 0] + flow[i, 1] / 2)) < mpmath.mpf("1e-30")


def test_planted_damping_fails_every_check(dampsym_bin: str, workdir: str) -> None:
    """dampsym on the case: every check passes; with gamma x (1 + 1e-7) every check fails."""
    out = os.path.join(workdir, "closed-form")
    ok = subprocess.run([dampsym_bin, "run", CASE, "--out", out, "--quiet"], capture_output=True)
    assert ok.returncode == 0, ok.stderr
    g = _case()["problem"]["gamma"] * (1 + 1e-7)
    bad = subprocess.run([dampsym_bin, "run", CASE, "--out", out + "-planted", "--quiet", "--set",
                          "problem.gamma=%.17g" % g], capture_output=True)
    assert bad.returncode == 1, bad.stderr
    with open(os.path.join(out + "-planted", "report.json"), encoding="utf-8") as f:
        checks = json.load(f)["cases"][0]["checks"]
    assert checks and not any(c["passed"] for c in checks)


WINDOW_CASE = os.path.join(os.path.dirname(__file__), "..", "cases", "osc-order-window.json")


def test_the_window_case_is_decided_by_the_band() -> None:
    """osc-order-window: the closed form's local orders spread over all four steps by 14 % of
    their mean (between the 10 % band and 20 %, with a margin of 4 points of percent either way),
    so the documented rule drops the coarsest step and a band of 20 % would keep it; the slope
    bounds are the closed form's slope x (1 -+ 1e-9) and exclude a 1e-7 relative change."""
    with open(WINDOW_CASE, encoding="utf-8") as f:
        case = json.load(f)
    fit = local_order_fit(case, "euler")
    lo = fit["local_orders"]
    assert isinstance(lo, list) and len(lo) == 3
    mean = sum(lo) / 3
    assert 0.12 < max(abs(x - mean) for x in lo) / mean < 0.18
    assert fit["window_dt"] == case["dt_ladder"][1:]
    chk = case["expect"]
    assert chk["the window drops the pre-asymptotic coarsest step"]["near"] == len(fit["window_dt"])
    slope = fit["slope"]
    assert isinstance(slope, float)
    ge = chk["slope over the window >= its closed form - 1e-9 relative"]["ge"]
    le = chk["slope over the window <= its closed form + 1e-9 relative"]["le"]
    assert ge < slope < le and le - ge < 2.1e-9 * slope
    assert not ge <= slope * (1 + 1e-7) <= le and not ge <= slope * (1 - 1e-7) <= le


KEPLER_CASE = os.path.join(os.path.dirname(__file__), "..", "cases", "kepler-angular-momentum.json")


def test_kepler_angular_momentum_sees_a_1e6_coefficient(dampsym_bin: str, workdir: str) -> None:
    """kepler-angular-momentum's bound 1e-14 on q x p's law residual is tight: Stormer-Verlet
    exported with one coefficient of its p tableau x (1 + 1e-6) (not symplectic: HLW IV.2) fails
    it where the export itself passes."""
    src = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "methods", "stormer-verlet.json")
    with open(src, encoding="utf-8") as f:
        method = json.load(f)
    name = "angular momentum kept to round-off at every step"
    for tag, coef, want in (("export", "1/2", True), ("planted", "(1/2)*(1000001/1000000)", False)):
        method["id"] = "sv-" + tag
        method["p"]["A"][1][0] = coef
        method.pop("claims", None)      # the planted file claims nothing a check could refute
        path = os.path.join(workdir, "sv-%s.json" % tag)
        with open(path, "w", encoding="utf-8") as f:
            json.dump(method, f)
        out = os.path.join(workdir, "kepler-" + tag)
        subprocess.run([dampsym_bin, "run", KEPLER_CASE, "--out", out, "--quiet", "--methods", path,
                        "--substitute", "stormer-verlet=sv-" + tag], capture_output=True, check=False)
        with open(os.path.join(out, "report.json"), encoding="utf-8") as f:
            checks = json.load(f)["cases"][0]["checks"]
        mine = [c for c in checks if c["name"] == name and c["method"] == "sv-" + tag]
        assert len(mine) == 1 and mine[0]["passed"] is want, (tag, mine)


ENERGY_CASE = os.path.join(os.path.dirname(__file__), "..", "cases", "pend-energy-kept.json")


def test_pendulum_energy_bound_sees_a_1e6_coefficient(dampsym_bin: str, workdir: str) -> None:
    """pend-energy-kept's bound 1e-12 on max |H_n - H_0| is tight: gauss3 exported as a method file
    passes it, the same file with one entry of A x (1 + 1e-6) (no longer symplectic) fails it."""
    name = "Gauss-Legendre keeps the energy to round-off over 1000 steps"
    for tag, factor, want in (("export", 1.0, True), ("planted", 1.0 + 1e-6, False)):
        mid = "g3-" + tag
        exported = subprocess.run([dampsym_bin, "methods", "--export", "gauss3", "--as", mid],
                                  capture_output=True, text=True, check=True).stdout
        method = json.loads(exported)
        method["tableau"]["A"][1][0] *= factor
        method.pop("claims", None)      # the planted file claims nothing a check could refute
        path = os.path.join(workdir, mid + ".json")
        with open(path, "w", encoding="utf-8") as f:
            json.dump(method, f)
        out = os.path.join(workdir, "energy-" + tag)
        subprocess.run([dampsym_bin, "run", ENERGY_CASE, "--out", out, "--quiet", "--methods", path,
                        "--substitute", "gauss3=" + mid], capture_output=True, check=False)
        with open(os.path.join(out, "report.json"), encoding="utf-8") as f:
            checks = json.load(f)["cases"][0]["checks"]
        mine = [c for c in checks if c["name"] == name and c["method"] == mid]
        assert len(mine) == 1 and mine[0]["passed"] is want, (tag, mine)
