"""Unit tests of the cross-check's own Klein-Gordon box scheme (5.5) and its semi-discretisation
klein-gordon-box (verify/xmethods.py kg_box_step, verify/xproblems.py KleinGordonBox), against
facts derived from B, independent of dampsym: the scheme's exact discrete plane wave (its
dispersion relation tan^2(Omega h/2)(2/h)^2 = tan^2(K dx/2)(2/dx)^2 + c - gamma^2, docs/pde.md),
the operator's symbol, and the exact solution's own differential equation."""
from __future__ import annotations

import math
from typing import Any, List

import numpy as np
import pytest

from verify import xmethods as xm
from verify import xproblems as xp

C, GAMMA, K = 1.0, 0.375, 3


def box(M: int = 17, k: int = K) -> Any:
    return xp.make_problem("klein-gordon-box", {"M": M, "c": C, "gamma": GAMMA, "K": k})


def plane(prob: Any, omega: float, t: float) -> Any:
    return math.exp(-GAMMA * t) * np.cos(prob.K * prob.x - omega * t)


@pytest.mark.parametrize("M", [17, 33])
def test_discrete_plane_wave(M: int) -> None:
    """Fed two exact levels of the discrete plane wave, the stepper reproduces it for 300 steps;
    a wrong Omega (x (1 + 1e-6)) is told apart (negative control)."""
    p, h = box(M), 0.1
    tx = 2.0 / p.dx * math.tan(0.5 * K * p.dx)
    om = 2.0 / h * math.atan(0.5 * h * math.sqrt(tx * tx + C - GAMMA ** 2))

    def worst(omega: float) -> float:
        step = xm.kg_box_step(p, h)
        zero = np.zeros(p.M)
        step(0.0, np.concatenate([plane(p, omega, 0.0), zero]))    # the start, then the levels:
        z = np.concatenate([plane(p, omega, h), zero])              # u^0 stored, u^1 passed
        err = 0.0
        for i in range(2, 302):
            z, _ = step((i - 1) * h, z)
            err = max(err, float(np.max(np.abs(z[:p.M] - plane(p, omega, i * h)))) * math.exp(GAMMA * i * h))
        return err

    assert worst(om) <= 1e-11
    assert abs(worst(om * (1 + 1e-6))) >= 1e-7


def test_operator_symbol_and_exact_solution() -> None:
    """F(cos j x) = -(c + (2/dx)^2 tan^2(pi j/M)) cos j x; the exact solution satisfies z' = f(z)
    (central difference in t, step 1e-4: O(1e-8 |z'''|))."""
    p = box()
    k2 = C + (2.0 / p.dx * np.tan(math.pi * np.arange(p.M) / p.M)) ** 2
    for j in range(p.M):   # to 1e-13 of the largest symbol: the FFT applies it to every mode's rounding
        q = np.cos(j * p.x)
        assert np.max(np.abs(p.force(0.0, q) + k2[j] * q)) <= 1e-13 * np.max(k2)
    d = 1e-4
    Z = p.exact(0.0, [0.7 - d, 0.7, 0.7 + d])
    assert np.max(np.abs((Z[2] - Z[0]) / (2 * d) - p.f(0.7, Z[1]))) <= 1e-6


def test_orders_of_u_and_v() -> None:
    """u and v of kg-box both converge with order 2 to the exact solution of klein-gordon-box."""
    p = box(k=1)
    hs = [0.02, 0.01, 0.005]
    eu: List[float] = []
    ev: List[float] = []
    for h in hs:
        step = xm.kg_box_step(p, h)
        z = np.array(p.z0, float)
        n = int(round(1.0 / h))
        for i in range(n):
            z, _ = step(i * h, z)
        ex = p.exact(0.0, n * h)[0]
        eu.append(float(np.max(np.abs(z[:p.M] - ex[:p.M]))))
        ev.append(float(np.max(np.abs(z[p.M:] - ex[p.M:]))))
    for e in (eu, ev):
        assert np.polyfit(np.log(hs), np.log(e), 1)[0] == pytest.approx(2.0, abs=0.1)


def test_applies_to_its_own_problem_only() -> None:
    kg = xp.make_problem("klein-gordon", {"M": 17, "c": C, "gamma": GAMMA, "K": 1})
    with pytest.raises(xm.NotApplicable):
        xm.make_stepper("kg-box", kg, 0.01)
    with pytest.raises(TypeError):
        box(M=16)
