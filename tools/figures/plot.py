#!/usr/bin/python3
"""Draws the figures of a dampsym report directory (issue 14; docs/reports.md "Figures").

    /usr/bin/python3 tools/figures/plot.py REPORT_DIR [--jobs N] [--format png,svg]

Reads REPORT_DIR/report.json and, when the run was made with --figures, REPORT_DIR/series/*.json;
writes REPORT_DIR/figures/<case>-<kind>.png (and .svg/.pdf on request), the list of figures per
case REPORT_DIR/figures/manifest.json (which `dampsym` embeds in report.md) and the paper-figure
gallery REPORT_DIR/figures.md. Figures are drawn in N worker processes (forked after matplotlib is
imported once). Kinds: convergence (with work-precision beside it), series (time series), orbit,
stability, poincare. What each plots is computed in figdata.py (without matplotlib)."""

import argparse
import json
import math
import multiprocessing
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import figdata as fd  # noqa: E402

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

plt.rcParams.update({"font.size": 9, "axes.titlesize": 9, "legend.fontsize": 7,
                     "figure.dpi": 100, "axes.grid": True, "grid.alpha": 0.3})

REPORT = None
SERIES = None
OUT = None
FORMATS = ["png"]


def title_of(case, what):
    paper = fd.paper_figure(case)
    return f"{case['id']}: {what}" + (f"  [{paper}]" if paper else "")


def save(fig, case, kind):
    name = f"{case['id']}-{kind}"
    for ext in FORMATS:
        fig.savefig(os.path.join(OUT, "figures", f"{name}.{ext}"))
    plt.close(fig)
    return f"figures/{name}.png"


def layout(fig, bottom=0.1, top=0.9, left=0.09, right=0.98, hspace=0.35, wspace=0.3):
    """Fixed margins (tight_layout costs most of a figure's drawing time)."""
    fig.subplots_adjust(left=left, right=right, bottom=bottom, top=top, hspace=hspace,
                        wspace=wspace)


def style(m):
    return fd.method_style(m)


