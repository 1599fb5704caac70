"""Readability of the state-space figures and the labels on held-out cases: x tick labels on the
panels above an empty slot, Hill's phase portrait named (q, p), the perihelion rays inside the
panel, snapshots of at most six methods a panel, invariants and the probe in mathtext."""

import math
from typing import Any, Dict, List

import pytest

from dampfig import draw_space, render
from dampfig import figdata as fd
from dampfig.render import Ctx

from test_readable_layout import covered, drawn_figures, outside

Json = Dict[str, Any]


def ctx_for(case: Json, tmp_path: Any) -> Ctx:
    ctx = Ctx(report={"cases": [case]}, out=str(tmp_path), formats=["png"])
    ctx.styles = fd.case_styles(list(dict.fromkeys(r["method"] for r in case["runs"])))
    return ctx


def base_case(methods: List[str], problem: str) -> Json:
    return {"id": "held-out", "title": "", "source": "", "checks": [], "dt_ladder": [0.1],
            "runs": [{"method": m, "dt": 0.1, "status": "ok", "metrics": {}} for m in methods],
            "problem": {"id": problem, "params": {}}}


def test_poincare_columns_above_an_empty_slot_keep_their_x_labels(
        monkeypatch: pytest.MonkeyPatch, tmp_path: Any) -> None:
    seen = drawn_figures(monkeypatch, draw_space)
    methods = [f"m{k}" for k in range(7)]  # 3 columns: the last row holds one panel
    case = base_case(methods, "driven-pendulum")
    sec = {"q": [0.1 * k for k in range(30)], "p": [math.sin(k) for k in range(30)]}
    ser = {"runs": [{"method": m, "dt": 0.1, "series": {"poincare": sec}} for m in methods]}
    draw_space.fig_poincare(ctx_for(case, tmp_path), case, ser)
    fig = seen[0]
    for i in (4, 5):  # above the two empty slots
        ax = fig.axes[i]
        labels = [t.label1 for t in ax.xaxis.get_major_ticks()]
        assert any(lb.get_visible() and lb.get_text() for lb in labels), i
    assert not fig.axes[1].xaxis.get_major_ticks()[0].label1.get_visible()  # sharex elsewhere


def test_hill_orbit_is_a_phase_portrait() -> None:
    assert draw_space.AXES["hill"] == ("q", "p") and "hill" not in draw_space.EQUAL_ASPECT


