"""The user's own methods: the cross-check reads the method files a run loaded (docs/method-files.md)
and steps their tableaux with its own engines, so a method brought as a file is reproduced like a
built-in one.  Independent of dampsym's parser: the coefficients are evaluated here from the
file's text by the grammar docs/method-files.md gives (an expression in +, -, *, /, sqrt and
parentheses, or a JSON number), in long-double arithmetic (mpmath at a 64-bit mantissa, every
operation rounded to nearest, as the documented "evaluated in long double") and rounded to
double once.

Families stepped here: `exponential-rk` (B (2.7), (2.10): rk_family_step on the conformal form,
coefficients at x = Gamma(t + h) - Gamma(t)), `partitioned-exponential-rk` (B (2.14), perk_step at
B's x_B = 2x, pairs whose stages can be ordered), `partitioned-rk` (xmethods.prk_file_step, on the
separable form) and `rk` -- explicit tableaux as the built-in explicit RK methods
(xmethods.EXPLICIT_RK: the compiled loops, the stability polynomial), implicit tableaux by the
RK-family Newton step (xmethods.rk_family_step, Newton counts by xnewton), and either under the
integrating factor B(2.5) (xmethods.ifrk_coef, as glifrk); `general-linear` (BD (2.3), BS) by
xmethods.GLM, the built-in glm4's stepper, with the file's [A U; B V], c and starting method.  A
file the cross-check cannot step (a coupled partitioned exponential pair, a file it cannot read) is
named with the reason in the runs it leaves "not reproduced".

Where the files are found (as dampsym finds them): every case file's `method_files` (relative to
the case file), the run's `--methods` (provenance.selection.method_files) and every *.json in
`methods/` beside the run's cases directory."""
from __future__ import annotations

import glob
import json
import os
import re
import stat
from typing import Any, Dict, List, Optional, Tuple

import mpmath
import numpy as np

from . import xcache
from . import xmethods as xm
from . import xnewton

# a method file larger than this is not read (as dampsym: docs/method-files.md "The format")
FILE_LIMIT = 16 << 20
# where a registered file method's coefficients are kept (xmethods)
FILE_TABLES = ("FILE_RK", "FILE_PRK", "FILE_ERK", "FILE_PERK", "FILE_GLM")
# method id -> why the cross-check does not step it (a family without an engine here, a file it
# cannot read): the reason its runs are not reproduced
UNSUPPORTED: Dict[str, str] = {}
Json = Dict[str, Any]


class MethodFileError(ValueError):
    """A coefficient or a file the cross-check cannot read."""


_TOKEN = re.compile(r"\s*(?:(\d+(?:\.\d+)?)|(sqrt)|([-+*/()]))")


def _tokens(text: str) -> List[str]:
    out, pos, text = [], 0, text.rstrip()
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if m is None or m.end() == pos:
            raise MethodFileError("coefficient %r: cannot read it at position %d" % (text, pos))
        out.append(m.group(0).strip())
        pos = m.end()
    return out


class _Parser:
    """expr := term (('+'|'-') term)*; term := factor (('*'|'/') factor)*;
    factor := ('+'|'-') factor | number | 'sqrt' '(' expr ')' | '(' expr ')'."""

    def __init__(self, text: str) -> None:
        self.text, self.toks, self.i = text, _tokens(text), 0

    def peek(self) -> Optional[str]:
        return self.toks[self.i] if self.i < len(self.toks) else None

    def take(self, want: Optional[str] = None) -> str:
        tok = self.peek()
        if tok is None or (want is not None and tok != want):
            raise MethodFileError("coefficient %r: expected %s" % (self.text, want or "more"))
        self.i += 1
        return tok

    def expr(self) -> Any:
        v = self.term()
        while self.peek() in ("+", "-"):
            v = v + self.term() if self.take() == "+" else v - self.term()
        return v

    def term(self) -> Any:
        v = self.factor()
        while self.peek() in ("*", "/"):
            if self.take() == "*":
                v = v * self.factor()
                continue
            d = self.factor()
            if d == 0:
                raise MethodFileError("coefficient %r: division by zero" % self.text)
            v = v / d
        return v

    def factor(self) -> Any:
        tok = self.take()
        if tok in ("+", "-"):
            v = self.factor()
            return v if tok == "+" else -v
        if tok == "sqrt":
            self.take("(")
            v = self.expr()
            self.take(")")
            if v < 0:
                raise MethodFileError("coefficient %r: sqrt of a negative number" % self.text)
            return mpmath.sqrt(v)
        if tok == "(":
            v = self.expr()
            self.take(")")
            return v
        if tok[0].isdigit():
            return mpmath.mpf(tok)
        raise MethodFileError("coefficient %r: unexpected %r" % (self.text, tok))


