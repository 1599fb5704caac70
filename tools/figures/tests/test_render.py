"""Drawing helpers and the readability rules of the figures (matplotlib, Agg): tick choice, the
power of ten taken out of linear panels, coinciding lines, and a synthetic case of 8 methods
drawn as a series figure (no panel with more than six methods, every panel at least 250 px tall,
a note naming the two coinciding runs)."""

import math
from typing import Any, Dict, List, Tuple

import pytest

from dampfig import draw_series, render
from dampfig.render import Ctx


def test_log_ticks_label_at_least_three_below_two_decades() -> None:
    assert len(render.log_ticks(2e-3, 7e-2)) >= 3
    assert render.log_ticks(1e-16, 1e-2)[0] == 1e-16 and len(render.log_ticks(1e-16, 1e-2)) <= 8
    assert render.log_label(2.5e-3) == "2.5×10⁻³" and render.log_label(1e4) == "10⁴"


def test_close_ticks_get_distinct_labels() -> None:
    # step sizes 2 % apart (a stability threshold's 0.99 h* and 1.01 h*) were both 1.3×10⁰
    hs = [1.2941001297150938, 1.320243566679035]
    assert render.log_label(hs[0]) == render.log_label(hs[1])
    assert render.distinct_digits(hs) == 3
    fmt = render.log_formatter(hs)
    assert [fmt(h, None) for h in hs] == ["1.29×10⁰", "1.32×10⁰"]
    assert render.distinct_digits([1e-3, 2.5e-3]) == 2  # labels that differ keep two digits


def test_narrow_log_range_gets_two_ticks() -> None:
    # bare-loop times 1 % apart: no 1, 1.2, 1.5, ... × 10^k falls inside, and the axis had none
    lo, hi = 1.305e-6, 1.3255e-6
    finest = (1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6, 8)
    assert not [m * 1e-6 for m in finest if lo <= m * 1e-6 <= hi]
    ticks = render.log_ticks(lo, hi)
    assert len(ticks) >= 2 and all(lo <= t <= hi for t in ticks)
    assert len({render.log_formatter(ticks)(t, None) for t in ticks}) == len(ticks)
    # a spectral radius of 1 ± 1e-6 (stress-gamma-1e3): nice values would need 7 digits to tell
    # apart and were labelled 10⁰ and 1×10⁰; the axis keeps its one label
    assert render.log_label(0.9999999) == render.log_label(1.000002) == "10⁰"
    assert render.log_label(9.99e-3) == "10⁻²" and render.log_label(6.25e-3) == "6.2×10⁻³"
    assert len(render.log_ticks(0.9999995, 1.000003)) <= 1


def test_sci_scale() -> None:
    assert render.sci_scale([[0.0, -2.4e-5]]) == -5
    assert render.sci_scale([[0.5, 3.0]]) == 0
    assert render.sci_scale([[]]) == 0


def test_coincident() -> None:
    t = [0.0, 1.0, 2.0, 3.0]
    a = (t, [0.0, 1.0, 2.0, 3.0])
    assert 0 <= render.coincident(a, (t, [0.0, 1.0, 2.0, 3.0 + 1e-4]), 3.0, False) < 1e-3
    assert render.coincident(a, (t, [0.0, 1.0, 2.0, 3.2]), 3.0, False) < 0  # 7 % of the span


def series_case(n: int) -> Tuple[Dict[str, Any], Dict[str, Any]]:
    methods = [f"m{k}" for k in range(n)]
    t = [0.1 * i for i in range(1, 101)]
    runs = [{"method": m, "dt": 0.1, "status": "ok", "metrics": {}} for m in methods]
    ser_runs = []
    for k, m in enumerate(methods):
        # m0 and m1 coincide; the others are apart
        y = [1e-5 * (1 + (k if k > 1 else 0)) * math.sin(x) for x in t]
        ser_runs.append({"method": m, "dt": 0.1, "status": "ok",
                         "series": {"invariants.I.ratio_dev": {"t": t, "y": y}}})
    case = {"id": "synthetic", "title": "", "source": "", "runs": runs, "checks": [],
            "dt_ladder": [0.1], "problem": {"id": "oscillator", "params": {}}}
    return case, {"t0": 0.0, "t_end": 10.0, "runs": ser_runs}


