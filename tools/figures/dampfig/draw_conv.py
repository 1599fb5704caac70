"""Figures against the step size: convergence (the claim's metric, the final error with the
report's order fit, the local error), the claim's ratio of two methods, work-precision, F Fig
3.4's half-trace error, and F Figs 3.1-3.3's stability maps."""

import textwrap
from typing import Any, Dict, List, Tuple

from matplotlib.lines import Line2D
from matplotlib.patches import Patch
from matplotlib.transforms import offset_copy

from . import figdata as fd
from .draw_series import coincidence_text
from .render import Ctx, Drawn, Json, label_above_gaps, layout, save, subplots, title_of
from .styles import REFERENCE_GREY


def conv_axis(ctx: Ctx, ax: Any, data: Dict[str, Json], ylabel: str, fit_label: str) -> List[str]:
    """Points per method (hollow: dropped from the report's fit), the fitted line over its window
    and the slope in the legend; returns notes on the dropped points."""
    notes: List[str] = []
    for m, d in data.items():
        c, mk, ls = ctx.style(m)
        pts = d["points"]
        dropped = {h for h, _ in d.get("dropped", [])}
        ax.plot([h for h, _ in pts], [e for _, e in pts], color=c, ls=ls, lw=0.8, alpha=0.6)
        kept = [(h, e) for h, e in pts if h not in dropped]
        gone = [(h, e) for h, e in pts if h in dropped]
        label = f"{m}, slope {d['fit']['slope']:.3f}" if "fit" in d else m
        if "line_h" in d.get("fit", {}):  # a fit whose line leaves the doubles: its slope only
            ax.plot(d["fit"]["line_h"], d["fit"]["line_error"], color=c, ls="-", lw=2.4,
                    alpha=0.35)
        ax.plot([h for h, _ in kept], [e for _, e in kept], mk, color=c, label=label, ms=5)
        if gone:
            ax.plot([h for h, _ in gone], [e for _, e in gone], mk, mfc="none", mec=c, ms=6)
            notes += [f"{m} h={h:g}: {why}" for h, why in d["dropped"]]
    ax.set_xscale("log")
    ax.set_yscale("log")
    ctx.xticks[id(ax)] = sorted({h for d in data.values() for h, _ in d["points"]})
    ax.set_xlabel("step size h")
    ax.set_ylabel(ylabel)
    same = coincidence_text([(m, [h for h, _ in d["points"]], [e for _, e in d["points"]])
                             for m, d in data.items()], True)
    handles, labels = ax.get_legend_handles_labels()
    if same:  # in the legend, where it cannot be hidden under it
        handles.append(Line2D([], [], ls="none"))
        labels.append(textwrap.fill(same, 34))
    if notes:
        handles.append(Line2D([], [], marker="o", mfc="none", mec="k", ls="none"))
        labels.append("hollow: dropped from the fit")
    if any("fit" in d for d in data.values()):  # explained only where a fitted line is drawn
        handles.append(Line2D([], [], color="k", ls="-", lw=2.4, alpha=0.35))
        labels.append(fit_label)
    under_axes(ax, handles, labels)
    return notes


# a legend under its panel (never over the data): rows of entries, pixels from the axes' bottom
LEGEND_BELOW_PX, LEGEND_ROW_PX = 46.0, 12.5


def under_axes(ax: Any, handles: List[Any], labels: List[str]) -> None:
    """The panel's legend in two columns under its x label, out of the data's way."""
    ax.legend(handles, labels, loc="upper center", ncol=2, fontsize=6.5, frameon=False,
              bbox_to_anchor=(0.5, 0.0), borderaxespad=0.0, columnspacing=1.0,
              bbox_transform=offset_copy(ax.transAxes, ax.get_figure(), y=-LEGEND_BELOW_PX,
                                         units="dots"))


