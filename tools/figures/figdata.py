"""What the figures plot, computed from report.json and the series files without matplotlib
(issue 14; docs/reports.md "Figures"). tools/figures/plot.py draws exactly these data;
verify/figures/test_figure_data.py compares them with report.json; test_figdata.py tests the
helpers (min/max decimation, the fitted slope line).

Everything here is plain Python (json, math): importing it costs nothing, so the data test runs in
a fraction of a second."""

import math
import os
import re
import sys
import zlib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import safeio as sio  # noqa: E402

# Fixed colour, marker and line style per method, the same in every figure: conformal methods
# (F, B) solid, classical and exponential Runge-Kutta methods dashed, the symplectic (undamped)
# methods dash-dotted (in sparse plots; dense time series are solid, so colour alone tells runs
# apart there). Colours chosen so that any two methods run together by a case of verify/cases
# differ by CIE76 ΔE >= 25 (test_figdata.py checks it; glifrk2 and gauss3 were two purples
# 15 apart). Any other method: a stable hash of its id into a dotted palette.
STYLES = {
    "cimp": ("#1f77b4", "o", "-"), "csv1": ("#d62728", "s", "-"), "csv2": ("#2ca02c", "^", "-"),
    "glifrk1": ("#ff7f0e", "D", "-"), "glifrk2": ("#9467bd", "v", "-"),
    "glifrk3": ("#8c564b", "P", "-"), "etdrk2": ("#e377c2", "X", "-"),
    "cse-if": ("#17becf", "<", "-"), "cse-etd": ("#bcbd22", ">", "-"),
    "csv1-perk": ("#7f0000", "h", "-"), "csv2-perk": ("#00441b", "p", "-"),
    "glm4": ("#000000", "*", "-"),
    "euler": ("#4d4d4d", "o", "--"), "heun": ("#08306b", "s", "--"), "rk3": ("#fc8d62", "^", "--"),
    "rk4": ("#e7298a", "D", "--"), "etdprk2": ("#a6761d", "8", "--"),
    "implicit-euler": ("#666600", "v", "--"), "gauss1": ("#000080", "P", "--"),
    "gauss2": ("#1b9e77", "X", "--"), "gauss3": ("#40004b", ">", "--"),
    "symplectic-euler": ("#4b0082", "o", "-."), "symplectic-euler-adjoint": ("#ff7f0e", "s", "-."),
    "stormer-verlet": ("#ff00ff", "^", "-."), "implicit-midpoint": ("#2ca02c", "D", "-."),
    # B's Burgers schemes (5.10), (5.12), (4.18)
    "burgers-csv": ("#b8860b", "s", "-"), "burgers-box": ("#008080", "D", "-"),
    "burgers-nsfd": ("#8b0000", "v", "--"),
}
PALETTE = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2",
           "#7f7f7f", "#bcbd22", "#17becf", "#393b79", "#637939", "#8c6d31", "#843c39",
           "#7b4173", "#3182bd", "#e6550d", "#31a354", "#756bb1", "#636363"]
MARKERS = ["o", "s", "^", "D", "v", "P", "X", "<", ">", "*", "h", "p"]


def method_style(method):
    """(colour, marker, line style) of a method: fixed across all figures."""
    if method in STYLES:
        return STYLES[method]
    i = zlib.crc32(method.encode()) % 1000
    return PALETTE[i % len(PALETTE)], MARKERS[(i // 7) % len(MARKERS)], ":"


def case_styles(methods):
    """Styles of the methods of one case: the fixed ones, and for any other method its hashed
    style, unless its colour is within ΔE 25 of a colour already taken in the case (two loaded
    methods, or one that hashes onto a built-in's colour: dense time series tell runs apart by
    colour alone); then the first palette colour after it that is 25 from every taken one (the
    hashed colour if none is). Decided in the order of the case's method list, so the same for
    every figure of the case."""
    out = {m: STYLES[m] for m in methods if m in STYLES}
    taken = [c for c, _, _ in out.values()]
    for m in methods:
        if m in out:
            continue
        c, mk, ls = method_style(m)
        k = PALETTE.index(c)
        for j in range(len(PALETTE)):
            cand = PALETTE[(k + j) % len(PALETTE)]
            if all(lab_distance(cand, t) >= 25 for t in taken):
                c = cand
                break
        out[m] = (c, mk, ls)
        taken.append(c)
    return out


def lab_distance(c1, c2):
    """CIE76 ΔE between two '#rrggbb' colours (sRGB, D65)."""
    def lab(h):
        rgb = [int(h[i:i + 2], 16) / 255 for i in (1, 3, 5)]
        r, g, b = [c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4 for c in rgb]
        x = (0.4124 * r + 0.3576 * g + 0.1805 * b) / 0.95047
        y = 0.2126 * r + 0.7152 * g + 0.0722 * b
        z = (0.0193 * r + 0.1192 * g + 0.9505 * b) / 1.08883
        f = [u ** (1 / 3) if u > 0.008856 else 7.787 * u + 16 / 116 for u in (x, y, z)]
        return 116 * f[1] - 16, 500 * (f[0] - f[1]), 200 * (f[1] - f[2])
    return math.dist(lab(c1), lab(c2))


def encode_png(pixels, width, height, channels):
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

    def chunk(kind, data):
        return (len(data).to_bytes(4, "big") + kind + data
                + (zlib.crc32(kind + data) & 0xFFFFFFFF).to_bytes(4, "big"))

    ihdr = (width.to_bytes(4, "big") + height.to_bytes(4, "big")
            + bytes([8, 6 if channels == 4 else 2, 0, 0, 0]))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw, 1))
            + chunk(b"IEND", b""))


