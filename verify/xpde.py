#!/usr/bin/python3
"""Independent cross-check of the PDE cases (docs/pde.md) in numpy/scipy.

Usage: /usr/bin/python3 verify/xpde.py REPORT_DIR [--cases verify/cases]

For every verify/cases/pde-*.json case in the report it re-implements the problem and the methods
from B's formulas (not from dampsym's code):
  klein-gordon: the semi-discretisation u' = v, v' = (delta_x^2 - c)u - 2 gamma v (B (5.2)), the
  schemes (5.3) = csv1 and (5.4) = csv2 as printed in B, classical rk4 and heun; checks the final
  state of every run against the report (relative 1e-10), recomputes the momentum residual
  max |I_{n+1} - e^{-2 gamma h} I_n| / S_n (B Theorem 5.1) and agrees with the report's verdict
  (<= 1e-13 for csv1/csv2, >= 1e-8 for rk4/heun), and checks the exact solution of the
  semi-discrete system (numpy FFT, per-mode oscillator) against a fine scipy solve_ivp (DOP853,
  rtol 1e-12).
Independently of the report it checks:
  - the PDE solution (5.1) against a fine-grid (M = 512) scipy integration of the PDE: the
    difference must match the predicted space error of the M = 512 grid, |W - W_d| t, to 10 %;
  - Burgers (5.10): Casimir residual (5.15) <= 1e-13; NSFD (4.18) >= 1e-6 (negative control);
  - NLS IF (4.15): R_2 (5.29) <= 1e-13 on damped NLS, IMP (5.28) >= 1e-8;
  - Burgers (5.10) is conformal Poisson (docs/pde.md "Conformal Poisson"):
    its step Jacobian Psi (complex step) satisfies Psi D Psi^T = e^{-4 gamma h} D with B's
    structure matrix D of (5.9) (on the full grid: the skew central difference), relative
    Frobenius defect <= 1e-13; heun's defect >= 1e-8 (negative control).
Exit 0 if everything agrees, 1 otherwise (the failures are printed).
"""
from typing import Any, Dict
import json
import math
import os
import sys

import numpy as np
from scipy.integrate import solve_ivp

FAIL = []


def check(ok: bool, what: Any) -> None:
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        FAIL.append(what)


# ---------------------------------------------------------------- Klein-Gordon (B 5.1)
class KG:
    def __init__(self, M: Any, c: Any, gamma: Any, K: Any) -> None:
        self.M, self.c, self.g, self.K = M, c, gamma, K
        self.dx = 2 * math.pi / M
        self.x = -math.pi + self.dx * np.arange(M)

    def d2(self, u: Any) -> Any:
        return (np.roll(u, -1) - 2 * u + np.roll(u, 1)) / self.dx**2

    def force(self, u: Any) -> Any:
        return self.d2(u) - self.c * u

    def initial(self) -> Any:
        W = math.sqrt(self.K**2 + self.c - self.g**2)
        ph = self.K * self.x
        return np.cos(ph), -self.g * np.cos(ph) + W * np.sin(ph)

    def momentum(self, u: Any, v: Any) -> Any:
        du = (np.roll(u, -1) - np.roll(u, 1)) / (2 * self.dx)
        return self.dx * np.dot(v, du), self.dx * np.dot(np.abs(v), np.abs(du))

    def step(self, name: Any, h: Any, u: Any, v: Any) -> Any:
        g = self.g
        if name == "csv1":  # B (5.3)
            vh = math.exp(-g * h) * v + 0.5 * h * self.force(u)
            u = u + h * vh
            return u, math.exp(-g * h) * (vh + 0.5 * h * self.force(u))
        if name == "csv2":  # B (5.4)
            e = math.exp(-0.5 * g * h)
            vh = (e * v + 0.5 * h * self.force(u)) / (1 + 0.5 * g * h)
            u = e * ((1 + 0.5 * g * h) * e * u + h * vh) / (1 - 0.5 * g * h)
            return u, e * ((1 - 0.5 * g * h) * vh + 0.5 * h * self.force(u))
        f = lambda uu, vv: (vv, self.force(uu) - 2 * g * vv)
        if name == "rk4":
            k1 = f(u, v)
            k2 = f(u + 0.5 * h * k1[0], v + 0.5 * h * k1[1])
            k3 = f(u + 0.5 * h * k2[0], v + 0.5 * h * k2[1])
            k4 = f(u + h * k3[0], v + h * k3[1])
            return (u + h / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0]),
                    v + h / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1]))
        if name == "heun":
            k1 = f(u, v)
            k2 = f(u + h * k1[0], v + h * k1[1])
            return u + 0.5 * h * (k1[0] + k2[0]), v + 0.5 * h * (k1[1] + k2[1])
        raise KeyError(name)

    def exact_semidiscrete(self, u0: Any, v0: Any, t: Any) -> Any:
        U, V = np.fft.fft(u0), np.fft.fft(v0)
        j = np.arange(self.M)
        w2 = self.c + 4 * np.sin(math.pi * j / self.M) ** 2 / self.dx**2
        b = np.sqrt((w2 - self.g**2).astype(complex))
        e = math.exp(-self.g * t)
        C = np.cos(b * t)
        S = np.where(np.abs(b) > 0, np.sin(b * t) / np.where(b == 0, 1, b), t)
        Ut = e * (U * C + (V + self.g * U) * S)
        Vt = e * (V * C - (self.g * V + w2 * U) * S)
        return np.real(np.fft.ifft(Ut)), np.real(np.fft.ifft(Vt))


