"""crosscheck.md's per-case summary table: GFM-safe cells, the right counts and verdicts."""
from __future__ import annotations

import re
import shutil
import subprocess
from typing import Any, Dict, List

import pytest

from verify import crosscheck as cc


def comp(q: str, ours: float, theirs: float, tol: float, status: str = "agree") -> Dict[str, Any]:
    return dict(quantity=q, ours=ours, theirs=theirs, tolerance="rel", tol_abs=tol, status=status,
                agree=status == "agree", rel_diff=abs(ours - theirs) / abs(theirs))


def result(recs: List[Dict[str, Any]]) -> Dict[str, Any]:
    return dict(structure=[], runs=recs, orders=[], checks=[], timing=[("a|b", "p", 0.0, 0.0)])


def test_cells_are_escaped() -> None:
    assert cc.gfm_cell("|x| <= 1") == "\\|x\\| <= 1"
    assert cc.gfm_cell("a\nb") == "a b"


def test_rows_have_five_cells() -> None:
    recs = [dict(case="a|b", method="m", dt=0.1, verdict="agree", comparisons=[comp("x", 1.0, 1.0 + 1e-9, 1e-8)]),
            dict(case="a|b", method="m", dt=0.05, verdict="disagree",
                 comparisons=[comp("y", 1.0, 1.1, 1e-2, "disagree")])]
    table = cc.case_summary_table(result(recs))
    row = table[-1]
    cells = [c for c in row.replace("\\|", "").split("|")][1:-1]
    assert len(cells) == 5, row
    assert "1 of 2" in row and "**disagree**" in row and "10 (y)" in row


def test_agreeing_case() -> None:
    recs = [dict(case="c", method="m", dt=0.1, verdict="agree", comparisons=[comp("x", 1.0, 1.0 + 1e-9, 1e-8)])]
    row = cc.case_summary("c", recs)
    assert row[1:] == ("1", "1 of 1", "0.1 (x)", "agree")


@pytest.mark.skipif(shutil.which("cmark-gfm") is None, reason="cmark-gfm (Debian) not installed")
def test_renders_as_a_table_with_gfm() -> None:
    """A GFM renderer keeps the table: a header and one row per case, the cells as written, even
    with '|' in a case id and in a quantity (negative control: the unescaped row splits 'a|b')."""
    recs = [dict(case="a|b", method="m", dt=0.1, verdict="agree", comparisons=[comp("|x|", 1.0, 1.0, 1e-8)]),
            dict(case="c", method="m", dt=0.1, verdict="agree", comparisons=[comp("y", 1.0, 1.0, 1e-8)])]
    res = result(recs)
    res["timing"] = [("a|b", "p", 0.0, 0.0), ("c", "p", 0.0, 0.0)]
    md = "\n".join(cc.case_summary_table(res)) + "\n"

    def rows(text: str) -> List[List[str]]:
        html = subprocess.run(["cmark-gfm", "-e", "table"], input=text, capture_output=True, text=True,
                              check=True).stdout
        return [re.findall(r"<t[dh][^>]*>(.*?)</t[dh]>", r, re.S) for r in re.findall(r"<tr>(.*?)</tr>", html, re.S)]

    got = rows(md)
    assert [len(r) for r in got] == [5, 5, 5]
    assert got[1] == ["a|b", "1", "1 of 1", "0 (|x|)", "agree"]
    assert rows(md.replace("\\|", "|"))[1][0] == "a"