def conv_axis(ax, data, ylabel):
    notes = []
    for m, d in data.items():
        c, mk = style(m)
        pts = d["points"]
        dropped = {h for h, _ in d.get("dropped", [])}
        ax.plot([h for h, _ in pts], [e for _, e in pts], color=c, lw=0.8, alpha=0.5)
        kept = [(h, e) for h, e in pts if h not in dropped]
        gone = [(h, e) for h, e in pts if h in dropped]
        label = m
        if "fit" in d:
            f = d["fit"]
            label = f"{m} p = {f['slope']:.3f}"
            ax.plot(f["line_h"], f["line_error"], color=c, ls="--", lw=1.5)
        ax.plot([h for h, _ in kept], [e for _, e in kept], mk, color=c, label=label, ms=5)
        if gone:
            ax.plot([h for h, _ in gone], [e for _, e in gone], mk, mfc="none", mec=c, ms=6)
            for h, why in d["dropped"]:
                notes.append(f"{m} dt={h:g}: {why}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("step size h (time units of the problem)")
    ax.set_ylabel(ylabel)
    handles, labels = ax.get_legend_handles_labels()
    if notes:
        handles.append(Line2D([], [], marker="o", mfc="none", mec="k", ls="none"))
        labels.append("hollow: dropped from the fit")
    handles.append(Line2D([], [], color="k", ls="--"))
    labels.append("fitted slope over the window")
    ax.legend(handles, labels, loc="best", ncol=2 if len(labels) > 8 else 1)
    return notes


def wp_axes(axs, data):
    for m, pts in data.items():
        c, mk = style(m)
        pts = sorted(pts, key=lambda p: p["dt"])
        axs[0].plot([p["seconds"] for p in pts], [p["error"] for p in pts], mk + "-", color=c,
                    label=m, ms=4, lw=1)
        axs[1].plot([p["rhs_evals"] for p in pts], [p["error"] for p in pts], mk + "-", color=c,
                    label=m, ms=4, lw=1)
    for ax, xl in zip(axs, ["bare-loop wall time (s, min of N repetitions)",
                            "right-hand-side evaluations"]):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(xl)
        ax.set_ylabel("final error ‖z_N − z(t_end)‖")
        ax.set_title("work-precision")


def fig_convergence(case, ser, timing):
    """Convergence (and the local error, B Fig 3.2), with work-precision beside it when the
    ladder was timed: one figure, so one save."""
    glob = fd.convergence_data(case)
    loc = fd.local_convergence_data(case)
    wp = fd.work_precision_data(case, timing)
    panels = [p for p in [(glob, "global error ‖z_N − z(t_end)‖ at t_end"),
                          (loc, "local error (one step)")] if p[0]]
    n = len(panels) + (2 if wp else 0)
    fig, axs = plt.subplots(1, n, figsize=(5.2 * n, 4.8), squeeze=False)
    notes = []
    for ax, (data, ylabel) in zip(axs[0], panels):
        notes += conv_axis(ax, data, ylabel)
        ax.set_title("convergence (error vs h, log–log)")
    if wp:
        wp_axes(axs[0][len(panels):], wp)
    fig.suptitle(title_of(case, "convergence" + (" and work-precision" if wp else "")))
    if notes:
        text = "; ".join(notes)
        if len(text) > 300:
            text = text[:297] + "…"
        fig.text(0.01, 0.01, "dropped: " + text, fontsize=6, wrap=True)
    layout(fig, bottom=0.17 if notes else 0.11, top=0.88, left=0.06 / n + 0.03, wspace=0.3)
    return [(save(fig, case, "convergence"), "convergence" + (" and work-precision" if wp else ""))]


def run_label(case, r, multi_dt):
    return f"{r['method']} h={r['dt']:g}" if multi_dt else r["method"]


def fig_series(case, ser):
    panels = fd.series_panels(ser)
    if not panels:
        return []
    runs = [r for r in ser["runs"] if r["series"]]
    multi_dt = len({r["dt"] for r in runs}) > 1
    fig, axs = plt.subplots(len(panels), 1, figsize=(8, 1.9 + 2.0 * len(panels)), sharex=True,
                            squeeze=False)
    for ax, (key, label, scale) in zip(axs[:, 0], panels):
        logged = False
        for r in runs:
            s = r["series"].get(key)
            if not s or not s["y"]:
                continue
            c, mk = style(r["method"])
            t, y = s["t"], s["y"]
            if scale == "log":
                pts = [(a, b) for a, b in zip(t, y) if b > 0]
                if not pts:
                    continue
                t, y = [a for a, _ in pts], [b for _, b in pts]
                logged = True
            lab = run_label(case, r, multi_dt)
            if key == "dissipation-drift.d":
                ax.plot(t, y, mk, color=c, ms=2.5, label=lab)
                slope = fd.drift_fit(case, r["method"], r["dt"])
                if slope is not None and len(t) > 1:
                    b = sum(y) / len(y) - slope * sum(t) / len(t)
                    ax.plot([t[0], t[-1]], [b + slope * t[0], b + slope * t[-1]], "--", color=c,
                            lw=1, label=f"{r['method']} slope {slope:.3g}")
                ref = r["series"].get("dissipation-drift.d_reference")
                if ref and r is runs[0]:
                    ax.plot(ref["t"], ref["y"], "-", color="0.5", lw=0.8, label="reference")
            else:
                ax.plot(t, y, "-", color=c, lw=0.9, label=lab)
        if logged:
            ax.set_yscale("log")
        ax.set_ylabel(label, fontsize=7)
        ax.legend(loc="best", ncol=3, fontsize=6)
    axs[-1, 0].set_xlabel("time t (time units of the problem)")
    fig.suptitle(title_of(case, "time series"))
    height = 1.9 + 2.0 * len(panels)
    layout(fig, bottom=0.5 / height, top=1 - 0.55 / height, left=0.12, hspace=0.12)
    return [(save(fig, case, "series"), "time series")]


def orbit_coords(problem, states):
    """[(x, y, label)] to draw for a problem's states."""
    if not states:
        return []
    col = list(zip(*states))
    if problem == "outer-solar-system":
        nb = len(col) // 6
        return [(col[3 * k], col[3 * k + 1], f"body {k}") for k in range(nb)]
    if problem in ("kepler", "hill"):
        return [(col[0], col[1], "")]
    return [(col[0], col[1], "")]


AXES = {"kepler": ("q1", "q2"), "hill": ("q1", "q2"), "lotka-volterra": ("u", "v"),
        "pendulum": ("q (rad)", "p"), "oscillator": ("q", "p"),
        "outer-solar-system": ("x (AU)", "y (AU)"), "rigid-body": ("z1", "z2")}


def fig_orbit(case, ser):
    runs = [r for r in ser["runs"] if "orbit" in r["series"]]
    if not runs:
        return []
    problem = case["problem"]["id"]
    n = len(runs)
    cols = min(4, n)
    rows = (n + cols - 1) // cols
    fig, axs = plt.subplots(rows, cols, figsize=(3.6 * cols, 3.4 * rows + 0.6), squeeze=False)
    for ax in axs.flat[n:]:
        ax.axis("off")
    xl, yl = AXES.get(problem, ("z1", "z2"))
    for ax, r in zip(axs.flat, runs):
        c, _ = style(r["method"])
        ref = r["series"].get("orbit_reference")
        if ref:
            for x, y, _ in orbit_coords(problem, ref["states"]):
                ax.plot(x, y, "-", color="0.6", lw=2.2, alpha=0.6)
        for x, y, lab in orbit_coords(problem, r["series"]["orbit"]["states"]):
            ax.plot(x, y, "-", color=c, lw=0.6)
        ax.plot([r["series"]["orbit"]["states"][0][0]], [r["series"]["orbit"]["states"][0][1]],
                "k.", ms=5)
        ax.set_title(f"{r['method']} h={r['dt']:g}" + ("  (grey: reference)" if ref else ""))
        ax.set_xlabel(xl)
        ax.set_ylabel(yl)
        if problem in ("kepler", "outer-solar-system", "hill"):
            ax.set_aspect("equal", adjustable="datalim")
    fig.suptitle(title_of(case, "orbits"))
    height = 3.4 * rows + 0.6
    layout(fig, bottom=0.5 / height, top=1 - 0.75 / height, left=0.08, hspace=0.45, wspace=0.35)
    return [(save(fig, case, "orbit"), "orbits")]


MAP_CMAP = ListedColormap(["#c7e9c0", "#fdd49e", "#9ecae1", "#fb6a4a"])


def fig_stability(case, ser):
    data = fd.stability_data(case, ser)
    if not data:
        return []
    n = len(data)
    cols = min(3, n)
    rows = (n + cols - 1) // cols
    fig, axs = plt.subplots(rows, cols, figsize=(4.6 * cols, 4.0 * rows + 0.9), squeeze=False)
    for ax in axs.flat[n:]:
        ax.axis("off")
    for ax, (m, d) in zip(axs.flat, data.items()):
        if "map" in d:
            mp = d["map"]
            hs, gs = mp["h"], mp["gamma"]
            dh = (hs[1] - hs[0]) / 2 if len(hs) > 1 else 0.5
            dg = (gs[1] - gs[0]) / 2 if len(gs) > 1 else 0.5
            ax.imshow(mp["code"], origin="lower", aspect="auto", cmap=MAP_CMAP, vmin=-0.5,
                      vmax=3.5, interpolation="nearest",
                      extent=(hs[0] - dh, hs[-1] + dh, gs[0] - dg, gs[-1] + dg))
            fb = mp.get("F_formula_boundary")
            if fb:
                pts = [(h, g) for g, h in zip(fb["gamma"], fb["h"]) if h is not None]
                if pts:
                    ax.plot([h for h, _ in pts], [g for _, g in pts], "k-", lw=1.4,
                            label="F closed form (first h where it fails)")
        emp = [(h, g) for g, h in zip(d["gamma"], d["h_F_empirical"]) if h is not None]
        pbu = [(h, g) for g, h in zip(d["gamma"], d["h_power_unbounded"]) if h is not None]
        if emp:
            ax.plot([h for h, _ in emp], [g for _, g in emp], "wo", mec="k", ms=4,
                    label="empirical: first h with |½trM| ≥ e^{−γh}")
        if pbu:
            ax.plot([h for h, _ in pbu], [g for _, g in pbu], "x", color="#08306b", ms=5,
                    label="first h with M not power-bounded")
        ax.set_title(f"{m} (ω = {d['omega']:g})")
        ax.set_xlabel("step size h")
        ax.set_ylabel("damping γ")
    handles, labels = axs.flat[0].get_legend_handles_labels()
    from matplotlib.patches import Patch
    handles += [Patch(color=MAP_CMAP(i), label=t) for i, t in
                enumerate(["F holds, power-bounded", "F fails, power-bounded",
                           "F holds, not power-bounded", "F fails, not power-bounded"])]
    fig.legend(handles=handles, loc="lower center", ncol=3, fontsize=7)
    fig.suptitle(title_of(case, "stability map in (h, γ)"))
    height = 4.0 * rows + 0.9
    layout(fig, bottom=1.2 / height, top=1 - 0.6 / height, left=0.07, hspace=0.4, wspace=0.3)
    return [(save(fig, case, "stability"), "stability map")]


def fig_poincare(case, ser):
    runs = [r for r in ser["runs"] if "poincare" in r["series"]]
    if not runs:
        return []
    ref = next((r["series"]["poincare_reference"] for r in runs
                if "poincare_reference" in r["series"]), None)
    panels = ([("reference (certified GSL)", ref, "0.2")] if ref else []) + [
        (f"{r['method']} h={r['dt']:g}", r["series"]["poincare"], style(r["method"])[0])
        for r in runs]
    cols = min(3, len(panels))
    rows = (len(panels) + cols - 1) // cols
    fig, axs = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.8 * rows + 0.5), squeeze=False,
                            sharex=True, sharey=True)
    for ax in axs.flat[len(panels):]:
        ax.axis("off")
    for ax, (name, pts, c) in zip(axs.flat, panels):
        ax.scatter(pts["q"], pts["p"], s=0.6, color=c, lw=0)
        ax.set_title(name)
        ax.set_xlabel("q mod 2π (rad)")
        ax.set_ylabel("p")
    fig.suptitle(title_of(case, "Poincaré section at t = t0 + kT"))
    height = 3.8 * rows + 0.5
    layout(fig, bottom=0.5 / height, top=1 - 0.6 / height, left=0.08, hspace=0.35, wspace=0.15)
    return [(save(fig, case, "poincare"), "Poincaré sections")]