def kg_case(case: Any, report_case: Dict[str, Any]) -> None:
    p = case["problem"]
    kg = KG(int(p["M"]), p["c"], p["gamma"], int(p["K"]))
    for run in report_case["runs"]:
        name, h = run["method"], run["dt"]
        if name not in ("csv1", "csv2", "rk4", "heun"):
            continue
        n = int(round((case["t_end"]) / h))
        u, v = kg.initial()
        I0, S0 = kg.momentum(u, v)
        res = 0.0
        for i in range(n):
            u, v = kg.step(name, h, u, v)
            I1, S1 = kg.momentum(u, v)
            res = max(res, abs(I1 - math.exp(-2 * kg.g * h) * I0) / S0)
            I0, S0 = I1, S1
        z = np.concatenate([u, v])
        zr = np.array(run["final_state"])
        rel = np.max(np.abs(z - zr)) / max(np.max(np.abs(zr)), 1e-300)
        check(rel <= 1e-10 or not np.all(np.isfinite(zr)),
              f"{case['id']} {name} h={h}: final state vs report, rel diff {rel:.1e}")
        inv = run.get("metrics", {}).get("invariants", {}).get("momentum")
        if inv is not None and inv.get("max_step_res") is not None:
            ours = res <= 1e-13
            theirs = inv["max_step_res"] <= 1e-13
            check(ours == theirs and (ours or res >= 1e-8) == (theirs or inv["max_step_res"] >= 1e-8),
                  f"{case['id']} {name}: momentum residual {res:.2e} (report "
                  f"{inv['max_step_res']:.2e}) same verdict")
    # Exact semi-discrete solution vs scipy.
    u0, v0 = kg.initial()
    T = case["t_end"]
    ue, ve = kg.exact_semidiscrete(u0, v0, T)
    M = kg.M
    sol = solve_ivp(lambda t, z: np.concatenate([z[M:], kg.force(z[:M]) - 2 * kg.g * z[M:]]),
                    (0, T), np.concatenate([u0, v0]), method="DOP853", rtol=1e-12, atol=1e-14)
    d = np.max(np.abs(sol.y[:M, -1] - ue))
    check(d <= 1e-9, f"{case['id']}: semi-discrete exact solution vs scipy DOP853: {d:.1e}")