def coefficient(v: Any) -> float:
    """A coefficient of a method file: a JSON number as it is, an expression string evaluated
    in long double (64-bit mantissa, each operation rounded) and rounded to double once."""
    if isinstance(v, bool) or not isinstance(v, (int, float, str)):
        raise MethodFileError("coefficient %r: neither a number nor an expression" % (v,))
    if not isinstance(v, str):
        return float(v)
    with mpmath.workprec(64):
        p = _Parser(v)
        x = p.expr()
        if p.peek() is not None:
            raise MethodFileError("coefficient %r: unexpected %r" % (v, p.peek()))
        out = float(x)
    if out != out or out in (float("inf"), float("-inf")):
        raise MethodFileError("coefficient %r: not finite" % v)
    return out


def tableau(t: Any) -> Tuple[List[List[float]], List[float], List[float]]:
    """(A, b, c) of a {"A", "b", "c"} object, A square s x s, b and c of length s."""
    if not isinstance(t, dict) or not all(k in t for k in ("A", "b", "c")):
        raise MethodFileError("tableau: needs A, b and c")
    A = [[coefficient(x) for x in row] for row in t["A"]]
    b, c = [coefficient(x) for x in t["b"]], [coefficient(x) for x in t["c"]]
    s = len(b)
    if s < 1 or len(c) != s or len(A) != s or any(len(row) != s for row in A):
        raise MethodFileError("tableau: A must be s x s and b, c of length s")
    return A, b, c


def register_rk(mid: str, A: List[List[float]], b: List[float], c: List[float], integrating_factor: bool,
                source: str) -> None:
    """An `rk` method file's method, known to the engines of xmethods (and xnewton's counts)."""
    explicit = all(A[i][j] == 0.0 for i in range(len(b)) for j in range(i, len(b)))
    if explicit and not integrating_factor:
        xm.EXPLICIT_RK[mid] = (A, b, c)
    else:
        xm.FILE_RK[mid] = ("if" if integrating_factor else "plain", A, b, c)
    if explicit:
        xm.EXPLICIT_EVALS[mid] = len(b)
    else:
        xm.IMPLICIT.add(mid)
        xnewton.SUPPORTED.add(mid)
    if integrating_factor:
        xm.NEEDS_CONFORMAL.add(mid)
    xm.METHODS.add(mid)
    xm.COEFFICIENT_SOURCES[mid] = "%s (method file, read by the cross-check)" % source


def register_prk(mid: str, q: Any, p: Any, source: str) -> None:
    """A `partitioned-rk` file's pair (q and p tableaux of one size), stepped by
    xmethods.prk_file_step: stage by stage when its stages can be ordered (then one force
    evaluation per stage whose F_i some weight reads), else by Newton."""
    if len(q[1]) != len(p[1]):
        raise MethodFileError("partitioned-rk: the q and p tableaux must have the same size")
    xm.FILE_PRK[mid] = (q, p)
    s = len(q[1])
    if xm.prk_schedule(q[0], p[0]) is not None:
        xm.EXPLICIT_EVALS[mid] = sum(1 for i in range(s)
                                     if p[1][i] != 0 or any(p[0][k][i] != 0 for k in range(s)))
    else:
        xm.IMPLICIT.add(mid)
    xm.NEEDS_SEPARABLE.add(mid)
    xm.METHODS.add(mid)
    xm.COEFFICIENT_SOURCES[mid] = "%s (method file, read by the cross-check)" % source


def phi_terms(v: Any) -> List[Tuple[float, Optional[str], float]]:
    """A coefficient of an exponential tableau (docs/method-files.md): a constant, a term
    {"coef": C, "phi": NAME, "arg": K} = C NAME(K x), or a list of terms (their sum)."""
    if isinstance(v, list):
        if not v:
            raise MethodFileError("an empty list of terms")
        return [t for e in v for t in phi_terms(e)]
    if not isinstance(v, dict):
        return [(coefficient(v), None, 0.0)]
    name = v.get("phi")
    if name not in xm.PHI or set(v) - {"coef", "phi", "arg"}:
        raise MethodFileError("term %r: phi must be one of %s" % (v, ", ".join(sorted(xm.PHI))))
    return [(coefficient(v.get("coef", 1)), name, coefficient(v.get("arg", 1)))]


def exp_tableau(t: Any) -> Tuple[Any, Any, Any, Any, Any]:
    """(c, A, phi, b, phi0) of an exponential tableau, each entry's terms (phi_terms)."""
    if not isinstance(t, dict) or not all(k in t for k in ("c", "A", "phi", "b", "phi0")):
        raise MethodFileError("tableau: needs c, A, phi, b and phi0")
    c = [coefficient(x) for x in t["c"]]
    A = [[phi_terms(x) for x in row] for row in t["A"]]
    phi, b = [phi_terms(x) for x in t["phi"]], [phi_terms(x) for x in t["b"]]
    s = len(c)
    if s < 1 or len(phi) != s or len(b) != s or len(A) != s or any(len(r) != s for r in A):
        raise MethodFileError("tableau: A must be s x s and c, phi, b of length s")
    return c, A, phi, b, phi_terms(t["phi0"])


