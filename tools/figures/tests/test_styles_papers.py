"""Styles (colour-blind-safe palette, distinct colours per panel group, greys reserved) and the
paper-figure descriptions of figures.md (every paper item a case of verify/cases names is
described)."""

import glob
import itertools
import json
import os

from dampfig import figdata as fd
from dampfig import papers
from dampfig import styles as st

CASES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "verify",
                     "cases")


def chroma(c: str) -> float:
    r, g, b = (int(c[i:i + 2], 16) for i in (1, 3, 5))
    return float(max(r, g, b) - min(r, g, b))


def test_palette_apart_and_no_grey() -> None:
    for a, b in itertools.combinations(st.PALETTE, 2):
        assert st.lab_distance(a, b) >= 25, (a, b)
    for c in st.PALETTE:  # greys are the reference's and the transient's only
        assert c == "#000000" or chroma(c) > 60, c
        for g in (st.REFERENCE_GREY, st.TRANSIENT_GREY):
            assert st.lab_distance(c, g) >= 25
    # negative control: the old palette's glifrk2 and gauss3 were 15 apart
    assert st.lab_distance("#9467bd", "#756bb1") < 25


def test_case_styles_distinct_in_each_group() -> None:
    methods = ["cimp", "csv1", "csv2", "glifrk1", "glifrk2", "glifrk3", "etdrk2", "cse-if",
               "cse-etd", "gauss1", "gauss2", "gauss3", "rk3", "rk4", "heun", "my-file-method"]
    styles = st.case_styles(methods)
    for group in st.groups(methods):
        colours = [styles[m][0] for m in group]
        assert len(set(colours)) == len(colours), group
        assert len(group) <= st.GROUP
    # the preferred colour is kept when free; markers and line styles never change
    assert styles["cimp"] == st.method_style("cimp")
    assert all(styles[m][1:] == st.method_style(m)[1:] for m in methods)
    assert st.case_styles(["a-file", "b-file"]) == st.case_styles(["a-file", "b-file"])


def test_every_case_of_the_suite_has_distinct_colours_per_group() -> None:
    for path in glob.glob(os.path.join(CASES, "*.json")):
        with open(path) as f:
            methods = json.load(f).get("methods", [])
        methods = [m for m in methods if isinstance(m, str)]
        styles = st.case_styles(methods)
        for group in st.groups(methods):
            assert len({styles[m][0] for m in group}) == len(group), (path, group)


def test_paper_items() -> None:
    assert papers.items("F Figs 3.1-3.3") == ["F Fig 3.1", "F Fig 3.2", "F Fig 3.3"]
    assert papers.items("B Table 3.1, Fig 3.6") == ["B Table 3.1", "B Fig 3.6"]
    assert papers.items("F Figs 4.9 and 4.10") == ["F Fig 4.9", "F Fig 4.10"]
    assert papers.is_figure("HLW Fig 3.1, Table 3.1") and not papers.is_figure("F Table 4.1")
    assert papers.describe("X Fig 9.9") == "(not described)"


def test_every_paper_item_of_the_suite_is_described() -> None:
    named = 0
    for path in glob.glob(os.path.join(CASES, "*.json")):
        with open(path) as f:
            ref = fd.paper_figure(json.load(f))
        if ref:
            named += 1
            missing = [i for i in papers.items(ref) if i not in papers.PAPER_FIGURES]
            assert not missing, (path, ref, missing)
    assert named > 30


def test_gallery_row_sets_the_paper_beside_ours() -> None:
    from dampfig import cli
    case = {"id": "c1", "title": "a|b", "checks": [{"name": "k", "passed": False}]}
    figs = [{"file": "figures/c1-series.png", "caption": "c1: time series", "kind": "series",
             "quantities": ["measure-pointwise.q.rel", "measure.u_rel_max"]}]
    row = cli.gallery_row(case, figs, "B Fig 5.1")
    cells = [c.strip() for c in row.strip("|").split(" | ")]
    assert len(cells) == 8, cells  # no unescaped | inside a cell
    assert cells[2].startswith("B Fig 5.1: damped Klein–Gordon: absolute error")
    assert cells[4] == "series: measure-pointwise.q.rel, measure.u_rel_max"
    assert cells[3] == "a\\|b" and cells[7] == "**FAIL** (1)"