def decimate_columns(t, y, lo, hi, columns):
    """Exact decimation for drawing: of the samples falling in each of `columns` equal slices of
    [lo, hi] (one per pixel column of the axes) keep the smallest and the largest (in time
    order; both endpoints of the series too). The line drawn through them covers, in every pixel
    column, the same vertical extent as the full series: no extreme is lost. Non-finite values
    are dropped."""
    n = len(t)
    if n <= 2 * columns or not hi > lo:
        return [a for a, b in zip(t, y) if math.isfinite(b)], [b for b in y if math.isfinite(b)]
    scale = columns / (hi - lo)
    keep = set()
    lo_i = hi_i = None
    col = None
    for i in range(n):
        v = y[i]
        if not math.isfinite(v):
            continue
        c = int((t[i] - lo) * scale)
        if c != col:
            if lo_i is not None:
                keep.add(lo_i)
                keep.add(hi_i)
            col, lo_i, hi_i = c, i, i
        else:
            if v < y[lo_i]:
                lo_i = i
            if v > y[hi_i]:
                hi_i = i
    if lo_i is not None:
        keep.add(lo_i)
        keep.add(hi_i)
    fin = [i for i in range(n) if math.isfinite(y[i])]
    if fin:
        keep.update((fin[0], fin[-1]))
    idx = sorted(keep)
    return [t[i] for i in idx], [y[i] for i in idx]


FIGURE_KINDS = ("convergence", "series", "orbit", "stability", "poincare", "snapshots",
                "portrait")


def case_figure_kinds(case):
    """The case's "figures" key as a set of kinds: None when absent (the defaults), the empty set
    for false or [] (docs/case-keys.md "figures")."""
    v = case.get("figures")
    if v is None or v is True:
        return None
    if v is False:
        return set()
    return set(v)


def series_path(report_dir, case_id):
    """DIR/series/<case id>.json; the id must be a valid case id (safeio.output_name)."""
    return os.path.join(report_dir, "series", sio.output_name(case_id, ".json"))


def load_series(report_dir, case_id):
    """One case's series file, or None if there is none: a regular file of at most
    safeio.SERIES_LIMIT bytes (safeio.InputProblem otherwise)."""
    try:
        return sio.load_json(series_path(report_dir, case_id), sio.SERIES_LIMIT)
    except FileNotFoundError:
        return None


def decimate_minmax(t, y, buckets):
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


def slope_line(window_dt, errors_by_dt, slope):
    """The fitted convergence line drawn over the asymptotic window: e(h) = C h^slope with C
    fitted in the log (least squares of log e − slope log h over the window points), from its
    smallest to its largest h. Returns ([h_lo, h_hi], [e_lo, e_hi])."""
    hs = sorted(window_dt)
    logc = sum(math.log(errors_by_dt[h]) - slope * math.log(h) for h in hs) / len(hs)
    xs = [hs[0], hs[-1]]
    return xs, [math.exp(logc) * x ** slope for x in xs]


def loglog_slope(xs, ys):
    """Least-squares slope of log y against log x."""
    lx = [math.log(x) for x in xs]
    ly = [math.log(y) for y in ys]
    n = len(lx)
    mx, my = sum(lx) / n, sum(ly) / n
    den = sum((a - mx) ** 2 for a in lx)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / den


def linear_fit(xs, ys):
    """(slope, intercept) of the least-squares line y = a x + b."""
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    den = sum((a - mx) ** 2 for a in xs)
    a = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / den if den > 0 else 0.0
    return a, my - a * mx


PAPER_RE = re.compile(r"\b(F|B|HLW|BS|BD)\b[^;]*?\b((?:Figs?|Figures?|Tables?)\.?\s*[0-9][0-9.]*"
                      r"(?:\s*(?:-|–|and|,)\s*[0-9][0-9.]*)*)")


