"""The readability rules on figures of cases unlike the default suite's (held-out parameters,
method sets and failures): notes and legends never over data, every coinciding line named, a
failed run named, a series of exact zeros drawn and said to be 0, every panel at least 250 px
tall, nothing outside the figure, at most six methods per panel. Each check is on the drawn
figure (pixels of the texts against the pixels of the lines)."""

import math
from typing import Any, Dict, List, Tuple

import numpy as np
import pytest

from dampfig import draw_series, draw_space
from dampfig import figdata as fd
from dampfig.render import Ctx

Json = Dict[str, Any]


def drawn_figures(monkeypatch: pytest.MonkeyPatch, module: Any) -> List[Any]:
    """The figures `module`'s figure functions save (drawn, not written)."""
    seen: List[Any] = []

    def keep(ctx: Ctx, fig: Any, case: Json, kind: str) -> str:
        fig.canvas.draw()
        seen.append(fig)
        return f"figures/{case['id']}-{kind}.png"

    monkeypatch.setattr(module, "save", keep)
    return seen


def line_pixels(ax: Any) -> Any:
    """Display coordinates of every drawn line of an axes, its segments sampled every 2 px."""
    out = []
    for ln in ax.lines:
        xy = np.column_stack([np.asarray(ln.get_xdata(), float), np.asarray(ln.get_ydata(), float)])
        if len(xy) == 0 or not ln.get_visible():
            continue
        if ax.get_yscale() == "log":
            xy = xy[xy[:, 1] > 0]
        px = ax.transData.transform(xy)
        px = px[np.all(np.isfinite(px), axis=1)]
        if ln.get_linestyle() not in ("None", "none", "") and len(px) > 1:
            a, b = px[:-1], px[1:]
            k = int(min(256, max(2, np.max(np.hypot(*(b - a).T)) / 2)))
            f = np.linspace(0.0, 1.0, k)[None, :, None]
            px = (a[:, None, :] + (b - a)[:, None, :] * f).reshape(-1, 2)
        out.append(px)
    return np.concatenate(out) if out else np.zeros((0, 2))


def covered(fig: Any) -> List[Tuple[str, int]]:
    """(text, pixels of data under it) of every text and legend drawn inside an axes."""
    renderer = fig.canvas.get_renderer()
    out = []
    for ax in fig.axes:
        box = ax.get_window_extent(renderer)
        pts = line_pixels(ax)
        pts = pts[(pts[:, 0] >= box.x0) & (pts[:, 0] <= box.x1) & (pts[:, 1] >= box.y0)
                  & (pts[:, 1] <= box.y1)]
        items = [(t.get_text(), t.get_window_extent(renderer)) for t in ax.texts]
        if ax.get_legend() and box.contains(*ax.get_legend().get_window_extent(renderer).p0):
            items.append(("legend", ax.get_legend().get_window_extent(renderer)))
        for text, b in items:
            inside = ((pts[:, 0] > b.x0) & (pts[:, 0] < b.x1) & (pts[:, 1] > b.y0)
                      & (pts[:, 1] < b.y1))
            out.append((text, int(inside.sum())))
    return out


def outside(fig: Any) -> List[str]:
    """Texts (legends, notes, titles) reaching beyond the figure's edges."""
    renderer = fig.canvas.get_renderer()
    w, h = fig.bbox.width, fig.bbox.height
    items = [t for ax in fig.axes for t in ax.texts] + \
        [ax.get_legend() for ax in fig.axes if ax.get_legend()] + list(fig.legends)
    out = []
    for t in items:
        b = t.get_window_extent(renderer)
        if b.x0 < -0.5 or b.y0 < -0.5 or b.x1 > w + 0.5 or b.y1 > h + 0.5:
            out.append(getattr(t, "get_text", lambda: "legend")())
    return out