def plan():
    """[(case index, kind)] of every figure to draw."""
    jobs = []
    for i, c in enumerate(REPORT["cases"]):
        ser = SERIES.get(c["id"])
        mm = c.get("method_metrics", {})
        if len(c["dt_ladder"]) >= 2 and (fd.convergence_data(c) or fd.local_convergence_data(c)):
            jobs.append((i, "convergence"))
        if any("stability-sweep" in v for v in mm.values()):
            jobs.append((i, "stability"))
        if ser:
            if fd.series_panels(ser):
                jobs.append((i, "series"))
            if fd.wants_orbit_figure(c) and any("orbit" in r["series"] for r in ser["runs"]):
                jobs.append((i, "orbit"))
            if any("poincare" in r["series"] for r in ser["runs"]):
                jobs.append((i, "poincare"))
    return jobs


def draw(job):
    i, kind = job
    case = REPORT["cases"][i]
    ser = SERIES.get(case["id"])
    try:
        if kind == "convergence":
            out = fig_convergence(case, ser, fd.case_timing(REPORT, i))
        elif kind == "series":
            out = fig_series(case, ser)
        elif kind == "orbit":
            out = fig_orbit(case, ser)
        elif kind == "stability":
            out = fig_stability(case, ser)
        else:
            out = fig_poincare(case, ser)
        return case["id"], kind, out, None
    except Exception as e:  # one bad figure must not hide the others; reported, exit 1
        plt.close("all")
        return case["id"], kind, [], f"{type(e).__name__}: {e}"