def paper_figure(case):
    """'F Figs 4.6, 4.7' from a case's source, or '' when it names no paper figure or table."""
    m = PAPER_RE.search(case.get("source", ""))
    if not m:
        return "BS rigid body" if case.get("source", "").startswith("BS") else ""
    return (m.group(1) + " " + m.group(2)).rstrip(".,")


def load(report_dir):
    """report.json and the series files ({case id: series}) of a report directory."""
    report = sio.load_json(os.path.join(report_dir, "report.json"), sio.REPORT_LIMIT)
    series = {}
    for c in report["cases"]:
        s = load_series(report_dir, c["id"])
        if s is not None:
            series[s["case"]] = s
    return report, series


def case_timing(report, index):
    t = report.get("timings", {}).get("cases", [])
    if index < len(t) and t[index].get("id") == report["cases"][index]["id"]:
        return t[index]
    return None


def convergence_data(case):
    """Per method: points (dt, final error, kept or dropped with reason) and the fitted line."""
    out = {}
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
            xs, ys = slope_line(o["window_dt"], errs, o["slope"])
            d["fit"] = {"slope": o["slope"], "window_dt": o["window_dt"], "line_h": xs,
                        "line_error": ys}
    return out


def local_convergence_data(case):
    out = {}
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
            xs, ys = slope_line(o["window_dt"], errs, o["slope"])
            d["fit"] = {"slope": o["slope"], "window_dt": o["window_dt"], "line_h": xs,
                        "line_error": ys}
    return out


def work_precision_data(case, timing):
    out = {}
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


def stability_data(case, series):
    """Per method: the map (codes), F's closed-form boundary and, from the report's rows, the
    empirical boundary and the first h where M is not power-bounded."""
    out = {}
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
    ("energy.value", "energy H(q, p)", "linear"),
    ("energy.error", "H_exact − H_n (dimensionless)", "linear"),
    ("energy.change_res", "(H_n − H_0) / S_H(z_0)", "linear"),
    ("error.abs", "‖z_n − z_ref(t_n)‖ (dimensionless)", "log"),
    ("invariants.*.step_res", "step-law residual of {inv} / S(z_n)", "log"),
    ("invariants.*.ratio_dev", "e^{2Γ(t)} {inv}_n / {inv}_0 − 1", "linear"),
    ("dissipation-drift.d", "d(t) = ln max q + Γ(t)", "linear"),
    ("field-drift.d", "d(t) = ln max_x u + Γ(t) − Γ(t₀)", "linear"),
    ("conformal-symplectic.rel", "E_n / (e^{−2ΔΓ} ‖J⁻¹‖_F)", "log"),
    ("momentum.linear.law_res", "‖P_{n+1} − e^{−2ΔΓ}P_n‖ / S", "log"),
    ("momentum.linear.factor", "P_{n+1}·P_n / ‖P_n‖²", "linear"),
    ("momentum.angular.law_res", "‖L_{n+1} − e^{−2ΔΓ}L_n‖ / S", "log"),
    ("temperature", "temperature (K)", "linear"),
    ("energy-balance.residual", "|D_t H − dH/dt| (B(3.4))", "log"),
    ("attractor.probe", "probe {probe} (attractor)", "linear"),
]


# E_n of a problem with a Poisson structure matrix D instead of J (B's Burgers (5.9)): the series
# says so with "form": "structure-matrix" (docs/conventions.md, the conformal-symplectic metric).
STRUCTURE_MATRIX_EN_LABEL = "‖ΨDΨᵀ − λD‖/(λ‖D‖), λ = e^(−2ΔΓ)"


def series_panels(series):
    """[(key, label, scale)] of the step series present in a case's series file."""
    keys, forms = set(), {}
    for r in series.get("runs", []):
        for k, v in r["series"].items():
            if isinstance(v, dict) and "y" in v:
                keys.add(k)
                if "form" in v:
                    forms[k] = v["form"]
                if "probe" in v:
                    forms[k] = v["probe"]
    out = []
    for pat, label, scale in SERIES_PANELS:
        if pat == "conformal-symplectic.rel" and forms.get(pat) == "structure-matrix":
            label = STRUCTURE_MATRIX_EN_LABEL
        if pat == "attractor.probe":
            label = label.replace("{probe}", forms.get(pat, "s(t)"))
        if "*" in pat:
            pre, post = pat.split("*")
            for k in sorted(keys):
                if k.startswith(pre) and k.endswith(post):
                    inv = k[len(pre):-len(post)]
                    out.append((k, label.replace("{inv}", inv), scale))
        elif pat in keys:
            out.append((pat, label, scale))
    return out


def drift_fit(case, method, dt):
    """The report's d(t) slope of a run, for the line drawn over d(t)."""
    for r in case["runs"]:
        if r["method"] == method and r["dt"] == dt:
            return r.get("metrics", {}).get("dissipation-drift", {}).get("slope")
    return None
