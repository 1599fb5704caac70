"""What the figures plot, computed from report.json and the series files without matplotlib
(issue 14; docs/reports.md "Figures"). tools/figures/plot.py draws exactly these data;
verify/figures/test_figure_data.py compares them with report.json; test_figdata.py tests the
helpers (min/max decimation, the fitted slope line).

Everything here is plain Python (json, math): importing it costs nothing, so the data test runs in
a fraction of a second."""

import json
import math
import os
import re
import zlib

# Fixed colour and marker per method, the same in every figure. Known methods first (distinct
# colours for the families), any other method by a stable hash of its id.
PALETTE = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2",
           "#7f7f7f", "#bcbd22", "#17becf", "#393b79", "#637939", "#8c6d31", "#843c39",
           "#7b4173", "#3182bd", "#e6550d", "#31a354", "#756bb1", "#636363"]
MARKERS = ["o", "s", "^", "D", "v", "P", "X", "<", ">", "*", "h", "p"]
KNOWN = ["cimp", "csv1", "csv2", "glifrk1", "glifrk2", "glifrk3", "etdrk2", "cse-if", "cse-etd",
         "csv1-perk", "csv2-perk", "glm4", "euler", "heun", "rk3", "rk4", "gauss1", "gauss2",
         "gauss3", "etdprk2", "stormer-verlet", "symplectic-euler", "symplectic-euler-adjoint",
         "implicit-midpoint", "implicit-euler"]


def method_style(method):
    """(colour, marker) of a method: fixed across all figures."""
    if method in KNOWN:
        i = KNOWN.index(method)
    else:
        i = zlib.crc32(method.encode()) % 1000
    return PALETTE[i % len(PALETTE)], MARKERS[(i // 2) % len(MARKERS)]


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
    with open(os.path.join(report_dir, "report.json")) as f:
        report = json.load(f)
    series = {}
    sdir = os.path.join(report_dir, "series")
    if os.path.isdir(sdir):
        for name in os.listdir(sdir):
            if name.endswith(".json"):
                with open(os.path.join(sdir, name)) as f:
                    s = json.load(f)
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
    ("conformal-symplectic.rel", "E_n / (e^{−2ΔΓ} ‖J⁻¹‖_F)", "log"),
    ("momentum.linear.law_res", "‖P_{n+1} − e^{−2ΔΓ}P_n‖ / S", "log"),
    ("momentum.linear.factor", "P_{n+1}·P_n / ‖P_n‖²", "linear"),
    ("momentum.angular.law_res", "‖L_{n+1} − e^{−2ΔΓ}L_n‖ / S", "log"),
    ("temperature", "temperature (K)", "linear"),
    ("energy-balance.residual", "|D_t H − dH/dt| (B(3.4))", "log"),
]


def series_panels(series):
    """[(key, label, scale)] of the step series present in a case's series file."""
    keys = set()
    for r in series.get("runs", []):
        keys.update(k for k, v in r["series"].items() if isinstance(v, dict) and "y" in v)
    out = []
    for pat, label, scale in SERIES_PANELS:
        if "*" in pat:
            pre, post = pat.split("*")
            for k in sorted(keys):
                if k.startswith(pre) and k.endswith(post):
                    inv = k[len(pre):-len(post)]
                    out.append((k, label.replace("{inv}", inv), scale))
        elif pat in keys:
            out.append((pat, label, scale))
    return out


ORBIT_PROBLEMS = ("kepler", "hill", "lotka-volterra", "outer-solar-system")
PHASE_FIGURES = re.compile(r"Figs? 4\.(6|9)\b|Fig 1\.2\b")


def wants_orbit_figure(case):
    """Orbits for the problems whose papers draw them (Kepler, Hill, Lotka–Volterra, the outer
    solar system) and phase portraits for the cases reproducing F Figs 4.6, 4.9–4.10 and HLW
    Fig 1.2; the other oscillator and pendulum cases show their time series only."""
    return (case["problem"]["id"] in ORBIT_PROBLEMS
            or bool(PHASE_FIGURES.search(case.get("source", ""))))


def drift_fit(case, method, dt):
    """The report's d(t) slope of a run, for the line drawn over d(t)."""
    for r in case["runs"]:
        if r["method"] == method and r["dt"] == dt:
            return r.get("metrics", {}).get("dissipation-drift", {}).get("slope")
    return None