def _nonzero(A: Any) -> List[List[float]]:
    """1 where an entry of an exponential A is not identically 0, else 0."""
    return [[float(any(c != 0.0 for c, _, _ in e)) for e in row] for row in A]


def register_erk(mid: str, tab: Any, source: str) -> None:
    """An `exponential-rk` file (B (2.7), (2.10)), on the conformal form, by rk_family_step."""
    nz, s = _nonzero(tab[1]), len(tab[0])
    xm.FILE_ERK[mid] = tab
    if all(nz[i][j] == 0.0 for i in range(s) for j in range(i, s)):
        xm.EXPLICIT_EVALS[mid] = s
    else:
        xm.IMPLICIT.add(mid)
        xnewton.SUPPORTED.add(mid)
    xm.NEEDS_CONFORMAL.add(mid)
    xm.METHODS.add(mid)
    xm.COEFFICIENT_SOURCES[mid] = "%s (method file, read by the cross-check)" % source


def register_perk(mid: str, q: Any, p: Any, source: str) -> None:
    """A `partitioned-exponential-rk` pair (B (2.14)) whose stages can be ordered (perk_step's
    sweeps are then exact); a coupled pair is not stepped here."""
    s = len(q[0])
    if len(p[0]) != s:
        raise MethodFileError("partitioned-exponential-rk: the q and p tableaux must have the same size")
    if xm.prk_schedule(_nonzero(q[1]), _nonzero(p[1]), damped=False) is None:
        raise MethodFileError("a partitioned-exponential-rk pair with coupled stages: the cross-check "
                              "steps only pairs whose stages can be computed one after the other")
    xm.FILE_PERK[mid] = (q, p)
    nzp = _nonzero(p[1])
    xm.EXPLICIT_EVALS[mid] = sum(1 for j in range(s) if any(nzp[k][j] for k in range(s))
                                 or any(c != 0.0 for c, _, _ in p[3][j]))
    xm.NEEDS_SEPARABLE.add(mid)
    xm.METHODS.add(mid)
    xm.COEFFICIENT_SOURCES[mid] = "%s (method file, read by the cross-check)" % source


def _matrix(v: Any, rows: int, cols: int, key: str) -> Any:
    """A rows x cols matrix of coefficients (a list of rows)."""
    if not isinstance(v, list) or len(v) != rows or any(not isinstance(r, list) or len(r) != cols
                                                        for r in v):
        raise MethodFileError("general-linear: %s must be %d x %d" % (key, rows, cols))
    return np.array([[coefficient(x) for x in r] for r in v], float).reshape(rows, cols)


def _vector(v: Any, n: int, key: str) -> Any:
    if not isinstance(v, list) or len(v) != n:
        raise MethodFileError("general-linear: %s must have %d entries" % (key, n))
    return np.array([coefficient(x) for x in v], float)


def glm_coefficients(doc: Json) -> Dict[str, Any]:
    """A `general-linear` file's [A U; B V], c and starting method [A0 U0; B0 V0], c0 (as
    xmethods.GLM4); without "starting" (r = 1 only) y^[0] = y_0.  G and D are a certificate,
    not part of the step."""
    A, V = doc.get("A"), doc.get("V")
    if not isinstance(A, list) or not A or not isinstance(V, list) or not V:
        raise MethodFileError("general-linear: needs A (s x s) and V (r x r)")
    s, r = len(A), len(V)
    k = dict(A=_matrix(A, s, s, "A"), U=_matrix(doc.get("U"), s, r, "U"),
             B=_matrix(doc.get("B"), r, s, "B"), V=_matrix(V, r, r, "V"), c=_vector(doc.get("c"), s, "c"))
    st = doc.get("starting")
    if st is None:
        if r != 1:
            raise MethodFileError("general-linear: r = %d values need a starting method" % r)
        st = {"V": [1]}
    if not isinstance(st, dict):
        raise MethodFileError("general-linear: starting must be an object")
    s0 = len(st.get("A") or [])
    k.update(A0=_matrix(st.get("A") or [], s0, s0, "starting.A"),
             U0=_vector(st.get("U") if s0 else [], s0, "starting.U"),
             B0=_matrix(st.get("B") if s0 else [[] for _ in range(r)], r, s0, "starting.B"),
             V0=_vector(st.get("V"), r, "starting.V"), c0=_vector(st.get("c") if s0 else [], s0, "starting.c"))
    return k