def wave_case(methods: List[str], dts: List[float], key: str = "energy.value",
              failed: Tuple[str, ...] = ()) -> Tuple[Json, Json]:
    """A case whose runs' series under key fill the panel down to its bottom edge (a decaying
    wave) and coincide in pairs (method k and k+1 for even k)."""
    t = [0.05 * i for i in range(401)]
    runs, ser_runs = [], []
    for k, m in enumerate(methods):
        for h in dts:
            status = "diverged" if m in failed else "ok"
            runs.append({"method": m, "dt": h, "status": status, "metrics": {},
                         **({"failed_at_step": 17} if m in failed else {})})
            y = [math.cos(x) * math.exp(-0.1 * x) - 0.05 * x + 0.3 * (k // 2) for x in t]
            ser_runs.append({"method": m, "dt": h, "status": status,
                             "series": {} if m in failed else {key: {"t": t, "y": y}}})
    case = {"id": "held-out", "title": "", "source": "", "runs": runs, "checks": [],
            "dt_ladder": dts, "problem": {"id": "oscillator", "params": {}}}
    return case, {"t0": 0.0, "t_end": 20.0, "runs": ser_runs}


def draw(monkeypatch: pytest.MonkeyPatch, tmp_path: Any, case: Json, ser: Json) -> Any:
    seen = drawn_figures(monkeypatch, draw_series)
    ctx = Ctx(report={"cases": [case]}, out=str(tmp_path), formats=["png"])
    ctx.styles = fd.case_styles(list(dict.fromkeys(r["method"] for r in case["runs"])))
    draw_series.fig_series(ctx, case, ser)
    return seen[0]


def test_series_notes_are_never_over_data(monkeypatch: pytest.MonkeyPatch, tmp_path: Any) -> None:
    fig = draw(monkeypatch, tmp_path, *wave_case([f"m{k}" for k in range(6)], [0.1]))
    notes = [t for t, _ in covered(fig) if t.startswith("coincide")]
    assert notes, "the coinciding pairs are named"
    assert all(n == 0 for _, n in covered(fig)), covered(fig)
    assert not outside(fig)


def test_long_notes_are_wrapped_inside_their_panel(monkeypatch: pytest.MonkeyPatch,
                                                   tmp_path: Any) -> None:
    methods = [f"a-long-method-name-{k}" for k in range(6)]
    fig = draw(monkeypatch, tmp_path, *wave_case(methods, [0.2, 0.1]))
    renderer = fig.canvas.get_renderer()
    for ax in fig.axes:
        box = ax.get_window_extent(renderer)
        for t in ax.texts:
            b = t.get_window_extent(renderer)
            assert box.x0 - 0.5 <= b.x0 and b.x1 <= box.x1 + 0.5, t.get_text()
    assert all(n == 0 for _, n in covered(fig))


def test_every_coinciding_line_is_named(monkeypatch: pytest.MonkeyPatch, tmp_path: Any) -> None:
    # six methods on one line: each is hidden under another, each is named (in one group)
    case, ser = wave_case([f"m{k}" for k in range(6)], [0.1])
    for r in ser["runs"]:
        r["series"]["energy.value"]["y"] = ser["runs"][0]["series"]["energy.value"]["y"]
    fig = draw(monkeypatch, tmp_path, case, ser)
    note = next(t.get_text() for ax in fig.axes for t in ax.texts if "coincide" in t.get_text())
    assert all(f"m{k}" in note for k in range(6)), note
    assert fd.coincident_clusters(4, [(0, 1, 0.1), (2, 3, 0.0), (1, 2, 0.2)]) == \
        [([0, 1, 2, 3], 0.2)]
    assert fd.coincident_clusters(3, [(0, 2, 0.0)]) == [([0, 2], 0.0)]


def test_failed_runs_are_named_and_groups_keep_the_case_order(
        monkeypatch: pytest.MonkeyPatch, tmp_path: Any) -> None:
    methods = [f"m{k}" for k in range(8)]
    case, ser = wave_case(methods, [0.1], failed=("m1",))
    fig = draw(monkeypatch, tmp_path, case, ser)
    labels = [t.get_text() for ax in fig.axes if ax.get_legend()
              for t in ax.get_legend().get_texts()]
    assert any("m1" in x and "diverged at step 17" in x for x in labels), labels
    # the groups are the case's (m0..m5, m6..m7): the colours case_styles keeps apart
    first = [x for x in fig.axes[0].get_legend().get_texts()]
    assert [t.get_text().split(" ")[0] for t in first][:5] == ["m0", "m2", "m3", "m4", "m5"]


def test_a_series_of_exact_zeros_is_drawn_and_said_to_be_zero(
        monkeypatch: pytest.MonkeyPatch, tmp_path: Any) -> None:
    case, ser = wave_case(["m0", "m1"], [0.1], key="error.abs")
    for r in ser["runs"]:
        r["series"]["error.abs"]["y"] = [0.0] * len(r["series"]["error.abs"]["y"])
    fig = draw(monkeypatch, tmp_path, case, ser)
    ax = fig.axes[0]
    assert any("exactly 0" in t.get_text() for t in ax.texts)
    lo, hi = ax.get_ylim()
    assert lo < 0 < hi and hi - lo > 0.1  # no 1e-12 ticks
    assert ax.yaxis.get_offset_text().get_text() == ""


def test_panels_are_250_px_tall_and_the_legend_clears_the_title(
        monkeypatch: pytest.MonkeyPatch, tmp_path: Any) -> None:
    methods = [f"method-file-{k}" for k in range(7)]
    case, ser = wave_case(methods, [0.2, 0.1])
    for r in ser["runs"]:  # four quantities: four rows (236 px each before)
        y = r["series"]["energy.value"]
        r["series"].update({k: y for k in ("energy.error", "dissipation-drift.d",
                                           "temperature")})
    fig = draw(monkeypatch, tmp_path, case, ser)
    renderer = fig.canvas.get_renderer()
    axes = [ax for ax in fig.axes if ax.axison]
    assert all(ax.get_window_extent(renderer).height >= 250 for ax in axes)
    title = fig._suptitle.get_window_extent(renderer)
    for ax in axes[:2]:  # the top row's legends, above their columns
        b = ax.get_legend().get_window_extent(renderer)
        assert b.y1 <= title.y0 + 0.5 and b.y0 >= ax.get_window_extent(renderer).y1 - 0.5
    assert not outside(fig)
    assert all(n == 0 for _, n in covered(fig)), covered(fig)  # the d(t) legend too


def test_a_quantity_undefined_everywhere_is_named(monkeypatch: pytest.MonkeyPatch,
                                                  tmp_path: Any) -> None:
    case, ser = wave_case(["m0", "m1"], [0.1])
    for r in ser["runs"]:  # the series file's form of a ratio with I_0 = 0: no finite sample
        r["series"]["invariants.H_gamma.ratio_dev"] = {"t": [], "y": [], "nonfinite": 400}
    fig = draw(monkeypatch, tmp_path, case, ser)
    assert len([ax for ax in fig.axes if ax.axison]) == 1
    assert any("not drawn" in t.get_text() and "H_{\\gamma,n}" in t.get_text()
               for t in fig.texts), [t.get_text() for t in fig.texts]
