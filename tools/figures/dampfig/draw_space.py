"""Figures in the state space: orbits (equal aspect where both axes are lengths, the same limits
in every panel), the attractor's probe in its plane, Poincaré sections, and PDE snapshots with
their error against the PDE's solution."""

import math
from typing import Any, List, Optional, Tuple

import numpy as np
from matplotlib.lines import Line2D

from . import figdata as fd
from .draw_series import axes_px, coincidence_note, failed_of, unseries_label
from .render import PANEL_H, Ctx, Drawn, Json, dense, label_above_gaps, layout, pow10, save, \
    sci_scale, subplots, title_of
from .styles import REFERENCE_GREY, TRANSIENT_GREY

# axis names of a problem's orbit; problems whose two drawn coordinates are lengths in the same
# unit are drawn with equal aspect (a circle stays a circle: HLW Fig 2.1's precession)
# (Hill's equation has one degree of freedom: its orbit is the phase portrait (q, p))
AXES = {"kepler": ("q₁", "q₂"), "hill": ("q", "p"), "lotka-volterra": ("u", "v"),
        "pendulum": ("q (rad)", "p"), "oscillator": ("q", "p"),
        "outer-solar-system": ("x (AU)", "y (AU)"), "rigid-body": ("z₁", "z₂")}
EQUAL_ASPECT = {"kepler", "outer-solar-system"}
XY = Tuple[Any, Any, str]
# inches at a figure's foot for the line naming the runs that failed (nothing of theirs to draw)
FOOT = 0.25


def orbit_coords(problem: str, states: List[List[float]]) -> List[XY]:
    """[(x, y, label)] to draw for a problem's states (columns of one numpy array)."""
    if not states:
        return []
    col = np.asarray(states, dtype=float).T
    if problem == "outer-solar-system":
        nb = len(col) // 6
        return [(col[3 * k], col[3 * k + 1], f"body {k}") for k in range(nb)]
    return [(col[0], col[1], "")]


def failed_footer(fig: Any, case: Json, failed: List[Json]) -> None:
    """The line at the figure's foot (FOOT) naming the failed runs: a panel per run that ran,
    and without it a run that failed was left out without a word."""
    if failed:
        fig.text(0.01, 0.05 / fig.get_figheight(), "not drawn: " + "; ".join(
            unseries_label(case, r) for r in failed), fontsize=7, va="bottom")


def reference_of(ser: Json, r: Json) -> Optional[Json]:
    ref = r["series"].get("orbit_reference")
    if ref and "same_as_run" in ref:  # written once per case (case_series_json)
        ref = ser["runs"][ref["same_as_run"]]["series"]["orbit_reference"]
    return ref


def shared_limits(curves: List[XY], equal: bool) -> Tuple[Tuple[float, float],
                                                          Tuple[float, float]]:
    """One box around every curve of the figure (a 4 % margin); square when equal."""
    xs = np.concatenate([np.asarray(x, float)[np.isfinite(x)] for x, _, _ in curves])
    ys = np.concatenate([np.asarray(y, float)[np.isfinite(y)] for _, y, _ in curves])
    (x0, x1), (y0, y1) = (float(xs.min()), float(xs.max())), (float(ys.min()), float(ys.max()))
    if equal:
        half = 0.5 * max(x1 - x0, y1 - y0)
        cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
        x0, x1, y0, y1 = cx - half, cx + half, cy - half, cy + half
    px, py = 0.04 * (x1 - x0 or 1.0), 0.04 * (y1 - y0 or 1.0)
    return (x0 - px, x1 + px), (y0 - py, y1 + py)


