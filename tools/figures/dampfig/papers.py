"""What each reproduced paper figure shows (axes, range, the feature the text draws from it),
written from the papers' text and captions (docs/references.md, docs/claims.md), so that
figures.md can set it beside dampsym's figure for a reader without the paper. Keyed by the
paper's item ('B Fig 3.1'), never by a case: a case naming an item not listed here gets
'(not described)'."""

import re
from typing import Dict, List

PAPER_FIGURES: Dict[str, str] = {
    "F Fig 3.1": "stability of CIMP on the oscillator: the (h, γ) region where F's condition "
                 "|½tr M| < e^{−γh} holds (closed form F(3.12))",
    "F Fig 3.2": "the same region for CSV1 (F(3.17))",
    "F Fig 3.3": "the same region for CSV2 (F(3.22))",
    "F Fig 3.4": "the half-trace error ½tr M − e^{−γh}cos βh against h: O(h⁴), with its h⁴ "
                 "coefficient (F(3.13), (3.18), (3.23), which have typos: conventions §5)",
    "F Fig 4.1": "q_exact − q against t ≤ 100 for CIMP, CSV1, CSV2 (Δt = .0125, γ = .025): "
                 "all small, CSV1 = CSV2 slightly below CIMP",
    "F Fig 4.2": "H − H₀ against t for γ = 0: CIMP exact, CSV1/CSV2 in a band without drift",
    "F Fig 4.3": "H_exact − H against t for γ = .0001: CSV1 = CSV2, CIMP essentially zero",
    "F Fig 4.4": "relative error |U − u|/|u| against t for several γ: CSV lower at small γ, "
                 "CIMP lower at γ = .5",
    "F Fig 4.5": "H against t for RK3 beside the conformal methods: RK3 drifts",
    "F Fig 4.6": "phase portrait (q, p) at Δt = .5, γ = .005: RK3's spiral dissipates at a "
                 "step-dependent rate (a hole in the portrait)",
    "F Fig 4.7": "d(t) = ln max q + γt at the maxima: flat for CIMP, CSV1, CSV2, drifting for "
                 "RK3",
    "F Fig 4.8": "pendulum q_exact − q against t ≤ 100 (Δt = .0125, γ = .025): 'equal' for the "
                 "three methods",
    "F Fig 4.9": "pendulum: the decay of the maxima against t (Δt = .025, γ = .05): all methods "
                 "follow the exact decay",
    "F Fig 4.10": "zoom of Fig 4.9: CIMP slightly closer to the exact decay",
    "F Fig 4.11": "pendulum d(t) at the maxima (γ = .0025): no drift for any method",
    "F Fig 4.12": "pendulum total energy against t (Δt = .025, γ = .02): all three close",
    "F Fig 4.13": "pendulum H_exact − H against t: no method better throughout",
    "F Table 4.1": "function calls of CIMP, CSV1, CSV2 at Δt = .025 for six γ (a table)",
    "B Fig 3.1": "mean |θ_n − θ(t_n)| against the step size (four h) for IF (2.18) and ETD "
                 "(2.19), κ = 1, 5, 20, γ = 0.01, T = 50: ETD below IF, more so as h falls",
    "B Fig 3.2": "local error of one step against h, log–log, GL-IFRK s = 1, 2, 3: slopes "
                 "2s + 1",
    "B Fig 3.3": "E_n (3.2) against t for (3.1) with γ(t) = ½ε cos 2t: round-off for GL-IFRK, "
                 "far above it for Gauss",
    "B Fig 3.4": "energy-balance residual R(t_n) (3.4) against t: left imaginary γ, right real "
                 "γ (rapid decay); PERK smallest",
    "B Fig 3.5": "Poincaré sections (q mod 2π, p) of the driven pendulum: the conformal methods "
                 "reproduce the chaotic set, Heun fails at a larger step",
    "B Fig 3.6": "per-step linear and angular momentum factors of the N-body system against "
                 "B Table 3.1's laws (differences below machine precision)",
    "B Table 3.1": "per-step factors of Σp and Σq×p for CSV1, CSV2, CIMP (a table)",
    "B Fig 3.7": "conformal quadratic invariant residuals (Casimir, energy) of the rigid body "
                 "against t: round-off for GL-IFRK/ERK, falling with the order for Gauss",
    "B Fig 5.1": "damped Klein–Gordon: absolute error against t (falls with the solution, to "
                 "~1e-9 at t = 50) and relative error (stays near 1e-2) for CSV1, CSV2, CIMP",
    "B Fig 5.2": "d(t) = ln max_x u + γt (5.6) against t: no drift for the three methods",
    "B Fig 5.3": "total conformal momentum and its residual against t: round-off",
    "B Fig 5.4": "modified Burgers snapshots u(x) from a Gaussian at several t for (5.10), (5.12) "
                 "and NSFD (4.18): the conformal schemes closer to the solution",
    "B Fig 5.5": "residual of the mass law (5.15) against t: round-off for the conformal "
                 "schemes, not for NSFD",
    "B Fig 5.6": "linear Schrödinger: residuals of e^{4γt}I₁, I₂, I₃ against t for IF and ETD",
    "B Fig 5.7": "L∞ errors against the step, log–log: the methods' order",
    "B Fig 5.8": "damped NLS: residual of e^{4γt}I₂ against t for IF, ETD (round-off) and IMP",
    "B Fig 5.9": "soliton collision: |ψ| profiles and residuals R₁, R₂ against t; R₁ rises "
                 "only near the collision",
    "B Fig 5.10": "driven damped NLS: |ψ(0, t)| against t and ψ(0, t) in the complex plane; "
                  "(a) all schemes settle on the same periodic attractor, (b) a chaotic one",
    "HLW Fig 1.1": "Lotka–Volterra orbits (u, v), h = 0.12: explicit Euler spirals out, "
                   "implicit Euler in, symplectic Euler and midpoint closed curves",
    "HLW Fig 1.2": "pendulum phase portraits (q, p), h = 0.3: explicit Euler spirals, symplectic "
                   "Euler and midpoint keep the qualitative behaviour",
    "HLW Fig 2.1": "Kepler orbits (q₁, q₂), e = 0.6: explicit Euler spirals out; with a 100× "
                   "larger step symplectic Euler's ellipse turns clockwise, the midpoint rule's "
                   "anticlockwise",
    "HLW Fig 2.2": "Kepler energy error and global error against t, log–log: H error bounded for "
                   "the symplectic methods, linear for explicit Euler; global error linear / "
                   "quadratic",
    "HLW Table 2.1": "error in H, L and the global error as powers of t and h (a table)",
    "HLW Table 2.2": "outer solar system data (a table)",
    "HLW Fig 2.3": "outer solar system orbits over 200 000 days: explicit Euler spirals out, "
                   "symplectic Euler and midpoint correct",
    "HLW Fig 3.1": "argon crystal: total energy and temperature against t for explicit Euler, "
                   "symplectic Euler and Verlet (80 and 40 fs)",
    "HLW Table 3.1": "argon crystal initial data (a table)",
    "BS rigid body": "Butcher's slides: the rigid body's quadratic invariants under a "
                     "G-symplectic general linear method against Gauss and RK4",
}