def test_series_panels_readable(monkeypatch: pytest.MonkeyPatch, tmp_path: Any) -> None:
    seen: List[Any] = []

    def keep(ctx: Ctx, fig: Any, case: Dict[str, Any], kind: str) -> str:
        fig.canvas.draw()
        seen.append(fig)
        return f"figures/{case['id']}-{kind}.png"

    monkeypatch.setattr(draw_series, "save", keep)
    case, ser = series_case(8)
    ctx = Ctx(report={"cases": [case]}, out=str(tmp_path), formats=["png"])
    drawn = draw_series.fig_series(ctx, case, ser)
    assert drawn[0][2] == ["invariants.I.ratio_dev"]
    fig = seen[0]
    axes = [ax for ax in fig.axes if ax.axison]
    assert len(axes) == 2  # 8 methods: two groups
    for ax in axes:
        assert len(ax.lines) <= 6
        assert ax.get_window_extent().height >= 250
        assert "$" in ax.get_ylabel() and "10⁻⁵" in ax.get_ylabel()  # mathtext, scale in label
    notes = [t.get_text() for ax in axes for t in ax.texts]
    assert any("m0 = m1" in n for n in notes), notes
    assert not any("m2 = m3" in n for n in notes)
    assert fig.axes[0].yaxis.get_offset_text().get_text() == ""


def test_offset_base_replaces_the_offset_text() -> None:
    near = [[0.99004983375, 0.99004983338], [0.9900498323]]
    base = draw_series.offset_base(near)
    assert abs(base - 0.990049833) < 1e-15
    assert all(abs(v - base) < 1e-8 for y in near for v in y)
    # a spread of 1e-3 of the size needs no base; equal values are is_flat's
    assert draw_series.offset_base([[1.0, 1.001]]) == 0.0
    assert draw_series.offset_base([[2.0, 2.0]]) == 0.0


def test_draw_inside_widens_a_margin_only_where_a_label_is_cut_off(tmp_path: Any) -> None:
    ctx = Ctx(report={"cases": []}, out=str(tmp_path), formats=["png"])
    fig, axs = render.subplots(ctx, 1, 1, (4.6, 4.0))
    ax = axs[0][0]
    ax.plot([0.44, 3.5], [0.1, 3.0])
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_ylabel("local error (one step)")
    ax.set_xlim(0.44, 3.5)
    render.layout(fig, left=0.05, right=0.98)  # too narrow for the log tick labels and label
    render.tidy(fig, {id(ax): [0.44, 0.88, 1.75, 3.5]})  # a step ladder's h, the last at the edge
    fig.canvas.draw()
    left, right, _ = render.overhang(fig)
    assert left > 10 and right > 0.5  # planted: the y label and the last x tick label cut off
    render.draw_inside(fig)
    assert max(render.overhang(fig)) <= 0.5
    assert fig.subplotpars.left > 0.05 and fig.subplotpars.right < 0.98
    # labels that fit: drawn once, the margins as they were
    render.layout(fig, left=0.3, right=0.8)
    render.draw_inside(fig)
    assert (fig.subplotpars.left, fig.subplotpars.right) == (0.3, 0.8)
    assert max(render.overhang(fig)) <= 0.5
    render.recycle(ctx, fig)