def gallery(manifest):
    """figures.md: every case that names a paper figure or table, with its figures and checks."""
    rows = []
    for c in REPORT["cases"]:
        paper = fd.paper_figure(c)
        if not paper:
            continue
        figs = manifest["cases"].get(c["id"], [])
        checks = c["checks"]
        passed = sum(1 for k in checks if k["passed"])
        verdict = ("no checks" if not checks else
                   "pass" if passed == len(checks) else f"**FAIL** ({len(checks) - passed})")
        names = []
        for k in checks:
            if k["name"] not in names:
                names.append(k["name"])
        held = "; ".join(names[:3]) + (f"; … ({len(names) - 3} more)" if len(names) > 3 else "")
        imgs = " ".join(f'<a href="{f["file"]}"><img src="{f["file"]}" width="220" '
                        f'alt="{f["caption"]}"></a>' for f in figs) or "(no figure: " \
            "the case reduces to numbers, see report.md)"
        claim = c["title"].replace("|", "/")
        rows.append((paper, c["id"], claim, imgs, held.replace("|", "/"), verdict))
    rows.sort()
    out = ["# Paper figures and tables reproduced by dampsym", "",
           "Every case whose source names a figure or table of F (Floyd 2014), B (Bhatt 2016), "
           "HLW (Hairer–Lubich–Wanner ch. I) or BS (Butcher's slides) — docs/references.md. "
           "Drawn by `dampsym plot` (tools/figures/plot.py) from report.json and the run's "
           "series files; the case section in [report.md](report.md) has the full checks.", "",
           "| paper | case | what the paper claims (case title) | dampsym's figure | checks that "
           "hold it | verdict |", "|---|---|---|---|---|---|"]
    for paper, cid, claim, imgs, held, verdict in rows:
        out.append(f"| {paper} | [{cid}](report.md#case-{cid}) | {claim} | {imgs} | {held} | "
                   f"{verdict} |")
    return "\n".join(out) + "\n"