def kg_pde_vs_fine_grid() -> None:
    # (5.1) against scipy on M = 512: predicted difference = space error of that grid,
    # |e^{-gt}(cos(Kx - Wt) - cos(Kx - W_d t))| <= e^{-gt} |W - W_d| t.
    kg = KG(512, 1.0, 0.375, 2)
    u0, v0 = kg.initial()
    T, M = 2.0, 512
    sol = solve_ivp(lambda t, z: np.concatenate([z[M:], kg.force(z[:M]) - 2 * kg.g * z[M:]]),
                    (0, T), np.concatenate([u0, v0]), method="DOP853", rtol=1e-12, atol=1e-14)
    W = math.sqrt(4 + 1 - 0.375**2)
    Kd2 = 4 * math.sin(kg.dx) ** 2 / kg.dx**2
    Wd = math.sqrt(Kd2 + 1 - 0.375**2)
    pde = math.exp(-0.375 * T) * np.cos(2 * kg.x - W * T)
    d = np.max(np.abs(sol.y[:M, -1] - pde))
    pred = math.exp(-0.375 * T) * abs(W - Wd) * T
    check(abs(d / pred - 1) <= 0.1,
          f"klein-gordon (5.1) vs scipy at M=512: {d:.3e}, predicted space error {pred:.3e}")


# ---------------------------------------------------------------- Burgers (B 5.2)
def burgers() -> None:
    M, g, h = 128, 0.1, 0.01
    dx = 2 * math.pi / M
    x = -math.pi + dx * np.arange(M)
    u0 = np.exp(-0.5 * x * x) / math.sqrt(2 * math.pi)

    def flux(u: Any) -> Any:
        return (np.roll(u, -1) ** 2 - np.roll(u, 1) ** 2) / (4 * dx)

    e = math.exp(-g * h)
    u = u0.copy()
    C = u.sum()
    r = 0.0
    odd, even = np.arange(1, M, 2), np.arange(0, M, 2)
    for _ in range(600):  # B (5.10): w = odd, v = even
        u[odd] = e * u[odd] - 0.5 * h * flux(u)[odd]
        u[even] = e * (e * u[even] - h * flux(u)[even])
        u[odd] = e * (u[odd] - 0.5 * h * flux(u)[odd])
        C1 = u.sum()
        r = max(r, abs(math.log(C1 / C) + 2 * g * h))
        C = C1
    check(r <= 1e-13, f"burgers (5.10): Casimir residual (5.15) {r:.2e} <= 1e-13")
    # NSFD (4.18), dense solve (small M): negative control.
    phi = (1 - math.exp(-2 * g * h)) / (2 * g)
    u = u0.copy()
    C = u.sum()
    r = 0.0
    for _ in range(600):
        A: np.ndarray = np.diag(1 / phi + u / dx) - np.diag(u / dx) @ np.roll(np.eye(M), -1, axis=1)
        u = np.linalg.solve(A, u * (1 / phi - 2 * g))
        C1 = u.sum()
        r = max(r, abs(math.log(C1 / C) + 2 * g * h))
        C = C1
    check(r >= 1e-6, f"burgers NSFD (4.18): Casimir residual {r:.2e} >= 1e-6 (negative control)")