def test_orbits_that_stay_share_the_reference_frame(monkeypatch: pytest.MonkeyPatch,
                                                   tmp_path: Any) -> None:
    # Kepler at e = 0.99 on a held-out ladder: two of four methods fly off to 1e5. Judged
    # against the median box, the two that stay were shrunk to dots in a 1e5 frame; judged
    # against the reference orbit they share its frame and the others get their own.
    seen = drawn_figures(monkeypatch, draw_space)
    methods = ["m0", "m1", "m2", "m3"]
    case = base_case(methods, "kepler")
    th = [2 * math.pi * k / 200 for k in range(201)]
    ring = [[math.cos(a), math.sin(a), 0.0, 0.0] for a in th]
    away = [[1e5 * k / 200 + math.cos(a), math.sin(a), 0.0, 0.0] for k, a in enumerate(th)]
    ref = {"states": ring}
    ser = {"runs": [{"method": m, "dt": 0.1, "series": {
        "orbit": {"states": away if m in ("m0", "m3") else ring}, "orbit_reference": ref}}
        for m in methods]}
    draw_space.fig_orbit(ctx_for(case, tmp_path), case, ser)
    axes = seen[0].axes
    widths = [ax.get_xlim()[1] - ax.get_xlim()[0] for ax in axes[:4]]
    assert widths[1] == widths[2] < 3  # the two that stay: the reference's frame
    assert widths[0] > 1e4 and widths[3] > 1e4  # the two that left: their own
    assert "own limits" in axes[0].get_title() and "own limits" not in axes[1].get_title()
    assert "but those marked" in seen[0]._suptitle.get_text()
    # control: the median of the four boxes is a flown-off one, and every box is within 3x of it
    boxes = [2.0, 2.0, 1e5, 1e5]
    median = sorted(boxes)[len(boxes) // 2]
    assert all(b <= 3 * median for b in boxes)
    assert draw_space.yardstick(boxes, [], True) == median
    assert draw_space.limits_phrase(4, 4).startswith("each panel its own limits")


def test_perihelion_rays_stay_inside_the_panel(monkeypatch: pytest.MonkeyPatch,
                                               tmp_path: Any) -> None:
    seen = drawn_figures(monkeypatch, draw_space)
    case = base_case(["m0"], "kepler")
    e = 0.85  # the focus 0.15 from the perihelion: the t0 ray along +x
    th = [2 * math.pi * k / 400 for k in range(401)]
    r = [(1 - e * e) / (1 + e * math.cos(a)) for a in th]
    states = [[ri * math.cos(a), ri * math.sin(a), 0.0, 0.0] for ri, a in zip(r, th)]
    case["runs"][0]["metrics"] = {"precession": {"total": 0.4, "initial_angle": 0.0}}
    ser = {"runs": [{"method": "m0", "dt": 0.1, "series": {"orbit": {"states": states}}}]}
    draw_space.fig_orbit(ctx_for(case, tmp_path), case, ser)
    ax = seen[0].axes[0]
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    for ln in ax.lines:
        xs, ys = list(ln.get_xdata()), list(ln.get_ydata())
        assert all(x0 <= x <= x1 for x in xs) and all(y0 <= y <= y1 for y in ys)
    rays = [ln for ln in ax.lines if len(ln.get_xdata()) == 2 and ln.get_xdata()[0] == 0]
    assert rays and all(math.hypot(ln.get_xdata()[1], ln.get_ydata()[1]) > 0.5 for ln in rays)


def test_snapshots_hold_at_most_six_methods_a_panel(monkeypatch: pytest.MonkeyPatch,
                                                    tmp_path: Any) -> None:
    seen = drawn_figures(monkeypatch, draw_space)
    methods = [f"m{k}" for k in range(7)]
    case = base_case(methods, "burgers")
    for r in case["runs"]:
        r["metrics"] = {"pde-error": {"max_abs": 2.7e-3}}
    x = [0.1 * i for i in range(64)]
    pde = [[math.exp(-(v - 3) ** 2) for v in x] for _ in range(3)]
    ser = {"runs": [{"method": m, "dt": 0.1, "series": {"snapshots": {
        "t": [0.0, 1.0, 2.0], "x": x, "pde": pde,
        "u": [[v + 1e-6 * i * (k // 2 + 1) + 1e-9 * k for i, v in enumerate(row)]
              for row in pde]}}}
        for k, m in enumerate(methods)]}
    draw_space.fig_snapshots(ctx_for(case, tmp_path), case, ser)
    fig = seen[0]
    for ax in fig.axes:
        assert len([ln for ln in ax.lines if len(ln.get_xdata()) > 2]) <= 7  # PDE + six
    assert all(n == 0 for _, n in covered(fig)) and not outside(fig)
    # m0 = m1 apart by 1e-9, in u's units (not in the row's ×10⁻⁴: "to 1e-05")
    notes = [t.get_text().replace("\n", " ") for ax in fig.axes for t in ax.texts]
    assert any("m0 = m1 to 1e-09" in n for n in notes), notes
    labels = [t.get_text() for lg in fig.legends for t in lg.get_texts()]
    assert any("max $|u - u_{PDE}|$ = 0.0027" in lb for lb in labels), labels  # mathtext


def test_invariants_and_the_probe_in_mathtext() -> None:
    ser = {"runs": [{"series": {
        "invariants.angular_momentum.ratio_dev": {"t": [0.0], "y": [0.0]},
        "invariants.H_gamma.step_res": {"t": [0.0], "y": [1.0]},
        "attractor.probe": {"t": [0.0], "y": [1.0], "probe": "|psi(0, t)|"}}}]}
    labels = {k: lab for k, lab, _ in fd.series_panels(ser)}
    assert labels["invariants.angular_momentum.ratio_dev"] == \
        r"$e^{2\Gamma(t)}\,L_{n} / L_{0} - 1$ (angular momentum)"
    assert "$H_{\\gamma}$" in labels["invariants.H_gamma.step_res"]
    assert "_" not in labels["invariants.H_gamma.step_res"].replace("H_{", "").replace("z_n", "")
    assert r"$|\psi(0, t)|$" in labels["attractor.probe"]
    assert "H(q, p)" not in [lab for _, lab, _ in fd.SERIES_PANELS][0]  # z: any state


def test_a_fixed_point_attractor_is_marked() -> None:
    # B Fig 5.10's probe at A = 1, gamma = 0.5 settles on a point of the drive's frame: drawn as a
    # line of one point it was invisible; it gets a marker. Control: a periodic orbit gets none.
    import matplotlib.pyplot as plt
    import numpy as np
    t = np.linspace(0.0, 10.0, 400)
    settle = np.stack([np.exp(-t) - 0.23, -0.3 * (1 - np.exp(-t))], axis=1)
    loop = np.stack([np.cos(3 * t), np.sin(3 * t)], axis=1)
    late = t >= 5.0
    for pts, marked in ((settle, True), (loop, False)):
        fig, ax = plt.subplots()
        assert draw_space.portrait_panel(ax, pts, late, "C0", False, 0.01 * 2.0) is marked
        markers = [ln for ln in ax.lines if ln.get_marker() == "o"]
        assert len(markers) == (1 if marked else 0)
        if marked:
            assert abs(markers[0].get_xdata()[0] + 0.23) < 0.01
        plt.close(fig)


def test_a_failed_run_is_named_under_the_orbits(monkeypatch: pytest.MonkeyPatch,
                                                tmp_path: Any) -> None:
    # kepler-table21 at h = 2π/10: implicit-midpoint's solve fails at step 1; the figure drew
    # three panels for four methods and said nothing of the fourth. Control: without a failed run
    # there is no such line.
    seen = drawn_figures(monkeypatch, draw_space)
    case = base_case(["m0", "m1"], "kepler")
    case["runs"][1].update(status="solve-failed", failed_at_step=1)
    ring = [[math.cos(a), math.sin(a), 0.0, 0.0] for a in (0.1 * k for k in range(63))]
    for runs, named in ((2, True), (1, False)):
        ser = {"runs": [{"method": "m0", "dt": 0.1, "series": {"orbit": {"states": ring}}},
                        {"method": "m1", "dt": 0.1, "status": "solve-failed", "series": {}}][:runs]}
        draw_space.fig_orbit(ctx_for(case, tmp_path), case, ser)
        texts = [t.get_text() for t in seen[-1].texts]
        assert any(t.startswith("not drawn: m1 h=0.1: solve-failed at step 1") for t in texts) \
            is named