def legend_px(ax: Any) -> float:
    """The height (pixels) of the legend under_axes placed, from its labels' lines."""
    lg = ax.get_legend()
    if lg is None:
        return 0.0
    lines = [t.get_text().count("\n") + 1 for t in lg.get_texts()]
    half = -(-len(lines) // 2)
    return LEGEND_ROW_PX * max(sum(lines[:half]), sum(lines[half:])) + 6


def measure_label(case: Json, metric: str) -> str:
    """Axis label of a run metric: a measure as its definition (component, norm, reduction)."""
    if metric.startswith("measure."):
        spec = case.get("measures", {}).get(metric[len("measure."):], {})
        comp = spec.get("component", "state")
        sym = "z" if comp == "state" else comp.replace("[", "_{").replace("]", "}")
        core = f"|{sym}_n - {sym}(t_n)|"
        if spec.get("norm") == "rel":
            core += f"/|{sym}(t_n)|"
        over = {"mean": "mean over $t_n$ of ", "max": "max over $t_n$ of ",
                "rms": "rms over $t_n$ of ",
                "final": "at t_end: "}.get(spec.get("over", ""), "")
        return f"{over}${core}$ ({metric})"
    return metric


def ratio_axis(ctx: Ctx, ax: Any, r: Json) -> None:
    """The claim's ratio of two methods against h with the checks' bounds (B Fig 3.1: ETD/IF)."""
    ax.plot([h for h, _ in r["points"]], [v for _, v in r["points"]], "o-", color="k", ms=4,
            lw=1, label=f"{r['label']} of {r['metric']}")
    for i, (h, bound, op) in enumerate(r["bounds"]):
        ax.plot([h], [bound], "v" if op in ("le", "lt") else "^", color=REFERENCE_GREY, ms=6,
                ls="none", label="bound of the check at this h" if i == 0 else None)
    ax.axhline(1.0, color=REFERENCE_GREY, lw=0.8, ls=":", label="ratio 1 (equal)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ctx.xticks[id(ax)] = [h for h, _ in r["points"]]
    ax.set_xlabel("step size h")
    ax.set_ylabel(f"ratio {r['label']}")
    ax.set_title("the claim: ratio of the two methods")
    under_axes(ax, *ax.get_legend_handles_labels())


def wp_axes(ctx: Ctx, axs: List[Any], data: Dict[str, List[Json]]) -> None:
    for m, pts in data.items():
        c, mk, ls = ctx.style(m)
        pts = sorted(pts, key=lambda p: p["dt"])
        for ax, key in zip(axs, ("seconds", "rhs_evals")):
            ax.plot([p[key] for p in pts], [p["error"] for p in pts], marker=mk, ls=ls,
                    color=c, label=m, ms=4, lw=1)
    for ax, xl in zip(axs, ["bare-loop wall time (s, min of N repetitions)",
                            "right-hand-side evaluations"]):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(xl)
        ax.set_ylabel(r"final error $\|z_N - z(t_{end})\|$")
        ax.set_title("work-precision")
    under_axes(axs[1], *axs[1].get_legend_handles_labels())


def convergence_panels(case: Json) -> Tuple[List[Tuple[Dict[str, Json], str, str, str]],
                                             List[str]]:
    """The step-size panels of a case and the quantities they draw: the claim's metric (when a
    check reads one other than the final error), the final error when the report fits an order
    to it (or nothing else is drawn), the local error."""
    panels, quantities = [], []
    claim = fd.claim_ladder_metric(case)
    if claim and not claim.startswith(("order", "local-order", "local-error")):
        panels.append((fd.metric_ladder_data(case, claim), measure_label(case, claim),
                       "least-squares slope over all h", "the claim's measure against h"))
        quantities.append(claim)
    glob = fd.convergence_data(case)
    fitted = any("fit" in d for d in glob.values())
    if glob and (fitted or not panels):
        panels.append((glob, r"global error $\|z_N - z(t_{end})\|$", "fitted order (window)",
                       "convergence (final error)"))
        quantities += ["error.final_abs", "order.slope"]
    loc = fd.local_convergence_data(case)
    if loc:
        panels.append((loc, "local error (one step)", "fitted local order (window)",
                       "local error"))
        quantities += ["local-error.abs", "local-order.slope"]
    return panels, quantities


def by_group(data: Dict[str, Any], group: List[str]) -> Dict[str, Any]:
    return {m: d for m, d in data.items() if m in group}


def grid_of(top: int, wp: bool, groups: int) -> Tuple[int, int, bool]:
    """(rows, cols, one row per group): the step-size panels and the two work-precision panels
    of a group side by side when they fit in four columns, else work-precision in rows under."""
    if not wp:
        return groups, top, True
    if top + 2 <= 4:
        return groups, top + 2, True
    return 2 * groups, max(top, 2), False


def fig_convergence(ctx: Ctx, case: Json, timing: Any) -> List[Drawn]:
    """The step-size panels (the claim's ratio beside them) and work-precision when the ladder
    was timed; a case of more than six methods in one row of each per group of six."""
    panels, quantities = convergence_panels(case)
    ratio = fd.ratio_check_data(case)
    wp = fd.work_precision_data(case, timing)
    groups = fd.groups([m for m in ctx.styles] or list(wp))
    top = len(panels) + (1 if ratio else 0)
    rows, cols, same_row = grid_of(top, bool(wp), len(groups))
    fig, axs = subplots(ctx, rows, cols, (4.6 * cols, 3.9 * rows + 1.0))
    for ax in axs.flat:
        ax.axis("off")
    notes: List[str] = [f"{r['method']} h={r['dt']:g}: {r.get('status')} (not drawn)"
                        for r in case["runs"] if r.get("status", "ok") != "ok"]
    for g, group in enumerate(groups):
        row = axs[g]
        for ax, (data, ylabel, fit_label, title) in zip(row, panels):
            ax.axis("on")
            notes += conv_axis(ctx, ax, by_group(data, group), ylabel, fit_label)
            ax.set_title(title)
        if ratio and g == 0:
            row[len(panels)].axis("on")
            ratio_axis(ctx, row[len(panels)], ratio)
        if wp:
            wax = list(row[top:top + 2]) if same_row else list(axs[len(groups) + g][:2])
            for ax in wax:
                ax.axis("on")
            wp_axes(ctx, wax, by_group(wp, group))
    if wp:
        quantities += ["timing.wall_seconds_min", "rhs_evals"]
    # the legends under the panels: the gap between rows holds the x label, the tallest legend
    # and the next row's title; each panel 2.9 in (290 px) tall
    under = (LEGEND_BELOW_PX + max(legend_px(ax) for ax in axs.flat)) / 100.0
    gap, panel_h = under + 0.45, 2.9
    bottom = under + (0.45 if notes else 0.15)
    height = 0.75 + bottom + rows * panel_h + (rows - 1) * gap
    fig.set_size_inches(4.6 * cols, height)
    fig.suptitle(title_of(case, "error against the step size" +
                          (" and work-precision" if wp else "")), y=1 - 0.1 / height, va="top")
    if notes:
        text = "; ".join(notes)
        fig.text(0.01, 0.01, "dropped: " + (text[:297] + "…" if len(text) > 300 else text),
                 fontsize=6, wrap=True)
    layout(fig, bottom=bottom / height, top=1 - 0.75 / height,
           left=0.55 / (4.6 * cols) + 0.03, hspace=gap / panel_h, wspace=0.32)
    return [(save(ctx, fig, case, "convergence"), "convergence" +
             (" and work-precision" if wp else ""), quantities)]


def trace_axis(ctx: Ctx, ax: Any, data: Dict[str, Json]) -> None:
    """One panel of F Fig 3.4: the measured half-trace errors and the fitted c h⁴ lines of at
    most six methods, the legend under the panel."""
    for m, d in data.items():
        c, mk, _ = ctx.style(m)
        hs, es = [h for h, _ in d["points"]], [e for _, e in d["points"]]
        ax.plot(hs, es, mk, color=c, ms=4, ls="none")
        exp = f", expected {d['c_expected']:.4g}" if d["c_expected"] is not None else ""
        label = f"{m}: $c\\,h^4$, c = {d['c']:.4g}{exp}" if d["c"] else f"{m} (no fit)"
        if d["c"]:
            ax.plot(hs, [d["c"] * h ** 4 for h in hs], "-", color=c, lw=1)
        ax.plot([], [], ls="-" if d["c"] else "none", marker=mk, color=c, ms=4, lw=1,
                label=label)
    ax.plot([], [], "o", color="k", ms=4, ls="none", label=r"marks: measured $|\frac{1}{2}"
            r"\mathrm{tr}M(h) - e^{-\gamma h}\cos\beta h|$; lines: fitted $c\,h^4$")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("step size h")
    ax.set_ylabel(r"half-trace error $|\frac{1}{2}\mathrm{tr}M - e^{-\gamma h}\cos\beta h|$")
    handles, labels = ax.get_legend_handles_labels()
    ax.legend(handles, labels, loc="upper center", ncol=1, fontsize=7, frameon=False,
              bbox_to_anchor=(0.5, 0.0), borderaxespad=0.0,
              bbox_transform=offset_copy(ax.transAxes, ax.get_figure(), y=-LEGEND_BELOW_PX,
                                         units="dots"))


def fig_trace(ctx: Ctx, case: Json, ser: Any) -> List[Drawn]:
    """F Fig 3.4: the half-trace error |½trM(h) − e^{−γh}cos βh| against h per method, with the
    report's fitted c h⁴ line (trace-taylor.h4_coeff) and the expected coefficient; a panel per
    group of six methods, the legend under it."""
    data = fd.half_trace_data(case, ser)
    if not data:
        return []
    groups = fd.groups([m for m in ctx.styles if m in data] or list(data))
    # rows of mathtext labels: 19 px each
    under = (LEGEND_BELOW_PX + 19.0 * (max(len(g) for g in groups) + 1) + 8) / 100
    width, height = 6.4 * len(groups) + 0.6, 0.8 + 3.4 + under + 0.1
    fig, axs = subplots(ctx, 1, len(groups), (width, height), sharey=True)
    for ax, g in zip(axs[0], groups):
        trace_axis(ctx, ax, by_group(data, g))
    d0 = next(iter(data.values()))
    fig.suptitle(title_of(case, "half-trace error against h") +
                 f"\non the case's oscillator: ω = {d0['omega']:g}, γ = {d0['gamma']:g}",
                 y=1 - 0.05 / height, va="top")
    layout(fig, bottom=(under + 0.1) / height, top=1 - 0.8 / height, left=1.0 / width,
           wspace=0.12)
    return [(save(ctx, fig, case, "trace"), "half-trace error against h",
             ["trace-taylor.h4_coeff", "trace-taylor.h4_coeff_expected",
              "stability_map.half_trace_error"])]


# codes of the stability map (figures/series.hpp stability_map_series) and the equality cells
MAP_COLOURS = ["#cfe8cf", "#f6d7a7", "#a6cee3", "#e66f5c"]
MAP_NAMES = ["F's condition holds, M power-bounded", "F fails, M power-bounded",
             "F holds, M not power-bounded", "F fails, M not power-bounded"]
EQUAL_COLOUR = "#ffffff"


def map_image(ax: Any, mp: Json) -> None:
    """The (h, γ) map as an image of its codes; cells where |½trM| = e^{−γh} to round-off (the
    boundary of F's strict inequality itself, e.g. cimp at γ = ω) white and hatched: which side
    round-off puts them on is not a property of the method."""
    from matplotlib.colors import ListedColormap
    hs, gs = mp["h"], mp["gamma"]
    dh = (hs[1] - hs[0]) / 2 if len(hs) > 1 else 0.5
    dg = (gs[1] - gs[0]) / 2 if len(gs) > 1 else 0.5
    codes = [list(row) for row in mp["code"]]
    eq = mp.get("F_equal")
    if eq:
        codes = [[4 if e else c for c, e in zip(row, erow)] for row, erow in zip(codes, eq)]
    ax.imshow(codes, origin="lower", aspect="auto", cmap=ListedColormap(MAP_COLOURS +
              [EQUAL_COLOUR]), vmin=-0.5, vmax=4.5, interpolation="nearest",
              extent=(hs[0] - dh, hs[-1] + dh, gs[0] - dg, gs[-1] + dg))
    if eq:
        for j, g in enumerate(gs):
            cells = [hs[i] for i, e in enumerate(eq[j]) if e]
            if cells:
                ax.plot(cells, [g] * len(cells), "|", color="0.35", ms=4, mew=0.6)
    fb = mp.get("F_formula_boundary")
    pts = [(h, g) for g, h in zip(fb["gamma"], fb["h"]) if h is not None] if fb else []
    if pts:
        ax.plot([h for h, _ in pts], [g for _, g in pts], "k-", lw=1.4)


def map_legend() -> List[Any]:
    """Every patch, line and marker of the maps, explained."""
    handles: List[Any] = [Patch(facecolor=c, edgecolor="0.5", label=t)
                          for c, t in zip(MAP_COLOURS, MAP_NAMES)]
    handles.append(Line2D([], [], color="0.35", marker="|", ls="none", ms=6,
                          label=r"$|\frac{1}{2}\mathrm{tr}M| = e^{-\gamma h}$ to round-off "
                                "(F's boundary itself)"))
    handles.append(Line2D([], [], color="k", lw=1.4,
                          label="F's closed form: first h where the condition fails"))
    handles.append(Line2D([], [], marker="o", mfc="w", mec="k", ls="none", ms=5,
                          label=r"measured: first h with $|\frac{1}{2}\mathrm{tr}M| \geq "
                                r"e^{-\gamma h}$ (report rows)"))
    handles.append(Line2D([], [], marker="x", color="k", ls="none", ms=5,
                          label="measured: first h where M is not power-bounded"))
    return handles


def fig_stability(ctx: Ctx, case: Json, ser: Any) -> List[Drawn]:
    """F Figs 3.1-3.3: per method the (h, γ) map of F's condition and power-boundedness, F's
    closed-form boundary and the report's measured boundaries."""
    data = fd.stability_data(case, ser)
    if not data:
        return []
    n = len(data)
    cols = n if n <= 3 else (2 if n == 4 else 3)
    rows = -(-n // cols)
    height = 3.3 * rows + 1.9
    fig, axs = subplots(ctx, rows, cols, (max(7.5, 3.9 * cols), height), sharex=True,
                        sharey=True)
    for ax in axs.flat[n:]:
        ax.axis("off")
    for ax, (m, d) in zip(axs.flat, data.items()):
        if "map" in d:
            map_image(ax, d["map"])
        emp = [(h, g) for g, h in zip(d["gamma"], d["h_F_empirical"]) if h is not None]
        pbu = [(h, g) for g, h in zip(d["gamma"], d["h_power_unbounded"]) if h is not None]
        ax.plot([h for h, _ in emp], [g for _, g in emp], "o", mfc="w", mec="k", ms=5)
        ax.plot([h for h, _ in pbu], [g for _, g in pbu], "x", color="k", ms=5)
        ax.set_title(f"{m} (ω = {d['omega']:g})")
        ax.set_xlabel("step size h")
        ax.set_ylabel("damping γ")
        ax.grid(False)
    label_above_gaps(axs, n, "step size h")
    fig.legend(handles=map_legend(), loc="lower center", ncol=2, fontsize=7, frameon=False)
    fig.suptitle(title_of(case, r"where F's condition $|\frac{1}{2}\mathrm{tr}M| < e^{-\gamma h}$"
                          " holds, and where M is power-bounded"), fontsize=9,
                 y=1 - 0.08 / height, va="top")
    layout(fig, bottom=1.45 / height, top=1 - 0.8 / height, left=0.6 / max(7.5, 3.9 * cols),
           hspace=0.35, wspace=0.12)
    return [(save(ctx, fig, case, "stability"), "stability map",
             ["stability-sweep.rows", "stability-sweep.F_violations",
              "stability-sweep.mismatch_points", "stability_map"])]