def burgers_conformal_poisson() -> None:
    """E_n of docs/pde.md for the Burgers semi-discrete map (5.10) with B's singular D of (5.9).
    (5.9) is z' = D grad H - 2 gamma z, D = skew central difference (D_{j,j+1} = 1, D_{j,j-1} = -1,
    up to a constant), H = -sum u^3/6 (times that constant). With y = e^{2 gamma t} z the flow is
    a Poisson map of D (time-dependent Hamiltonian), so the damped step map satisfies
    Psi D Psi^T = e^{-4 gamma h} D = e^{-2 dGamma} D (Gamma = 2 gamma t, docs/pde.md item 1): the
    same power as the canonical law.  D is singular (kernel: the Casimir gradient 1 and, for even
    M, the alternating vector), so this is the Poisson (not symplectic) condition; it is the one
    the splitting (5.10) keeps, each of its three substeps being the exact flow of a Poisson
    subsystem times a damping factor."""
    M, g, h = 16, 0.1, 0.05
    dx = 2 * math.pi / M
    x = -math.pi + dx * np.arange(M)
    D = np.roll(np.eye(M), 1, axis=1) - np.roll(np.eye(M), -1, axis=1)   # D[j, j+1] = 1
    e = math.exp(-g * h)
    odd, even = np.arange(1, M, 2), np.arange(0, M, 2)

    def flux(u: Any) -> Any:
        return (np.roll(u, -1, axis=-1) ** 2 - np.roll(u, 1, axis=-1) ** 2) / (4 * dx)

    def csv(u: Any) -> Any:
        u = np.array(u)
        u[..., odd] = e * u[..., odd] - 0.5 * h * flux(u)[..., odd]
        u[..., even] = e * (e * u[..., even] - h * flux(u)[..., even])
        u[..., odd] = e * (u[..., odd] - 0.5 * h * flux(u)[..., odd])
        return u

    def heun(u: Any) -> Any:
        f = lambda v: -flux(v) - 2 * g * v
        k1 = f(u)
        return u + 0.5 * h * (k1 + f(u + h * k1))

    def defect(step: Any) -> Any:
        u = np.exp(-0.5 * x * x) / math.sqrt(2 * math.pi) + 0.3 * np.sin(3 * x)
        worst: Any = 0.0
        for _ in range(40):
            Z = u[None, :] + 1e-30j * np.eye(M)
            P = (np.imag(step(Z)) / 1e-30).T
            E = P @ D @ P.T - math.exp(-4 * g * h) * D
            worst = max(worst, np.linalg.norm(E) / (math.exp(-4 * g * h) * np.linalg.norm(D)))
            u = step(u)
        return worst

    r = defect(csv)
    check(r <= 1e-13, f"burgers (5.10): Psi D Psi^T = e^{{-4 gamma h}} D, defect {r:.2e} <= 1e-13")
    r = defect(heun)
    check(r >= 1e-8, f"burgers heun: Poisson defect {r:.2e} >= 1e-8 (negative control)")


# ---------------------------------------------------------------- NLS (B 5.3)
def nls() -> None:
    M, g, lam, h = 64, 0.1, 2.0, 0.01
    dx = 2 * math.pi / M
    x = -math.pi + dx * np.arange(M)
    psi0 = 0.6 * np.exp(1j * x) + 0.3 * np.exp(3j * x)
    sig = 4 * np.sin(math.pi * np.arange(M) / M) ** 2 / dx**2

    def step(psi: Any, imp: Any) -> Any:
        Y = psi if imp else math.exp(-g * h) * psi
        Phi = Y.copy()
        for _ in range(100):
            rhs = 2j / h * Y - lam * np.abs(Phi) ** 2 * Phi
            new = np.fft.ifft(np.fft.fft(rhs) / (2j / h + (2j * g if imp else 0) - sig))
            if np.max(np.abs(new - Phi)) <= 1e-15:
                Phi = new
                break
            Phi = new
        return (2 * Phi - Y) if imp else math.exp(-g * h) * (2 * Phi - Y)

    for imp in (False, True):
        psi = psi0.copy()
        I = np.sum(np.abs(psi) ** 2)
        R = 0.0
        for _ in range(500):
            psi = step(psi, imp)
            I1 = np.sum(np.abs(psi) ** 2)
            R = max(R, abs(math.log(I1 / I) + 4 * g * h))
            I = I1
        if imp:
            check(R >= 1e-8, f"nls IMP (5.28): R_2 {R:.2e} >= 1e-8 (negative control)")
        else:
            check(R <= 1e-13, f"nls IF (4.15): R_2 {R:.2e} <= 1e-13")


def main() -> Any:
    if len(sys.argv) < 2:
        print(__doc__)
        return 2
    report = json.load(open(os.path.join(sys.argv[1], "report.json")))
    cases_dir = os.path.join(os.path.dirname(os.path.abspath(__file__)), "cases")
    seen = 0
    for rc in report["cases"]:
        if not rc["id"].startswith("pde-"):
            continue
        case = json.load(open(os.path.join(cases_dir, rc["id"] + ".json")))
        if case["problem"]["id"] == "klein-gordon":
            kg_case(case, rc)
            seen += 1
    check(seen > 0, f"{seen} pde-* Klein-Gordon cases in the report")
    kg_pde_vs_fine_grid()
    burgers()
    burgers_conformal_poisson()
    nls()
    print(f"{len(FAIL)} failure(s)")
    return 1 if FAIL else 0


if __name__ == "__main__":
    sys.exit(main())
