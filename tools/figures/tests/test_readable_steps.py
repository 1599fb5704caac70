"""Readability of the figures against the step size (held-out method sets): legends under their
panels, never over the data; a legend entry only for what is drawn; failed runs named; log tick
labels that do not run into each other."""

from typing import Any, Dict, List, Tuple

import pytest

from dampfig import draw_conv, render
from dampfig import figdata as fd
from dampfig.render import Ctx

from test_readable_layout import covered, drawn_figures, outside

Json = Dict[str, Any]


def ladder_case(n: int, fitted: bool, failed: Tuple[str, ...] = ()) -> Json:
    """n methods whose final errors fill the panel's diagonal (C_k h^2 with C_k 2^k apart)."""
    dts = [0.2, 0.1, 0.05, 0.025]
    runs, mm = [], {}
    for k in range(n):
        m = f"method-{k}"
        for h in dts:
            bad = m in failed and h == dts[0]
            runs.append({"method": m, "dt": h, "status": "diverged" if bad else "ok",
                         "metrics": {} if bad else {"error": {"final_abs": 2.0 ** k * h ** 2}}})
        if fitted:
            mm[m] = {"order": {"ok": True, "slope": 2.0, "window_dt": dts, "dropped": []}}
    return {"id": "held-out", "title": "", "source": "", "runs": runs, "checks": [],
            "dt_ladder": dts, "method_metrics": mm, "problem": {"id": "pendulum", "params": {}}}


def draw(monkeypatch: pytest.MonkeyPatch, tmp_path: Any, case: Json) -> Any:
    seen = drawn_figures(monkeypatch, draw_conv)
    ctx = Ctx(report={"cases": [case]}, out=str(tmp_path), formats=["png"])
    ctx.styles = fd.case_styles(list(dict.fromkeys(r["method"] for r in case["runs"])))
    draw_conv.fig_convergence(ctx, case, None)
    render.tidy(seen[0], ctx.xticks)
    seen[0].canvas.draw()
    return seen[0]


def legend_texts(fig: Any) -> List[str]:
    return [t.get_text() for ax in fig.axes if ax.get_legend()
            for t in ax.get_legend().get_texts()]


def test_convergence_legend_is_not_over_the_data(monkeypatch: pytest.MonkeyPatch,
                                                 tmp_path: Any) -> None:
    fig = draw(monkeypatch, tmp_path, ladder_case(6, True))
    assert any("slope 2.000" in x for x in legend_texts(fig))
    assert all(n == 0 for _, n in covered(fig)), covered(fig)
    assert not outside(fig)
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    lg = ax.get_legend().get_window_extent(renderer)
    assert lg.y1 <= ax.xaxis.label.get_window_extent(renderer).y0  # under the x label


def test_legend_explains_only_what_is_drawn(monkeypatch: pytest.MonkeyPatch,
                                            tmp_path: Any) -> None:
    texts = legend_texts(draw(monkeypatch, tmp_path, ladder_case(3, False)))
    assert not any("fitted" in x for x in texts), texts  # no fit drawn: no fit explained
    texts = legend_texts(draw(monkeypatch, tmp_path, ladder_case(3, True)))
    assert any("fitted" in x for x in texts)


def test_failed_runs_are_named(monkeypatch: pytest.MonkeyPatch, tmp_path: Any) -> None:
    fig = draw(monkeypatch, tmp_path, ladder_case(3, True, failed=("method-1",)))
    assert any("method-1 h=0.2: diverged" in t.get_text() for t in fig.texts)


def test_log_tick_labels_do_not_overlap(tmp_path: Any) -> None:
    ctx = Ctx(report={"cases": []}, out=str(tmp_path), formats=["png"])
    fig, axs = render.subplots(ctx, 1, 3, (13.8, 4.0))
    for ax in axs[0]:
        ax.plot([1.4e-6, 8e-6], [1e-4, 5e-3])  # work-precision's wall times: 0.76 decades
        ax.set_xscale("log")
        ax.set_yscale("log")
    render.layout(fig)
    render.tidy(fig, {})
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    for ax in axs[0]:
        boxes = sorted((t.label1.get_window_extent(renderer) for t in ax.xaxis.get_major_ticks()
                        if t.label1.get_visible() and t.label1.get_text()), key=lambda b: b.x0)
        assert len(boxes) >= 2
        assert all(a.x1 < b.x0 for a, b in zip(boxes, boxes[1:])), [(b.x0, b.x1) for b in boxes]
    assert render.fit_ticks([1.5e-6, 2e-6, 3e-6], 1.4e-6, 8e-6, 1000.0, True) == \
        [1.5e-6, 2e-6, 3e-6]  # room enough: every tick kept
    render.recycle(ctx, fig)


def trace_case(n: int) -> Tuple[Json, Json]:
    hs = [0.002 * 1.3 ** i for i in range(25)]
    methods = [f"method-{k}" for k in range(n)]
    mm = {m: {"trace-taylor": {"h4_coeff": 0.5 * (k + 1), "h4_coeff_expected": None}}
          for k, m in enumerate(methods)}
    maps = {m: {"half_trace_error": {"omega": 2.0, "gamma": 0.5, "h": hs,
                                     "error": [0.5 * (k + 1) * h ** 4 for h in hs]}}
            for k, m in enumerate(methods)}
    case = {"id": "held-out", "title": "", "source": "", "checks": [], "method_metrics": mm,
            "runs": [{"method": m, "dt": 0.1, "status": "ok", "metrics": {}} for m in methods],
            "dt_ladder": [0.1], "problem": {"id": "oscillator", "params": {}}}
    return case, {"stability_map": maps}


def test_half_trace_panels_hold_six_methods_and_their_legends_fit(
        monkeypatch: pytest.MonkeyPatch, tmp_path: Any) -> None:
    seen: List[Any] = []

    def keep(ctx: Ctx, fig: Any, case: Json, kind: str) -> str:
        render.draw_inside(fig)  # as save draws it: the margins and the height it needs
        seen.append(fig)
        return "f.png"

    monkeypatch.setattr(draw_conv, "save", keep)
    case, ser = trace_case(7)
    ctx = Ctx(report={"cases": [case]}, out=str(tmp_path), formats=["png"])
    ctx.styles = fd.case_styles([r["method"] for r in case["runs"]])
    draw_conv.fig_trace(ctx, case, ser)
    fig = seen[0]
    axes = [ax for ax in fig.axes if ax.axison]
    assert len(axes) == 2 and all(len([ln for ln in ax.lines if len(ln.get_xdata())]) <= 12
                                  for ax in axes)  # six methods: points and a line each
    assert all(n == 0 for _, n in covered(fig)), covered(fig)
    assert not outside(fig)


def test_a_legend_below_the_figure_makes_it_taller(tmp_path: Any) -> None:
    ctx = Ctx(report={"cases": []}, out=str(tmp_path), formats=["png"])
    fig, axs = render.subplots(ctx, 1, 1, (4.0, 3.0))
    ax = axs[0][0]
    ax.plot([0, 1], [0, 1], label="a")
    render.layout(fig, bottom=0.2)
    draw_conv.under_axes(ax, *ax.get_legend_handles_labels())
    for k in range(12):  # planted: many more entries than the margin holds
        ax.plot([], [], label=f"entry {k}")
    draw_conv.under_axes(ax, *ax.get_legend_handles_labels())
    height = ax.get_window_extent().height
    render.draw_inside(fig)
    assert render.legends_below(fig) <= 0.5 and not outside(fig)
    assert abs(ax.get_window_extent().height - height) < 1  # the panel keeps its size
    render.recycle(ctx, fig)