def test_a_renderer_kept_from_another_figure_draws_the_same_pixels() -> None:
    """reuse_renderer: a figure drawn on a renderer of its size kept from another figure (whose
    size changed) is the same pixels as on a new renderer."""
    import matplotlib.pyplot as plt
    import numpy as np
    assert render.GET_RENDERER_KNOWN, "matplotlib's get_renderer changed: check reuse_renderer"

    def figure(label: str) -> Any:
        fig, ax = plt.subplots(figsize=(4, 3), dpi=100)
        ax.plot([0, 1, 2], [1, 0, 2], "o-", label=label)
        ax.legend()
        return fig

    pool: Dict[Any, Any] = {}
    first = figure("first")
    render.reuse_renderer(pool, first)
    first.canvas.draw()
    kept = first.canvas.get_renderer()
    first.set_size_inches(5, 3)
    render.reuse_renderer(pool, first)  # its 4x3 renderer kept for another figure
    first.canvas.draw()
    second = figure("second")
    render.reuse_renderer(pool, second)
    second.canvas.draw()
    assert second.canvas.get_renderer() is kept and first.canvas.get_renderer() is not kept
    fresh = figure("second")
    fresh.canvas.draw()
    assert np.array_equal(np.asarray(second.canvas.buffer_rgba()),
                          np.asarray(fresh.canvas.buffer_rgba()))
    for f in (first, second, fresh):
        plt.close(f)


def test_a_written_figure_releases_its_renderer(monkeypatch: pytest.MonkeyPatch) -> None:
    """release_renderer (through recycle): after many figures of different sizes only the pooled
    renderers are alive, and a recycled figure drawn again is the same pixels. Negative control:
    without the release, every blank figure and its texts keep the renderer of their last draw."""
    import gc

    import matplotlib.pyplot as plt
    import numpy as np
    from matplotlib.backends.backend_agg import RendererAgg
    assert render.GET_RENDERER_KNOWN, "matplotlib's get_renderer changed: check release_renderer"

    def live() -> int:
        gc.collect()
        return sum(1 for o in gc.get_objects() if isinstance(o, RendererAgg))

    def draw_sizes(ctx: Ctx, sizes: int) -> Any:
        for k in range(sizes):
            fig, axs = render.subplots(ctx, 1 + k % 12, 1, (3 + 0.1 * k, 2 + 0.2 * k))
            axs[0][0].plot([0, 1, 2], [1, 0, 2], label="a")
            axs[0][0].set_title(f"figure {k}")
            render.reuse_renderer(ctx.renderers, fig)
            fig.canvas.draw()
            pixels = np.asarray(fig.canvas.buffer_rgba()).copy()
            render.recycle(ctx, fig)
        return pixels

    plt.close("all")
    before = live()
    ctx = Ctx(report={}, out="", formats=["png"])
    last = draw_sizes(ctx, 3 * render.KEEP_RENDERERS)
    assert live() - before <= render.KEEP_RENDERERS
    plt.close("all")
    ctx.blank.clear()
    ctx.renderers.clear()

    # negative control: no release, the renderers pile up
    monkeypatch.setattr(render, "release_renderer", lambda pool, fig: None)
    ctx = Ctx(report={}, out="", formats=["png"])
    again = draw_sizes(ctx, 3 * render.KEEP_RENDERERS)
    assert live() - before >= 12 + render.KEEP_RENDERERS  # a blank figure of each grid
    plt.close("all")
    assert np.array_equal(last, again)


def test_gap_note_names_lines_that_stop() -> None:
    # cimp's e^{2Γ} H_n / H_0 − 1 on the overdamped oscillator ends at t = 3.66 (its round-off
    # times e^{2Γ} after that, skipped as non-finite by the C++ series): the note says so
    key = "invariants.H_gamma.ratio_dev"

    def run(method: str, nonfinite: int, last: Any) -> Dict[str, Any]:
        return {"method": method, "dt": 0.1, "series": {key: {
            "t": [0.1, 0.2, 3.66], "y": [0.0, 1e-9, 2e-9], "nonfinite": nonfinite, "last": last}}}

    runs = [run("cimp", 1014, None), run("csv1", 0, [10.0, 2.7e15]), run("rk3", 2, [10.0, 1.0])]
    assert draw_series.gap_note(runs, key, False) == \
        "no value (not drawn): cimp after t = 3.66, rk3 at 2 points"
    assert draw_series.gap_note(runs[1:2], key, False) == ""  # control: every point has a value