ITEM_RE = re.compile(r"(Figs?|Tables?)\.?\s*([0-9][0-9.]*(?:\s*(?:-|–|and|,)\s*[0-9][0-9.]*)*)")


def items(paper_ref: str) -> List[str]:
    """'F Figs 4.6, 4.7' -> ['F Fig 4.6', 'F Fig 4.7']; 'F Figs 3.1-3.3' -> 3.1, 3.2, 3.3;
    'B Table 3.1, Fig 3.6' -> ['B Table 3.1', 'B Fig 3.6']."""
    if paper_ref in PAPER_FIGURES:
        return [paper_ref]
    paper = paper_ref.split(" ", 1)[0]
    out: List[str] = []
    for kind, nums in ITEM_RE.findall(paper_ref):
        word = "Table" if kind.startswith("Table") else "Fig"
        for part in re.split(r"\s*(?:,|and)\s*", nums):
            ends = [x.strip().rstrip(".") for x in re.split(r"[-–]", part)]
            if len(ends) == 2 and "." in ends[0]:
                major, a = ends[0].rsplit(".", 1)
                b = ends[1].rsplit(".", 1)[-1]
                out += [f"{paper} {word} {major}.{k}" for k in range(int(a), int(b) + 1)]
            elif ends[0]:
                out.append(f"{paper} {word} {ends[0]}")
    return out


def describe(paper_ref: str) -> str:
    """What the paper's figure(s) show, joined; '(not described)' for an unknown item."""
    found = [f"{i}: {PAPER_FIGURES[i]}" for i in items(paper_ref) if i in PAPER_FIGURES]
    return "; ".join(found) if found else "(not described)"


def is_figure(paper_ref: str) -> bool:
    """Whether the item names a figure (a table reduces to numbers)."""
    return any(" Fig " in i or i == "BS rigid body" for i in items(paper_ref))
