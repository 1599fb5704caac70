"""The work-precision figure (dampfig.workprecision, tools/figures/work_precision_plot.py) on a tiny
fixture: it is drawn (a PNG with one row of two log-log panels and a legend naming every solver),
and malformed data is refused with exit 2 and a message naming the file and the key."""

import copy
import json
import os
import sys
from typing import Any, Dict, List

import pytest

from dampfig import workprecision as wp

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import work_precision_plot  # noqa: E402


def point(t: float, n: int, e: float) -> Dict[str, Any]:
    return {"cpu_seconds": t, "force_evals": n, "error": e}


def fixture() -> Dict[str, Any]:
    series = [
        {"solver": "csv1", "library": "dampsym", "kind": "fixed",
         "points": [point(1e-4, 1000, 1e-3), point(2e-4, 2000, 2.5e-4)]},
        {"solver": "gsl-rk8pd", "library": "GSL", "kind": "adaptive",
         "points": [point(5e-5, 700, 1e-4), point(8e-5, 1100, 1e-7), {"failed": "GSL_ENOPROG"}]},
        {"solver": "scipy-DOP853", "library": "scipy", "kind": "adaptive",
         "points": [point(5e-3, 600, 1e-5), point(9e-3, 900, 0.0)]},
    ]
    return {"schema": wp.SCHEMA, "machine": {"cpu": "test cpu", "cpus": 2,
                                              "load_avg_cpp": [0.5, 0.4, 0.3]},
            "problems": [{"id": "toy", "case": "toy-case", "params": {"gamma": 0.1},
                          "t_end": 10.0, "series": series,
                          "reference": {"name": "certified toy", "error_estimate": 1e-12,
                                        "final_state": [0.3, 0.4]}}]}


def write(tmp_path: Any, data: Any, name: str = "wp.json") -> str:
    path = str(tmp_path / name)
    with open(path, "w") as f:
        f.write(data if isinstance(data, str) else json.dumps(data))
    return path


def test_fixture_is_drawn(tmp_path: Any) -> None:
    out = str(tmp_path / "wp.png")
    assert work_precision_plot.main([write(tmp_path, fixture()), "--out", out]) == 0
    with open(out, "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"


def test_rows_panels_and_legend() -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig = plt.figure()
    axes = [fig.add_subplot(1, 3, 1), fig.add_subplot(1, 3, 2)]
    leg = fig.add_subplot(1, 3, 3)
    data = fixture()
    wp.draw_row(axes, leg, data["problems"][0], wp.solver_styles(data["problems"]))
    assert all(ax.get_xscale() == "log" and ax.get_yscale() == "log" for ax in axes)
    texts = [t.get_text() for t in leg.get_legend().get_texts()]
    assert texts[:3] == ["dampsym csv1 (fixed h)", "GSL rk8pd (adaptive)",
                         "scipy DOP853 (adaptive)"]
    assert "reference: certified toy" in leg.get_legend().get_title().get_text()
    # the failed point and the zero error are not drawn; the others are
    assert [len(line.get_xdata()) for line in axes[1].get_lines()[:3]] == [2, 2, 1]
    plt.close(fig)


def test_styles_distinct_within_a_row_and_kept_across_rows() -> None:
    a = [{"solver": s, "library": lib} for s, lib in
         [("csv1", "dampsym"), ("glifrk2", "dampsym"), ("odeint-dopri5", "Boost.Odeint"),
          ("gsl-rk8pd", "GSL"), ("scipy-DOP853", "scipy"), ("scipy-Radau", "scipy"),
          ("gsl-rk4imp", "GSL"), ("odeint-rkn", "Boost.Odeint"), ("glifrk3", "dampsym")]]
    b = [{"solver": "cimp", "library": "dampsym"}] + a[1:]
    styles = wp.solver_styles([{"series": a}, {"series": b}])
    for row in (a, b):
        assert len({styles[s["solver"]][0] for s in row}) == len(row)
        assert len({styles[s["solver"]][1] for s in row}) == len(row)
    assert styles["scipy-Radau"][2] == ":" and styles["csv1"][2] == "-"


def malformed() -> List[Any]:
    cases: List[Any] = []
    for edit, key in [
        (lambda d: d.pop("schema"), "schema"),
        (lambda d: d.update(problems=[]), "problems"),
        (lambda d: d["problems"][0]["series"][0]["points"][1].update(error=-1.0),
         "problems[0].series[0].points[1].error"),
        (lambda d: d["problems"][0]["series"][1]["points"][0].pop("cpu_seconds"),
         "problems[0].series[1].points[0].cpu_seconds"),
        (lambda d: d["problems"][0]["series"][2].update(kind="sometimes"),
         "problems[0].series[2].kind"),
        (lambda d: d["problems"][0]["reference"].pop("name"), "problems[0].reference.name"),
        (lambda d: d["problems"][0]["series"][0]["points"][0].update(force_evals="many"),
         "problems[0].series[0].points[0].force_evals"),
    ]:
        d = copy.deepcopy(fixture())
        edit(d)
        cases.append((d, key))
    return cases + [("{not json", "not JSON"), ([1, 2], "(top level)")]


@pytest.mark.parametrize("data,key", malformed())
def test_malformed_data_exits_2_naming_file_and_key(tmp_path: Any, capsys: Any, data: Any,
                                                    key: str) -> None:
    path = write(tmp_path, data)
    out = str(tmp_path / "wp.png")
    assert work_precision_plot.main([path, "--out", out]) == 2
    err = capsys.readouterr().err
    assert path in err and key in err
    assert not os.path.exists(out)


def test_missing_file_exits_2_and_unwritable_output_3(tmp_path: Any) -> None:
    assert work_precision_plot.main([str(tmp_path / "absent.json"), "--out",
                                     str(tmp_path / "a.png")]) == 2
    assert work_precision_plot.main([write(tmp_path, fixture()), "--out",
                                     str(tmp_path / "no-dir" / "a.png")]) == 3