def yardstick(sizes: List[float], refs: List[List[XY]], equal: bool) -> float:
    """The size an orbit panel's box is judged against: the median size of the reference orbits
    when the runs have any, else the median of the runs' boxes."""
    ref_sizes = sorted(max(x[1] - x[0], y[1] - y[0])
                       for x, y in (shared_limits(b, equal) for b in refs if b))
    pool = ref_sizes or sorted(sizes)
    return pool[len(pool) // 2]


def limits_phrase(own: int, n: int) -> str:
    """What the orbit figure's title says of its panels' limits, `own` of n having their own."""
    if own == 0:
        return "same limits in every panel"
    if own == n:
        return "each panel its own limits (every run far outside the reference orbit)"
    return "same limits in every panel but those marked 'own limits'"


def rays_of(r: Json, curves: List[XY]) -> List[XY]:
    """The ends of the perihelion rays precession_rays draws (half the orbit's size from the
    focus), as a curve for the limits: a ray along the short side of the focus (e = 0.85: the
    perihelion 0.15 from it) was cut to a stub at the panel's edge."""
    p = r.get("metrics", {}).get("precession") or {}
    if p.get("total") is None or p.get("initial_angle") is None or not curves:
        return []
    (x0, x1), (y0, y1) = shared_limits(curves, True)
    reach = 0.5 * max(x1 - x0, y1 - y0)
    angles = [p["initial_angle"], p["initial_angle"] + p["total"]]
    return [(np.array([0.0] + [reach * math.cos(a) for a in angles]),
             np.array([0.0] + [reach * math.sin(a) for a in angles]), "")]


def precession_rays(ax: Any, r: Json, colour: Any, reach: float) -> Optional[str]:
    """HLW Fig 2.1: the perihelion direction at the start (grey, dashed) and at the end (the
    method's colour) from the focus at the origin; returns the turn for the panel's title."""
    p = r.get("metrics", {}).get("precession")
    if not p or p.get("total") is None or p.get("initial_angle") is None:
        return None
    a0, turn = p["initial_angle"], p["total"]
    ax.plot([0, reach * math.cos(a0)], [0, reach * math.sin(a0)], "--", color="k", lw=0.9)
    ax.plot([0, reach * math.cos(a0 + turn)], [0, reach * math.sin(a0 + turn)], "-",
            color=colour, lw=1.6)
    return f"perihelion turned {turn:+.3f} rad"


def fig_orbit(ctx: Ctx, case: Json, ser: Json) -> List[Drawn]:
    runs = [r for r in ser["runs"] if "orbit" in r["series"]]
    if not runs:
        return []
    problem = case["problem"]["id"]
    report_runs = {(r["method"], r["dt"]): r for r in case["runs"]}
    n, cols = len(runs), min(4, len(runs))
    rows = -(-n // cols)
    failed = failed_of(ser, "orbit")
    foot = FOOT if failed else 0.0
    height = 3.5 * rows + 0.9 + foot
    fig, axs = subplots(ctx, rows, cols, (max(7.0, 3.6 * cols), height))
    for ax in axs.flat[n:]:
        ax.axis("off")
    xl, yl = AXES.get(problem, ("z₁", "z₂"))
    equal = problem in EQUAL_ASPECT
    drawn = [(r, orbit_coords(problem, r["series"]["orbit"]["states"]),
              orbit_coords(problem, (reference_of(ser, r) or {}).get("states", []))) for r in runs]
    # one box for every panel, except a run that leaves it by far (explicit Euler's spiral),
    # which gets its own and says so: one outlier must not shrink the others to a dot. The
    # yardstick is the reference orbit where there is one (Kepler at e = 0.99: two of four
    # methods flew off to 1e5 and, as the median, shrank the other two to dots), else the median
    boxes = [shared_limits(a + b + rays_of(report_runs.get((r["method"], r["dt"]), {}), a + b),
                           equal) for r, a, b in drawn]
    sizes = [max(x[1] - x[0], y[1] - y[0]) for x, y in boxes]
    typical = yardstick(sizes, [b for _, _, b in drawn], equal)
    inside = [d for d, s in zip(drawn, sizes) if s <= 3 * typical]
    # (no run inside: each panel has its own box; the shared one is the reference's, unused)
    xlim, ylim = shared_limits([c for r, a, b in inside for c in a + b + rays_of(
        report_runs.get((r["method"], r["dt"]), {}), a + b)]
        or [c for _, a, b in drawn for c in (b or a)], equal)
    greys, turned = set(), False
    for ax, (r, curves, refs), box, size in zip(axs.flat, drawn, boxes, sizes):
        c = ctx.style(r["method"])[0]
        own = size > 3 * typical
        lims = box if own else (xlim, ylim)
        own_x, own_y = shared_limits(curves + refs, True)  # the reach rays_of made room for
        reach = 0.5 * max(own_x[1] - own_x[0], own_y[1] - own_y[0])
        for x, y, _ in refs:
            ax.plot(x, y, "-", color=REFERENCE_GREY, lw=2.2, alpha=0.6, rasterized=dense(len(x)))
        for x, y, _ in curves:
            ax.plot(x, y, "-", color=c, lw=0.6, rasterized=dense(len(x)))
        ax.plot([curves[0][0][0]], [curves[0][1][0]], "k.", ms=6)
        if refs:
            greys.add("exact solution" if (reference_of(ser, r) or {}).get("exact")
                      else "reference")
        turn = precession_rays(ax, report_runs.get((r["method"], r["dt"]), {}), c, reach)
        turned = turned or turn is not None
        ax.set_title(f"{r['method']} h={r['dt']:g}" + (f"\n{turn}" if turn else "") +
                     ("\n(own limits: far outside the shared frame)" if own else ""), fontsize=8)
        ax.set_xlabel(xl)
        ax.set_ylabel(yl)
        ax.set_xlim(*lims[0])
        ax.set_ylim(*lims[1])
        if equal:
            ax.set_aspect("equal", adjustable="box")
    handles = [Line2D([], [], color="k", marker=".", ls="none", ms=6, label="initial state")]
    handles += [Line2D([], [], color=REFERENCE_GREY, lw=2.2, alpha=0.6, label=g) for g in greys]
    if turned:
        handles += [Line2D([], [], color="k", ls="--", lw=0.9, label="perihelion direction at "
                           "t₀ (from the focus)"),
                    Line2D([], [], color="0.3", lw=1.6, label="perihelion direction at t_end")]
    fig.legend(handles=handles, loc="upper center", ncol=len(handles), fontsize=7, frameon=False,
               bbox_to_anchor=(0.5, 1 - 0.35 / height))
    failed_footer(fig, case, failed)
    fig.suptitle(title_of(case, "orbits, " + limits_phrase(sum(s > 3 * typical for s in sizes),
                                                        n) + (", equal aspect" if equal else "")),
                 y=1 - 0.05 / height, va="top")
    layout(fig, bottom=(0.5 + foot) / height, top=1 - 0.95 / height,
           left=0.75 / fig.get_figwidth(), hspace=0.5, wspace=0.35)
    quantities = ["orbit"] + (["orbit_reference"] if greys else []) + \
        (["precession.total", "precession.initial_angle"] if turned else [])
    return [(save(ctx, fig, case, "orbit"), "orbits", quantities)]


def drive_frame(case: Json, t: Any, pts: Any) -> Tuple[Any, str]:
    """The probe's plane points in the frame that turns with the drive F(t) = Γ e^{i(ω₀t + α)}
    (problem parameters omega0, alpha), where a response locked to the drive is a closed curve
    (B Fig 5.10(a)'s periodic attractor; in the lab frame it winds as a rosette). Unchanged, with
    an empty note, for a problem without a drive frequency."""
    params = case.get("problem", {}).get("params", {})
    w = params.get("omega0")
    if not isinstance(w, (int, float)) or w == 0:
        return pts, ""
    phase = -(w * np.asarray(t, float) + float(params.get("alpha", 0.0)))
    z = (pts[:, 0] + 1j * pts[:, 1]) * np.exp(1j * phase)
    return np.stack([z.real, z.imag], axis=1), r"$\cdot e^{-i(\omega_0 t + \alpha)}$"


def statistics_start(case: Json, r: Json, ser: Json) -> float:
    """Where the attractor statistics begin (the run's attractor.from; half the run otherwise):
    before it is the transient."""
    for rr in case["runs"]:
        if rr["method"] == r["method"] and rr["dt"] == r["dt"]:
            v = fd.run_metric(rr, "attractor.from")
            if v is not None:
                return v
    return 0.5 * (ser.get("t0", 0.0) + ser.get("t_end", 0.0))


def portrait_panel(ax: Any, pts: Any, late: Any, colour: Any, thinned: bool,
                   point: float) -> bool:
    """One run's probe: the transient in light grey, the attractor in the method's colour (dots
    where the series is thinned: joins would be chords), the origin; an attractor smaller than
    `point` across (a fixed point of the drive's frame, drawn as a line it was invisible) also
    gets a marker at its mean. Returns whether it did."""
    for mask, col, lw in ((~late, TRANSIENT_GREY, 0.5), (late, colour, 0.7)):
        if mask.any():
            ax.plot(pts[mask, 0], pts[mask, 1], "." if thinned else "-", color=col, lw=lw,
                    ms=1.5, rasterized=dense(int(mask.sum())))
    ax.plot([0.0], [0.0], "k+", ms=6)
    on = pts[late]
    on = on[np.isfinite(on).all(axis=1)]
    if not len(on) or float(np.ptp(on, axis=0).max()) >= point:
        return False
    ax.plot([float(on[:, 0].mean())], [float(on[:, 1].mean())], "o", color=colour, mec="k",
            ms=6)
    return True


def fig_portrait(ctx: Ctx, case: Json, ser: Json) -> List[Drawn]:
    """B Fig 5.10's right panels: the attractor diagnostic's probe as a point of its plane (in
    the drive's frame when the problem has a drive frequency), the transient in light grey (its
    only use), the attractor in the method's colour."""
    runs = [r for r in ser["runs"] if "attractor.plane" in r["series"]]
    if not runs:
        return []
    n, cols = len(runs), min(3, len(runs))
    rows = -(-n // cols)
    failed = failed_of(ser, "attractor.plane")
    foot = FOOT if failed else 0.0
    height = 3.7 * rows + 1.0 + foot
    fig, axs = subplots(ctx, rows, cols, (max(7.0, 3.8 * cols), height), sharex=True,
                        sharey=True)
    for ax in axs.flat[n:]:
        ax.axis("off")
    frame = ""
    data = []
    for r in runs:
        pl = r["series"]["attractor.plane"]
        t = np.asarray(pl["t"], dtype=float)
        pts, frame = drive_frame(case, t, np.asarray(pl["points"], dtype=float).reshape(-1, 2))
        data.append((r, pl, pts, t >= statistics_start(case, r, ser)))
    # one square box for every panel (equal aspect: a box as wide as the data and as tall as
    # its width left a 1.2 x 0.5 portrait 125 px tall in a 3.7 in row)
    (x0, x1), (y0, y1) = shared_limits([(p[:, 0], p[:, 1], "") for _, _, p, _ in data], True)
    fixed = False
    for ax, (r, pl, pts, late) in zip(axs.flat, data):
        fixed = portrait_panel(ax, pts, late, ctx.style(r["method"])[0],
                               pl.get("stride", 1) > 1, 0.01 * (x1 - x0)) or fixed
        ax.set_title(f"{r['method']} h={r['dt']:g}")
        # "Re psi(0, t)" in the drive's frame: Re[psi(0, t) e^{-i(w0 t + a)}]
        names = [f"{x.split(' ', 1)[0]}[{x.split(' ', 1)[-1]}{frame}]" if frame else x
                 for x in pl["names"]]
        ax.set_xlabel(names[0].replace("psi", r"$\psi$"))
        ax.set_ylabel(names[1].replace("psi", r"$\psi$"))
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
        ax.set_aspect("equal", adjustable="box")
    label_above_gaps(axs, n, axs.flat[0].get_xlabel())
    handles = [Line2D([], [], color=TRANSIENT_GREY, lw=1.5, label="transient (before the "
                      "attractor statistics)"),
               Line2D([], [], color="0.2", lw=1.5, label="on the attractor (the method's colour)"),
               Line2D([], [], color="k", marker="+", ls="none", label="origin")]
    if fixed:
        handles.append(Line2D([], [], color="0.2", marker="o", mec="k", ls="none", ms=6,
                              label="attractor a fixed point (its mean)"))
    fig.legend(handles=handles, loc="upper center", ncol=len(handles), fontsize=7, frameon=False,
               bbox_to_anchor=(0.5, 1 - 0.35 / height))
    fig.suptitle(title_of(case, "the probe in its plane" +
                          (", in the frame turning with the drive" if frame else "")),
                 y=1 - 0.05 / height, va="top")
    failed_footer(fig, case, failed)
    layout(fig, bottom=(0.6 + foot) / height, top=1 - 0.95 / height, left=0.75 / fig.get_figwidth(),
           hspace=0.45, wspace=0.3)
    return [(save(ctx, fig, case, "portrait"), "probe portrait",
             ["attractor.plane", "attractor.from"])]


def fig_poincare(ctx: Ctx, case: Json, ser: Json) -> List[Drawn]:
    """Poincaré sections, one panel per run, each over the reference's section (grey)."""
    runs = [r for r in ser["runs"] if "poincare" in r["series"]]
    if not runs:
        return []
    ref = next((r["series"]["poincare_reference"] for r in runs
                if "poincare_reference" in r["series"]), None)
    n = len(runs)
    cols = n if n <= 3 else (2 if n == 4 else 3)
    rows = -(-n // cols)
    failed = failed_of(ser, "poincare")
    foot = FOOT if failed else 0.0
    height = 3.9 * rows + 1.0 + foot
    fig, axs = subplots(ctx, rows, cols, (4.3 * cols, height), sharex=True, sharey=True)
    for ax in axs.flat[n:]:
        ax.axis("off")
    for ax, r in zip(axs.flat, runs):
        if ref:
            ax.scatter(ref["q"], ref["p"], s=9, color=REFERENCE_GREY, lw=0, alpha=0.55,
                       rasterized=True)
        pts = r["series"]["poincare"]
        ax.scatter(pts["q"], pts["p"], s=5, color=ctx.style(r["method"])[0], lw=0,
                   rasterized=True)
        ax.set_title(f"{r['method']} h={r['dt']:g} ({len(pts['q'])} points)")
        ax.set_xlabel("q mod 2π (rad)")
        ax.set_ylabel("p")
    label_above_gaps(axs, n, "q mod 2π (rad)")
    handles = [Line2D([], [], color="0.3", marker="o", ls="none", ms=3,
                      label="the method's section (its colour)")]
    if ref:
        handles.append(Line2D([], [], color=REFERENCE_GREY, marker="o", ls="none", ms=4,
                              alpha=0.55, label="reference section (certified GSL)"))
    fig.legend(handles=handles, loc="upper center", ncol=2, fontsize=7, frameon=False,
               bbox_to_anchor=(0.5, 1 - 0.35 / height))
    fig.suptitle(title_of(case, "Poincaré section at t = t₀ + kT"), y=1 - 0.05 / height,
                 va="top")
    failed_footer(fig, case, failed)
    layout(fig, bottom=(0.55 + foot) / height, top=1 - 0.95 / height, left=0.08, hspace=0.4,
           wspace=0.15)
    return [(save(ctx, fig, case, "poincare"), "Poincaré sections",
             ["poincare"] + (["poincare_reference"] if ref else []))]


def snapshot_errors(runs: List[Json], k: int, n_x: int) -> List[Tuple[str, List[float]]]:
    """Per run, u(x, t_k) − u_PDE(x, t_k) at the snapshot k."""
    out = []
    for r in runs:
        sn = r["series"]["snapshots"]
        if k < len(sn["u"]) and k < len(sn["pde"]):
            out.append((r["method"], [a - b for a, b in zip(sn["u"][k], sn["pde"][k])][:n_x]))
    return out


def snapshot_legend(ctx: Ctx, case: Json, fig: Any, runs: List[Json], y: float) -> None:
    """The legend of a group's rows (centred at figure height y): the PDE's solution and each
    run with its pde-error.max_abs."""
    handles = [Line2D([], [], color=REFERENCE_GREY, lw=3.0, alpha=0.7,
                      label="solution of the PDE")]
    for r in runs:
        v = fd.run_metric(next((rr for rr in case["runs"] if rr["method"] == r["method"]
                                and rr["dt"] == r["dt"]), {}), "pde-error.max_abs")
        c, _, ls = ctx.style(r["method"])
        handles.append(Line2D([], [], color=c, ls="--" if ls == ":" else ls, lw=1.2,
                              label=r["method"] + (f" (max $|u - u_{{PDE}}|$ = {v:.2g})"
                                                  if v is not None else "")))
    fig.legend(handles=handles, loc="lower center", ncol=min(4, len(handles)), frameon=False,
               fontsize=7.5, bbox_to_anchor=(0.5, y))


def snapshot_rows(ctx: Ctx, top: Any, bottom: Any, runs: List[Json], k: int,
                  emax: float, scale: int) -> float:
    """The field of each run over the PDE's solution at snapshot k (top) and u − u_PDE (bottom,
    one scale for the row); returns the pixels of the bottom panel's note on coinciding lines."""
    first = runs[0]["series"]["snapshots"]
    x = first["x"] or list(range(len(first["pde"][k])))
    top.plot(x, first["pde"][k], "-", color=REFERENCE_GREY, lw=3.0, alpha=0.7)
    for r in runs:
        sn = r["series"]["snapshots"]
        c, _, ls = ctx.style(r["method"])
        if k < len(sn["u"]):
            top.plot(x, sn["u"][k], "--" if ls == ":" else ls, color=c, lw=1.0)
    drawn = []
    for m, e in snapshot_errors(runs, k, len(x)):
        c, _, ls = ctx.style(m)
        y = [v / 10.0 ** scale for v in e]
        bottom.plot(x[:len(e)], y, ls, color=c, lw=1.0)
        drawn.append((m, list(x[:len(e)]), y))
    bottom.axhline(0.0, color="k", lw=0.5)
    top.set_title(f"t = {first['t'][k]:g}")
    return coincidence_note(bottom, drawn, False, factor=10.0 ** scale)


def fig_snapshots(ctx: Ctx, case: Json, ser: Json) -> List[Drawn]:
    """B Fig 5.4: per group of at most six runs, a row of the field u(x) of each run over the
    PDE's own solution (grey) at the output times and under it u − u_PDE, the error the case
    checks (pde-error.max_abs), which the top row cannot show (the lines coincide at its
    scale)."""
    runs = [r for r in ser["runs"] if r["series"].get("snapshots", {}).get("t")]
    if not runs:
        return []
    first = runs[0]["series"]["snapshots"]
    times = first["t"]
    n = min(len(times), 5)  # at most 5 times: the first, the last and 3 between
    pick = sorted({round(i * (len(times) - 1) / max(1, n - 1)) for i in range(n)})
    groups = [[r for r in runs if r["method"] in g]
              for g in fd.groups(list(dict.fromkeys(r["method"] for r in runs)))]
    # between two groups: the x label, the next group's legend and titles (1.1 in)
    gap = 0.25 if len(groups) == 1 else 1.1
    height = 2 * len(groups) * PANEL_H + (2 * len(groups) - 1) * gap + 1.6
    fig, axs = subplots(ctx, 2 * len(groups), len(pick), (3.0 * len(pick) + 0.8, height),
                        sharex=True)
    layout(fig, bottom=0.5 / height, top=1 - 1.1 / height, left=0.95 / fig.get_figwidth(),
           hspace=gap / PANEL_H, wspace=0.25)
    errs = [e for k in pick for _, e in snapshot_errors(runs, k, len(first["pde"][k]))]
    scale = sci_scale(errs)
    # one error scale in every panel: how the error grows with t is seen at a glance
    emax = max((abs(v) for e in errs for v in e), default=1.0) / 10.0 ** scale or 1.0
    bands = [max(snapshot_rows(ctx, axs[2 * g, j], axs[2 * g + 1, j], gruns, k, emax, scale)
                 for j, k in enumerate(pick)) for g, gruns in enumerate(groups)]
    # the same limits in every error row (the bands of the notes kept free in each)
    lim = fd.band_limits(-emax, emax, max(bands) / axes_px(axs[1, 0])[1], 0.0, False)
    for g, gruns in enumerate(groups):
        for j in range(len(pick)):
            axs[2 * g + 1, j].set_ylim(*lim)
            axs[2 * g + 1, j].set_xlabel("x")
            axs[2 * g + 1, j].xaxis.set_tick_params(labelbottom=True)
            axs[2 * g + 1, j]._dampsym_relabelled = True  # hidden again by render.recycle
        axs[2 * g, 0].set_ylabel("u(x, t)")
        axs[2 * g + 1, 0].set_ylabel(r"$u - u_{PDE}$" + (f"  [×{pow10(scale)}]" if scale else ""))
        snapshot_legend(ctx, case, fig, gruns, axs[2 * g, 0].get_position().y1 + 0.3 / height)
    fig.suptitle(title_of(case, "snapshots (top) and their error against the PDE's solution "
                          "(bottom)"), y=1 - 0.05 / height, va="top")
    return [(save(ctx, fig, case, "snapshots"), "snapshots and their error",
             ["snapshots", "pde-error.max_abs"])]
