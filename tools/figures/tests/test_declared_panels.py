"""A series no panel of figdata.SERIES_PANELS knows (a new diagnostic's) is drawn in a panel of its
own, with the label and scale its series declares: adding a diagnostic with a series needs no
change to the plotter."""

from typing import Any, Dict

import pytest

from dampfig import draw_series
from dampfig import figdata as fd
from dampfig.render import Ctx

from test_readable_layout import drawn_figures

Json = Dict[str, Any]


def series_file(extra: Json) -> Json:
    t = [0.5 * k for k in range(1, 41)]
    norm = {"t": t, "y": [1.0 / (1.0 + x) for x in t], "per_bucket": 1, "nonfinite": 0,
            "last": [t[-1], 1.0 / (1.0 + t[-1])], **extra}
    return {"format": "dampsym-series-1", "case": "held-out", "problem": "oscillator",
            "runs": [{"method": "cimp", "dt": 0.1, "status": "ok",
                      "series": {"state-norm.norm": norm,
                                 "dissipation-drift.d_reference": {"t": t, "y": t}}}]}


def test_declared_label_and_scale() -> None:
    panels = fd.series_panels(series_file({"label": r"$\|z_n\|_2$", "scale": "log"}))
    assert panels == [("state-norm.norm", r"$\|z_n\|_2$", "log")]


def test_undeclared_or_bad_declarations_fall_back() -> None:
    """Its name as the label (a '$' escaped: not mathtext) and a linear axis; the reference's
    d(t), drawn inside d(t)'s panel, gets none of its own."""
    assert fd.series_panels(series_file({})) == [("state-norm.norm", "state-norm.norm", "linear")]
    bad = series_file({"label": "x" * 500, "scale": "cubic"})
    assert fd.series_panels(bad) == [("state-norm.norm", "state-norm.norm", "linear")]
    dollar = series_file({})
    dollar["runs"][0]["series"]["a$b"] = dollar["runs"][0]["series"].pop("state-norm.norm")
    assert fd.series_panels(dollar) == [("a$b", r"a\$b", "linear")]


def test_a_declared_series_is_drawn(monkeypatch: pytest.MonkeyPatch, tmp_path: Any) -> None:
    seen = drawn_figures(monkeypatch, draw_series)
    case = {"id": "held-out", "title": "", "source": "", "checks": [], "dt_ladder": [0.1],
            "runs": [{"method": "cimp", "dt": 0.1, "status": "ok", "metrics": {}}],
            "problem": {"id": "oscillator", "params": {}}}
    ctx = Ctx(report={"cases": [case]}, out=str(tmp_path), formats=["png"])
    ctx.styles = fd.case_styles(["cimp"])
    drawn = draw_series.fig_series(ctx, case, series_file({"label": r"$\|z_n\|_2$",
                                                            "scale": "log"}))
    assert [q for _, _, q in drawn] == [["state-norm.norm"]]
    (ax,) = [a for a in seen[0].axes if a.lines]
    assert ax.get_yscale() == "log" and ax.get_ylabel() == r"$\|z_n\|_2$"


def test_declared_panels_are_capped() -> None:
    """A series file with many unknown keys (hand-made or damaged) gives at most MAX_DECLARED
    panels, the first in name order."""
    ser = series_file({})
    one = ser["runs"][0]["series"].pop("state-norm.norm")
    for k in range(50):
        ser["runs"][0]["series"][f"x{k:02d}"] = one
    panels = fd.series_panels(ser)
    assert [p[0] for p in panels] == [f"x{k:02d}" for k in range(fd.MAX_DECLARED)]
