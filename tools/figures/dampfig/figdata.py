"""What the figures plot, computed from report.json and the series files without matplotlib
(docs/reports.md "Figures"). tools/figures/plot.py draws exactly these data;
verify/figures/test_figure_data.py compares them with report.json; tools/figures/tests test the
helpers (min/max decimation, the fitted slope line, the quantities each figure draws).

Everything here is plain Python (json, math): importing it costs nothing, so the data test runs in
a fraction of a second."""

import math
import os
import re
import zlib
from typing import Any, Dict, List, Optional, Sequence, Set, Tuple, Union

from . import safeio as sio
from .styles import (GROUP, MARKERS, PALETTE, STYLES, Style, case_styles, groups,  # noqa: F401
                     lab_distance, method_style)

Json = Dict[str, Any]
# natural logs of the smallest normal and the largest double: a fitted line's ends must lie between
LOG_TINY, LOG_HUGE = math.log(2.2250738585072014e-308), math.log(1.7976931348623157e308)


def encode_png(pixels: Any, width: int, height: int, channels: int) -> bytes:
    """A PNG file (bytes) of 8-bit pixels given row by row (width × channels bytes per row; 3 = RGB,
    4 = RGBA, e.g. matplotlib's Agg buffer): no row filter and zlib level 1. Pillow's encoder, which
    matplotlib's savefig uses, tries every row filter and cost a sixth of the drawing time; plots
    are mostly flat colour, so the unfiltered rows compress as well (smaller files, in fact)."""
    if channels not in (3, 4) or width < 1 or height < 1:
        raise ValueError(f"encode_png: {width}x{height}x{channels}: need RGB or RGBA, >= 1 pixel")
    stride = width * channels
    view = memoryview(pixels).cast("B")
    if len(view) != stride * height:
        raise ValueError(f"encode_png: {len(view)} bytes for {width}x{height}x{channels}")
    raw = b"".join(b"\0" + view[r * stride:(r + 1) * stride] for r in range(height))
    return png_of_filtered_rows(raw, width, height, channels)


def png_of_filtered_rows(raw: Union[bytes, memoryview], width: int, height: int,
                         channels: int) -> bytes:
    """A PNG file of rows already prefixed by their filter byte 0 (encode_png; render builds
    them with numpy in one copy)."""
    def chunk(kind: bytes, data: bytes) -> bytes:
        return (len(data).to_bytes(4, "big") + kind + data
                + (zlib.crc32(kind + data) & 0xFFFFFFFF).to_bytes(4, "big"))

    ihdr = (width.to_bytes(4, "big") + height.to_bytes(4, "big")
            + bytes([8, 6 if channels == 4 else 2, 0, 0, 0]))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw, 1))
            + chunk(b"IEND", b""))


def decimate_columns(t: Sequence[float], y: Sequence[float], lo: float, hi: float,
                     columns: int) -> Tuple[List[float], List[float]]:
    """Exact decimation for drawing: of the samples falling in each of `columns` equal slices of
    [lo, hi] (one per pixel column of the axes) keep the smallest and the largest (in time
    order; both endpoints of the series too). The line drawn through them covers, in every pixel
    column, the same vertical extent as the full series: no extreme is lost. Non-finite values
    are dropped."""
    n = len(t)
    if n <= 2 * columns or not hi > lo:
        return [a for a, b in zip(t, y) if math.isfinite(b)], [b for b in y if math.isfinite(b)]
    scale = columns / (hi - lo)
    keep: Set[int] = set()
    lo_i = hi_i = -1
    col = None
    for i in range(n):
        v = y[i]
        if not math.isfinite(v):
            continue
        c = int((t[i] - lo) * scale)
        if c != col:
            if lo_i >= 0:
                keep.add(lo_i)
                keep.add(hi_i)
            col, lo_i, hi_i = c, i, i
        else:
            if v < y[lo_i]:
                lo_i = i
            if v > y[hi_i]:
                hi_i = i
    if lo_i >= 0:
        keep.add(lo_i)
        keep.add(hi_i)
    fin = [i for i in range(n) if math.isfinite(y[i])]
    if fin:
        keep.update((fin[0], fin[-1]))
    idx = sorted(keep)
    return [t[i] for i in idx], [y[i] for i in idx]


FIGURE_KINDS = ("convergence", "series", "orbit", "stability", "poincare", "snapshots",
                "portrait")