def main():
    global REPORT, SERIES, OUT, FORMATS
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("report_dir")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--format", default="png", help="comma list of png, svg, pdf (png always)")
    ap.add_argument("--filter", default="", help="only cases whose id contains this")
    a = ap.parse_args()
    OUT = a.report_dir
    FORMATS = ["png"] + [f for f in a.format.split(",") if f in ("svg", "pdf")]
    REPORT, SERIES = fd.load(OUT)
    os.makedirs(os.path.join(OUT, "figures"), exist_ok=True)
    for name in os.listdir(os.path.join(OUT, "figures")):
        if name.endswith((".png", ".svg", ".pdf")):
            os.remove(os.path.join(OUT, "figures", name))
    jobs = [j for j in plan() if a.filter in REPORT["cases"][j[0]]["id"]]
    # most expensive first, so that the workers finish together
    cost = {"series": 3, "poincare": 3, "orbit": 2, "stability": 2}
    jobs.sort(key=lambda j: -cost.get(j[1], 1))
    if a.jobs > 1 and len(jobs) > 1:
        with multiprocessing.get_context("fork").Pool(min(a.jobs, len(jobs))) as pool:
            results = pool.map(draw, jobs, chunksize=1)
    else:
        results = [draw(j) for j in jobs]
    order = {"convergence": 0, "series": 2, "orbit": 3, "poincare": 4,
             "stability": 5}
    manifest = {"cases": {}}
    failed = 0
    for cid, kind, out, error in sorted(results, key=lambda r: (r[0], order[r[1]])):
        if error:
            failed += 1
            print(f"plot.py: {cid} {kind}: {error}", file=sys.stderr)
        for f, caption in out:
            manifest["cases"].setdefault(cid, []).append(
                {"file": f, "caption": f"{cid}: {caption}", "kind": kind})
    with open(os.path.join(OUT, "figures", "manifest.json"), "w") as f:
        json.dump(manifest, f, indent=1)
    with open(os.path.join(OUT, "figures.md"), "w") as f:
        f.write(gallery(manifest))
    n = sum(len(v) for v in manifest["cases"].values())
    print(f"plot.py: {n} figures in {os.path.join(OUT, 'figures')}"
          + (f", {failed} failed" if failed else ""))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