def register_glm(mid: str, doc: Json, source: str) -> None:
    """A `general-linear` file (BD (2.3), BS), stepped by xmethods.GLM on the plain form as the
    built-in glm4 is: its r values y^[n] are the multivalue state; Newton counts (xnewton) for
    every shape of A."""
    xm.FILE_GLM[mid] = glm_coefficients(doc)
    xm.MULTIVALUE.add(mid)
    xm.IMPLICIT.add(mid)
    xnewton.SUPPORTED.add(mid)
    xm.METHODS.add(mid)
    xm.COEFFICIENT_SOURCES[mid] = "%s (method file, read by the cross-check)" % source


def read_file(path: str) -> Json:
    """A method file: a regular file of at most FILE_LIMIT bytes holding a JSON object with an id."""
    try:
        st = os.stat(path)
        if not stat.S_ISREG(st.st_mode) or st.st_size > FILE_LIMIT:
            raise MethodFileError("%s: not a regular file of at most 16 MiB" % path)
        with open(path) as fh:
            doc = json.load(fh)
    except (OSError, ValueError, RecursionError) as exc:
        raise MethodFileError("%s: %s" % (path, exc))
    if not isinstance(doc, dict) or not isinstance(doc.get("id"), str):
        raise MethodFileError("%s: not a method file (no id)" % path)
    return doc


def _exact(v: Any) -> Any:
    """v with numpy arrays as lists (repr of a float is exact; numpy's repr rounds to 8 digits),
    for the key of our cached results (FILE_DEFS)."""
    if isinstance(v, np.ndarray):
        return v.tolist()
    if isinstance(v, dict):
        return sorted((k, _exact(x)) for k, x in v.items())
    return v


def load(path: str) -> Optional[str]:
    """Registers the method of one file; its id (None when the file has none to read)."""
    try:
        doc = read_file(path)
    except MethodFileError:
        return None
    mid = doc["id"]
    if mid in xm.METHODS or mid in UNSUPPORTED:
        return mid        # the same file named twice, or a built-in id dampsym refused anyway
    family = doc.get("family")
    try:
        if family == "rk":
            A, b, c = tableau(doc.get("tableau"))
            register_rk(mid, A, b, c, doc.get("integrating_factor") is True, os.path.abspath(path))
        elif family == "partitioned-rk":
            register_prk(mid, tableau(doc.get("q")), tableau(doc.get("p")), os.path.abspath(path))
        elif family == "exponential-rk":
            register_erk(mid, exp_tableau(doc.get("tableau")), os.path.abspath(path))
        elif family == "partitioned-exponential-rk":
            register_perk(mid, exp_tableau(doc.get("q")), exp_tableau(doc.get("p")), os.path.abspath(path))
        elif family == "general-linear":
            register_glm(mid, doc, os.path.abspath(path))
        else:
            raise MethodFileError("a method file of family %r: the cross-check steps the 'rk', "
                                  "'partitioned-rk', 'exponential-rk', 'partitioned-exponential-rk' "
                                  "and 'general-linear' families" % family)
    except (MethodFileError, TypeError) as exc:
        UNSUPPORTED[mid] = "%s: %s" % (path, exc)
        return mid
    claims = doc.get("claims")
    xm.FILE_CLAIMS[mid] = [c for c in claims if isinstance(c, str)] if isinstance(claims, list) else []
    xm.FILE_DEFS[mid] = repr((family, [_exact(getattr(xm, t).get(mid)) for t in FILE_TABLES],
                              xm.EXPLICIT_RK.get(mid)))
    xcache.sources_changed()
    return mid


def paths(report: Json, case_files: List[str]) -> List[str]:
    """The method files the run loaded: each case file's `method_files` (relative to the case
    file), the run's --methods and the *.json of methods/ beside its cases directory."""
    out: List[str] = []
    for f in case_files:
        try:
            with open(f) as fh:
                spec = json.load(fh)
        except (OSError, ValueError, RecursionError):
            continue
        mf = spec.get("method_files") if isinstance(spec, dict) else None
        for p in mf if isinstance(mf, list) else []:
            if isinstance(p, str):
                out.append(os.path.join(os.path.dirname(os.path.abspath(f)), p))
    prov = report.get("provenance") or {}
    sel = (prov.get("selection") or {}).get("method_files")
    out += [p for p in sel if isinstance(p, str)] if isinstance(sel, list) else []
    cdir = prov.get("cases_dir")
    if isinstance(cdir, str) and cdir:
        out += sorted(glob.glob(os.path.join(os.path.dirname(os.path.abspath(cdir)), "methods", "*.json")))
    return list(dict.fromkeys(out))


def load_all(report: Json, case_files: List[str]) -> List[str]:
    """Registers every method file of the run; the ids read."""
    ids = [load(p) for p in paths(report, case_files)]
    return [i for i in ids if i is not None]
