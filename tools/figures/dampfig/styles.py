"""Colours, markers and line styles of the methods in the figures (docs/reports.md "Figures").

Colours come from a colour-blind-safe palette (Okabe and Ito's, with Tol's wine): eight colours
that stay apart for the common forms of colour blindness. Greys are never a method's colour: light
grey is the transient (the part of a run outside the attractor statistics), mid grey the reference
or exact solution. A method keeps its marker and line style in every figure (conformal methods
solid, classical and exponential Runge-Kutta methods dashed, the undamped symplectic methods
dash-dotted, any other method dotted); its colour is its preferred palette colour unless another
method of the same group of at most six (a panel's worth, in the case's method order) has it."""

import math
import zlib
from typing import Dict, List, Tuple

Style = Tuple[str, str, str]  # colour '#rrggbb', marker, line style

PALETTE = ["#0072B2", "#D55E00", "#009E73", "#E69F00", "#CC79A7", "#56B4E9", "#000000",
           "#882255"]
MARKERS = ["o", "s", "^", "D", "v", "P", "X", "<", ">", "*", "h", "p"]
REFERENCE_GREY = "#8c8c8c"
TRANSIENT_GREY = "#d0d0d0"
# methods drawn together in a panel at most (issue: readable panels); series figures split runs
# into groups of this many methods in the case's order
GROUP = 6

# method -> (preferred palette index, marker, line style)
STYLES: Dict[str, Tuple[int, str, str]] = {
    "cimp": (0, "o", "-"), "csv1": (1, "s", "-"), "csv2": (2, "^", "-"),
    "glifrk1": (3, "D", "-"), "glifrk2": (4, "v", "-"), "glifrk3": (5, "P", "-"),
    "etdrk2": (4, "X", "-"), "cse-if": (0, "<", "-"), "cse-etd": (1, ">", "-"),
    "csv1-perk": (7, "h", "-"), "csv2-perk": (5, "p", "-"), "glm4": (6, "*", "-"),
    "euler": (7, "o", "--"), "heun": (5, "s", "--"), "rk3": (3, "^", "--"),
    "rk4": (4, "D", "--"), "etdprk2": (7, "8", "--"), "implicit-euler": (2, "v", "--"),
    "gauss1": (7, "P", "--"), "gauss2": (2, "X", "--"), "gauss3": (0, ">", "--"),
    "symplectic-euler": (0, "o", "-."), "symplectic-euler-adjoint": (3, "s", "-."),
    "stormer-verlet": (4, "^", "-."), "implicit-midpoint": (2, "D", "-."),
    # B's Burgers schemes (5.10), (5.12), (4.18), NLS schemes (4.15), (5.27), (5.28), KG box (5.5)
    "burgers-csv": (3, "s", "-"), "burgers-box": (5, "D", "-"), "burgers-nsfd": (1, "v", "--"),
    "kg-box": (6, "D", "-"),
    "nls-if": (0, "p", "-"), "nls-etd": (1, "h", "-"), "nls-imp": (2, "<", "--"),
}


def method_style(method: str) -> Style:
    """(preferred colour, marker, line style) of a method; any method not listed here: a stable
    hash of its id into the palette and the markers, dotted."""
    if method in STYLES:
        k, mk, ls = STYLES[method]
        return PALETTE[k], mk, ls
    i = zlib.crc32(method.encode()) % 1000
    return PALETTE[i % len(PALETTE)], MARKERS[(i // 7) % len(MARKERS)], ":"


def case_styles(methods: List[str]) -> Dict[str, Style]:
    """Styles of the methods of one case, decided in the case's method order: each method its
    preferred colour unless a method earlier in its group of GROUP has it, then the next free
    palette colour. Within a group (what one panel draws) no two methods share a colour."""
    out: Dict[str, Style] = {}
    for i, m in enumerate(methods):
        colour, mk, ls = method_style(m)
        taken = {out[o][0] for o in methods[(i // GROUP) * GROUP:i] if o in out}
        k = PALETTE.index(colour)
        for j in range(len(PALETTE)):
            if PALETTE[(k + j) % len(PALETTE)] not in taken:
                colour = PALETTE[(k + j) % len(PALETTE)]
                break
        out[m] = (colour, mk, ls)
    return out


def groups(methods: List[str]) -> List[List[str]]:
    """The methods in groups of at most GROUP, in order (one panel each)."""
    return [methods[i:i + GROUP] for i in range(0, len(methods), GROUP)] or [[]]


def lab_distance(c1: str, c2: str) -> float:
    """CIE76 ΔE between two '#rrggbb' colours (sRGB, D65)."""
    def lab(h: str) -> Tuple[float, float, float]:
        rgb = [int(h[i:i + 2], 16) / 255 for i in (1, 3, 5)]
        r, g, b = [c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4 for c in rgb]
        x = (0.4124 * r + 0.3576 * g + 0.1805 * b) / 0.95047
        y = 0.2126 * r + 0.7152 * g + 0.0722 * b
        z = (0.0193 * r + 0.1192 * g + 0.9505 * b) / 1.08883
        f = [u ** (1 / 3) if u > 0.008856 else 7.787 * u + 16 / 116 for u in (x, y, z)]
        return 116 * f[1] - 16, 500 * (f[0] - f[1]), 200 * (f[1] - f[2])
    return math.dist(lab(c1), lab(c2))