def case_figure_kinds(case: Json) -> Optional[Set[str]]:
    """The case's "figures" key as a set of kinds: None when absent (the defaults), the empty set
    for false or [] (docs/case-keys.md "figures")."""
    v = case.get("figures")
    if v is None or v is True:
        return None
    if v is False:
        return set()
    return set(v)


def series_path(report_dir: str, case_id: Any) -> str:
    """DIR/series/<case id>.json; the id must be a valid case id (safeio.output_name)."""
    return os.path.join(report_dir, "series", sio.output_name(case_id, ".json"))


def load_series(report_dir: str, case_id: Any) -> Optional[Json]:
    """One case's series file, or None if there is none: a regular file of at most
    safeio.SERIES_LIMIT bytes (safeio.InputProblem otherwise)."""
    try:
        return sio.load_json(series_path(report_dir, case_id), sio.SERIES_LIMIT)
    except FileNotFoundError:
        return None


def decimate_minmax(t: Sequence[float], y: Sequence[float],
                    buckets: int) -> Tuple[List[float], List[float]]:
    """Min/max decimation as the C++ MinMaxDecimator (src/diagnostics/series.hpp): of every
    bucket of ceil(len/buckets) consecutive samples keep the smallest and the largest (in time
    order). Used to thin series further for drawing; keeps every extreme."""
    n = len(y)
    per = max(1, -(-n // max(1, buckets)))
    ot, oy = [], []
    for s in range(0, n, per):
        idx = [i for i in range(s, min(n, s + per)) if math.isfinite(y[i])]
        if not idx:
            continue
        lo = min(idx, key=lambda i: y[i])
        hi = max(idx, key=lambda i: y[i])
        for i in sorted({lo, hi}):
            ot.append(t[i])
            oy.append(y[i])
    return ot, oy


def slope_line(window_dt: Sequence[float], errors_by_dt: Dict[float, float],
               slope: float) -> Optional[Tuple[List[float], List[float]]]:
    """The fitted convergence line drawn over the asymptotic window: e(h) = C h^slope with C
    fitted in the log (least squares of log e − slope log h over the window points), from its
    smallest to its largest h (of the window's points that have an error: a failed run has
    none). Returns ([h_lo, h_hi], [e_lo, e_hi]), evaluated in the log (log C + slope log h: a
    steep fit between close step sizes, as a stability threshold's two runs give, has a C far
    outside the doubles while its line stays among its points), or None when the line leaves the
    doubles."""
    hs = sorted(h for h in window_dt if h in errors_by_dt) or sorted(errors_by_dt)
    logc = sum(math.log(errors_by_dt[h]) - slope * math.log(h) for h in hs) / len(hs)
    xs = [hs[0], hs[-1]]
    logs = [logc + slope * math.log(x) for x in xs]
    if not all(LOG_TINY < v < LOG_HUGE for v in logs):
        return None
    return xs, [math.exp(v) for v in logs]


def fit_line(slope: float, window_dt: Sequence[float],
             errors_by_dt: Dict[float, float]) -> Json:
    """A fit as the figures draw it: its slope, and its line when the line is drawable."""
    line = slope_line(window_dt, errors_by_dt, slope)
    return {"slope": slope, **({"line_h": line[0], "line_error": line[1]} if line else {})}


def loglog_slope(xs: Sequence[float], ys: Sequence[float]) -> float:
    """Least-squares slope of log y against log x."""
    lx = [math.log(x) for x in xs]
    ly = [math.log(y) for y in ys]
    n = len(lx)
    mx, my = sum(lx) / n, sum(ly) / n
    den = sum((a - mx) ** 2 for a in lx)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / den


def linear_fit(xs: Sequence[float], ys: Sequence[float]) -> Tuple[float, float]:
    """(slope, intercept) of the least-squares line y = a x + b."""
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    den = sum((a - mx) ** 2 for a in xs)
    a = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / den if den > 0 else 0.0
    return a, my - a * mx


PAPER_RE = re.compile(r"\b(F|B|HLW|BS|BD)\b[^;]*?\b((?:Figs?|Figures?|Tables?)\.?\s*[0-9][0-9.]*"
                      r"(?:\s*(?:-|–|and|,)\s*[0-9][0-9.]*)*)")


def paper_figure(case: Json) -> str:
    """'F Figs 4.6, 4.7' from a case's source, or '' when it names no paper figure or table."""
    m = PAPER_RE.search(case.get("source", ""))
    if not m:
        return "BS rigid body" if case.get("source", "").startswith("BS") else ""
    return (m.group(1) + " " + m.group(2)).rstrip(".,")


def load(report_dir: str) -> Tuple[Json, Dict[str, Json]]:
    """report.json and the series files ({case id: series}) of a report directory."""
    report = sio.load_json(os.path.join(report_dir, "report.json"), sio.REPORT_LIMIT)
    series = {}
    for c in report["cases"]:
        s = load_series(report_dir, c["id"])
        if s is not None:
            series[s["case"]] = s
    return report, series


def case_timing(report: Json, index: int) -> Optional[Json]:
    t = report.get("timings", {}).get("cases", [])
    if index < len(t) and t[index].get("id") == report["cases"][index]["id"]:
        return t[index]
    return None


def convergence_data(case: Json) -> Dict[str, Json]:
    """Per method: points (dt, final error, kept or dropped with reason) and the fitted line."""
    out: Dict[str, Json] = {}
    fits = case.get("method_metrics", {})
    for r in case["runs"]:
        e = r.get("metrics", {}).get("error", {}).get("final_abs")
        if r.get("status") != "ok" or e is None or not e > 0:
            continue
        out.setdefault(r["method"], {"points": []})["points"].append([r["dt"], e])
    for m, d in out.items():
        o = fits.get(m, {}).get("order")
        d["points"].sort()
        if o is None:
            continue
        dropped = {p["dt"]: p["reason"] for p in o.get("dropped", [])}
        d["dropped"] = [[h, dropped[h]] for h, _ in d["points"] if h in dropped]
        if o.get("ok"):
            errs = {h: e for h, e in d["points"]}
            d["fit"] = {**fit_line(o["slope"], o["window_dt"], errs),
                        "window_dt": o["window_dt"]}
    return out


def local_convergence_data(case: Json) -> Dict[str, Json]:
    out: Dict[str, Json] = {}
    for r in case["runs"]:
        e = r.get("metrics", {}).get("local-error", {}).get("abs")
        if e is None or not e > 0:
            continue
        out.setdefault(r["method"], {"points": []})["points"].append([r["dt"], e])
    for m, d in out.items():
        d["points"].sort()
        o = case.get("method_metrics", {}).get(m, {}).get("local-order")
        if o and o.get("ok"):
            errs = {h: e for h, e in d["points"]}
            d["fit"] = {**fit_line(o["slope"], o["window_dt"], errs),
                        "window_dt": o["window_dt"]}
    return out


def work_precision_data(case: Json, timing: Optional[Json]) -> Dict[str, List[Json]]:
    out: Dict[str, List[Json]] = {}
    if not timing:
        return out
    for i, r in enumerate(case["runs"]):
        e = r.get("metrics", {}).get("error", {}).get("final_abs")
        tr = timing["runs"][i] if i < len(timing["runs"]) else {}
        if r.get("status") != "ok" or e is None or not e > 0 or "timing" not in tr:
            continue
        out.setdefault(r["method"], []).append(
            {"dt": r["dt"], "error": e, "seconds": tr["timing"]["wall_seconds_min"],
             "rhs_evals": r.get("rhs_evals", 0)})
    return out


def stability_data(case: Json, series: Optional[Json]) -> Dict[str, Json]:
    """Per method: the map (codes), F's closed-form boundary and, from the report's rows, the
    empirical boundary and the first h where M is not power-bounded."""
    out: Dict[str, Json] = {}
    maps = (series or {}).get("stability_map", {})
    for m, mm in case.get("method_metrics", {}).items():
        sw = mm.get("stability-sweep")
        if not sw:
            continue
        rows = sw["rows"]
        d = {"omega": sw["omega"],
             "gamma": [r["gamma"] for r in rows],
             "h_F_empirical": [r["h_F_empirical"] for r in rows],
             "h_power_unbounded": [r["h_power_unbounded"] for r in rows],
             "h_F_formula": [r.get("h_F_formula") for r in rows]}
        if m in maps:
            d["map"] = maps[m]
        out[m] = d
    return out


# Step series of a run, in the order of the panels, with their axis labels and scales.
SERIES_PANELS = [
    ("energy.value", r"energy $H(z_n)$", "linear"),  # z: (q, p), the rigid body's z, ...
    ("energy.error", r"$H_{exact} - H_n$", "linear"),
    ("energy.change_res", r"$(H_n - H_0)\,/\,S_H(z_0)$", "linear"),
    ("error.abs", r"$\|z_n - z_{ref}(t_n)\|$", "log"),
    ("measure-pointwise.*.abs", r"$|{c}_n - {c}(t_n)|$", "log"),
    ("measure-pointwise.*.rel", r"$|{c}_n - {c}(t_n)|\,/\,|{c}(t_n)|$", "log"),
    ("invariants.*.step_res", r"step-law residual of {word} ${inv}$ / $S(z_n)$", "log"),
    ("invariants.*.ratio_dev", r"$e^{2\Gamma(t)}\,{inv_n} / {inv_0} - 1$ ({word})", "linear"),
    ("dissipation-drift.d", r"$d(t) = \ln \max q + \Gamma(t)$", "linear"),
    ("field-drift.d", r"$d(t) = \ln \max_x u + \Gamma(t) - \Gamma(t_0)$", "linear"),
    ("conformal-symplectic.rel", r"$E_n\,/\,(e^{-2\Delta\Gamma}\|J^{-1}\|_F)$", "log"),
    ("momentum.linear.law_res", r"$\|P_{n+1} - e^{-2\Delta\Gamma}P_n\|\,/\,S$", "log"),
    ("momentum.linear.factor", r"$P_{n+1}\cdot P_n\,/\,\|P_n\|^2$", "linear"),
    ("momentum.angular.law_res", r"$\|L_{n+1} - e^{-2\Delta\Gamma}L_n\|\,/\,S$", "log"),
    ("temperature", "temperature (K)", "linear"),
    ("energy-balance.residual", r"$|D_t H - \dot H|$ (B (3.4))", "log"),
    ("attractor.probe", "probe {probe} (attractor)", "linear"),
]


# E_n of a problem with a Poisson structure matrix D instead of J (B's Burgers (5.9)): the series
# says so with "form": "structure-matrix" (docs/conventions.md, the conformal-symplectic metric).
STRUCTURE_MATRIX_EN_LABEL = (r"$\|\Psi D\Psi^T - \lambda D\|\,/\,(\lambda\|D\|)$, "
                             r"$\lambda = e^{-2\Delta\Gamma}$")


# the problems' invariant names (invariant_names in src/) as the symbols of their papers: the
# oscillator's conformal energy H_γ, Kepler's L, the rigid body's and Burgers' Casimir C, ...
INVARIANT_SYMBOLS = {"H_gamma": (r"H_{\gamma}", ""), "angular_momentum": ("L", "angular momentum"),
                     "casimir": ("C", "Casimir"), "energy": ("H", "energy"),
                     "momentum": ("P", "momentum"), "mass": ("N", "mass"), "I": ("I", "")}


def invariant_label(label: str, name: str) -> str:
    """A series label with an invariant's symbol ({inv}; {inv_n}, {inv_0} its value at t_n and
    t_0) and its name in words ({word}, ' ({word})'); an unknown name as upright text."""
    sym, word = INVARIANT_SYMBOLS.get(name, (r"\mathrm{" + name.replace("_", r"\_") + "}",
                                             name.replace("_", " ")))

    def at(k: str) -> str:  # H_{\gamma} at t_n: H_{\gamma,n}
        return sym[:-1] + "," + k + "}" if sym.endswith("}") and "_{" in sym else f"{sym}_{{{k}}}"

    return (label.replace("{inv_n}", at("n")).replace("{inv_0}", at("0")).replace("{inv}", sym)
            .replace(" ({word})", f" ({word})" if word else "")
            .replace("{word} ", f"{word} " if word else ""))


def component_symbol(component: str) -> str:
    """A measure's component as a mathtext symbol: q, p, z, q_{2}."""
    sym = "z" if component == "state" else component
    return sym.replace("[", "_{").replace("]", "}")


def lawless_momenta(case: Json) -> Set[str]:
    """The momenta ("linear", "angular") the case's runs measured without a law to check: the
    momentum diagnostic reports such a part with a reason and no residuals (a body in a central
    field: Σp is not conserved, momentum_diagnostic.cpp), while its step observer still records
    the part's series. Decided from the runs' metrics (none reported: nothing is dropped)."""
    out: Set[str] = set()
    for part in ("linear", "angular"):
        reported = [m for r in case.get("runs", [])
                    for m in [((r.get("metrics") or {}).get("momentum") or {}).get(part)]
                    if isinstance(m, dict)]
        if reported and all("reason" in m and "max_law_res" not in m for m in reported):
            out.add(part)
    return out


def series_panels(series: Json, case: Optional[Json] = None) -> List[Tuple[str, str, str]]:
    """[(key, label, scale)] of the step series present in a case's series file (labels in
    mathtext); with the case, without the series of a momentum it has no law for
    (lawless_momenta)."""
    keys: Set[str] = set()
    forms: Dict[str, str] = {}
    lawless = tuple(f"momentum.{p}." for p in sorted(lawless_momenta(case))) if case else ()
    for r in series.get("runs", []):
        for k, v in r["series"].items():
            if isinstance(v, dict) and "y" in v and not (lawless and k.startswith(lawless)):
                keys.add(k)
                for attr in ("form", "probe", "component"):
                    if attr in v:
                        forms[k] = v[attr]
    out = []
    for pat, label, scale in SERIES_PANELS:
        if pat == "conformal-symplectic.rel" and forms.get(pat) == "structure-matrix":
            label = STRUCTURE_MATRIX_EN_LABEL
        if pat == "attractor.probe":
            probe = re.sub(r"\bpsi\b", r"\\psi", forms.get(pat, "s(t)"))  # ψ(0, t), not psi
            label = label.replace("{probe}", "$" + probe + "$")
        if "*" in pat:
            pre, post = pat.split("*")
            for k in sorted(keys):
                if k.startswith(pre) and k.endswith(post):
                    inv = k[len(pre):-len(post)]
                    sym = component_symbol(forms.get(k, inv))
                    out.append((k, invariant_label(label, inv).replace("{c}", sym), scale))
        elif pat in keys:
            out.append((pat, label, scale))
    return out + declared_panels(series, keys - {k for k, _, _ in out} - DRAWN_WITH_ANOTHER)


# Series drawn inside another series' panel (the reference's d(t) beside the methods').
DRAWN_WITH_ANOTHER = {"dissipation-drift.d_reference"}
# What a series that no panel above knows may declare of itself (a new diagnostic's series: its
# C++ part writes them beside "t" and "y"): its axis label and scale.
DECLARED_SCALES = ("linear", "log")
MAX_LABEL = 120
# At most this many such panels (in name order): a series file with thousands of unknown keys
# (hand-made or damaged) must not make a figure of thousands of panels.
MAX_DECLARED = 8


def declared_panels(series: Json, keys: Set[str]) -> List[Tuple[str, str, str]]:
    """[(key, label, scale)] of the step series no entry of SERIES_PANELS draws, in name order:
    each with the "label" and "scale" its series declares (its name and linear otherwise), so
    that a new diagnostic's series is drawn without a change here; the first MAX_DECLARED."""
    out = []
    for k in sorted(keys)[:MAX_DECLARED]:
        v = next(r["series"][k] for r in series.get("runs", []) if k in r["series"])
        label, scale = v.get("label"), v.get("scale")
        ok_label = isinstance(label, str) and 0 < len(label) <= MAX_LABEL
        out.append((k, label if ok_label else k.replace("$", r"\$"),
                    scale if scale in DECLARED_SCALES else "linear"))
    return out


def series_quantities(case: Json, key: str) -> List[str]:
    """The report metrics a drawn series carries: the series name, and for a measure's pointwise
    series the case's measures that reduce it (B Fig 5.1's measure.u_abs_max, u_rel_max)."""
    measures = case.get("measures", {})
    if key == "energy.error":  # |H(U_n) − H(u(t_n))|: the energy-error measures
        return [key] + [f"measure.{n}" for n, m in measures.items()
                        if m.get("quantity") == "energy-error"]
    if not key.startswith("measure-pointwise."):
        return [key]
    comp, norm = key[len("measure-pointwise."):].rsplit(".", 1)
    energy = comp == "energy"
    return [key] + [f"measure.{n}" for n, m in measures.items()
                    if (m.get("quantity") == "energy-error") == energy and m.get("norm", "abs") == norm
                    and (energy or m.get("component", "state") == comp)]


def growth_in_time(case: Json) -> bool:
    """Whether a measure of the case is a growth rate in t (the slope of log of the running
    maximum against log t: HLW Fig 2.2), so that its time series are drawn log–log."""
    return any(m.get("over") == "growth" for m in case.get("measures", {}).values())


def drift_fit(case: Json, method: str, dt: float) -> Optional[float]:
    """The report's d(t) slope of a run, for the line drawn over d(t)."""
    for r in case["runs"]:
        if r["method"] == method and r["dt"] == dt:
            return r.get("metrics", {}).get("dissipation-drift", {}).get("slope")
    return None


# --- What the case's claim reads (its checks' metrics), for the figures to draw it -------------

# Diagnostics whose metric names carry a sub-quantity after the family (invariants.<I>.…,
# momentum.<linear|angular>.…, measure.<name>): the family is the first two parts.
TWO_PART_FAMILIES = ("invariants", "momentum", "measure")


def metric_family(name: str) -> str:
    """The quantity a metric or series name belongs to: 'invariants.casimir' for
    'invariants.casimir.max_step_res', 'measure.theta_mean_abs' for itself, 'energy' for
    'energy.change_res'."""
    parts = name.split(".")
    n = 2 if parts[0] in TWO_PART_FAMILIES else 1
    return ".".join(parts[:n])


def check_metrics(case: Json) -> List[str]:
    """The metrics the case's checks read, each once, in the order of the checks."""
    out: List[str] = []
    for k in case.get("checks", []):
        m = k.get("metric")
        if isinstance(m, str) and m not in out:
            out.append(m)
    return out


def run_metric(run: Json, metric: str) -> Optional[float]:
    """A run's metric by its dotted name ('measure.theta_mean_abs', 'error.final_abs',
    'invariants.casimir.max_step_res'), or None when the run has no finite value of it."""
    node: Any = run.get("metrics", {})
    parts = metric.split(".")
    i = 0
    while i < len(parts) and isinstance(node, dict):
        # a key may itself hold dots (an invariant's name): take the longest that exists
        for j in range(len(parts), i, -1):
            key = ".".join(parts[i:j])
            if key in node:
                node, i = node[key], j
                break
        else:
            return None
    ok = i == len(parts) and isinstance(node, (int, float)) and not isinstance(node, bool)
    return float(node) if ok and math.isfinite(node) else None


def claim_ladder_metric(case: Json) -> Optional[str]:
    """The per-run metric of the case's checks that a convergence figure draws against h instead
    of the final error (B Fig 3.1's mean |θ| error: measure.theta_mean_abs): the first check
    metric other than the final error with a positive value in runs of at least two step sizes."""
    for m in check_metrics(case):
        # the final error is the convergence panel's; a reference's own error estimate is a
        # guard of the comparison, not a property of the method
        if m == "error.final_abs" or "reference" in m:
            continue
        vals = {r["dt"]: run_metric(r, m) for r in case.get("runs", [])}
        if len({h for h, v in vals.items() if v is not None and v > 0}) >= 2 and \
                len({v for v in vals.values() if v is not None}) >= 2:
            return m
    return None


def metric_ladder_data(case: Json, metric: str) -> Dict[str, Json]:
    """Per method: the points (h, metric) of its ok runs and the least-squares slope of log metric
    against log h over all of them (drawn as a line; the report's own order fit is of the final
    error, convergence_data)."""
    out: Dict[str, Json] = {}
    for r in case["runs"]:
        v = run_metric(r, metric)
        if r.get("status") == "ok" and v is not None and v > 0:
            out.setdefault(r["method"], {"points": []})["points"].append([r["dt"], v])
    for d in out.values():
        d["points"].sort()
        hs = [h for h, _ in d["points"]]
        if len(set(hs)) >= 2:
            p = loglog_slope(hs, [v for _, v in d["points"]])
            d["fit"] = fit_line(p, hs, {h: v for h, v in d["points"]})
    return out


def ratio_check_data(case: Json) -> Optional[Json]:
    """The first check that compares two methods as a ratio across the ladder (B Fig 3.1: ETD/IF
    of the mean |θ| error at each h): its name, metric, methods, the ratio per h and the bound of
    the checks of the same metric and methods per h."""
    for k in case.get("checks", []):
        pts = [[p["dt"], p["value"]] for p in k.get("inputs", [])
               if isinstance(p, dict) and "dt" in p and isinstance(p.get("value"), (int, float))]
        if k.get("form") != "ratio" or len({h for h, _ in pts}) < 2:
            continue
        bounds = [[c["dt"], c["expected"], c["op"]] for c in case["checks"]
                  if c.get("form") == "ratio" and c.get("metric") == k.get("metric")
                  and c.get("methods") == k.get("methods") and "dt" in c
                  and c.get("op") in ("le", "lt", "ge", "gt")]
        return {"name": k["name"], "metric": k["metric"], "methods": k.get("methods", []),
                "label": k.get("method", ""), "points": sorted(pts), "bounds": sorted(bounds)}
    return None


def half_trace_data(case: Json, series: Optional[Json]) -> Dict[str, Json]:
    """F Fig 3.4 per method: |½trM(h) − e^{−γh}cos βh| at the series' step sizes (the method on
    the case's oscillator) and the report's fitted h⁴ coefficient (trace-taylor.h4_coeff) with the
    expected one, when the method has a closed form."""
    out: Dict[str, Json] = {}
    maps = (series or {}).get("stability_map", {})
    for m, mm in case.get("method_metrics", {}).items():
        tt = mm.get("trace-taylor")
        ht = maps.get(m, {}).get("half_trace_error")
        if not tt or not ht:
            continue
        pts = [[h, e] for h, e in zip(ht["h"], ht["error"])
               if isinstance(e, (int, float)) and e > 0]
        out[m] = {"points": pts, "c": tt.get("h4_coeff"), "c_expected": tt.get("h4_coeff_expected"),
                  "omega": ht["omega"], "gamma": ht["gamma"]}
    return out


def missing_claim_metrics(case: Json, quantities: Sequence[str]) -> List[str]:
    """The metrics of the case's checks whose quantity (metric_family) none of its figures draws
    (quantities: the names the manifest records for the case's figures). Counts of the run (cost,
    a Newton count) are a table's, not a figure's: a case whose paper item is a table only is not
    held to this (the caller decides)."""
    drawn = {metric_family(q) for q in quantities}
    return [m for m in check_metrics(case) if metric_family(m) not in drawn]


# --- Layout of the notes and legends drawn inside a panel (figures' readability rules) ---------

def coincident_clusters(n: int, pairs: Sequence[Tuple[int, int, float]]) -> List[Tuple[List[int],
                                                                                    float]]:
    """The lines 0..n-1 joined by coinciding pairs (i, j, largest difference) into clusters, each
    with the largest difference of its pairs, in the order of their first line: every line hidden
    under another is named, and a group of six equal lines is one entry, not fifteen pairs."""
    root = list(range(n))

    def find(i: int) -> int:
        while root[i] != i:
            root[i] = root[root[i]]
            i = root[i]
        return i

    for i, j, _ in pairs:
        root[find(j)] = find(i)
    worst: Dict[int, float] = {}
    for i, _, d in pairs:
        worst[find(i)] = max(worst.get(find(i), 0.0), d)
    members: Dict[int, List[int]] = {}
    for i in range(n):
        members.setdefault(find(i), []).append(i)
    return [(m, worst[r]) for r, m in sorted(members.items(), key=lambda kv: kv[1][0])
            if len(m) > 1]


def wrap_lines(text: str, chars: int) -> List[str]:
    """text broken at spaces into lines of at most `chars` characters (a longer word alone)."""
    out: List[str] = []
    for word in text.split(" "):
        if out and len(out[-1]) + 1 + len(word) <= max(1, chars):
            out[-1] += " " + word
        else:
            out.append(word)
    return out


def band_limits(lo: float, hi: float, bottom: float, top: float, log: bool,
                margin: float = 0.04) -> Tuple[float, float]:
    """Axis limits that put the data [lo, hi] between the bands kept free for text: the lowest
    `bottom` and the highest `top` fractions of the panel (notes, a legend), plus a margin on
    each side of the data. On a log axis in decades (lo > 0)."""
    a, b = (math.log10(lo), math.log10(hi)) if log else (lo, hi)
    if not b > a:
        # one value: a decade around it, or a thousandth of it (1 around 0: no 1e-12 ticks)
        pad = 0.5 if log else (abs(a) * 1e-3 if a != 0 else 1.0)
        a, b = a - pad, b + pad
    free = max(0.2, 1.0 - bottom - top - 2 * margin)
    span = (b - a) / free
    y0 = a - (bottom + margin) * span
    y1 = y0 + span
    return (10.0 ** y0, 10.0 ** y1) if log else (y0, y1)
