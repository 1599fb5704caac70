"""cli --after-go (dampsym run --figures starts the script with the run): nothing is read or drawn
until the line "go" arrives; at the end of input without it the script exits 0 having done
nothing, and after it the script goes on as without the option (here: no report.json, exit 2)."""

import io
import os
from typing import Any

from dampfig import cli


def test_end_of_input_without_go_draws_nothing(monkeypatch: Any, tmp_path: Any) -> None:
    monkeypatch.setattr(cli.signal, "signal", lambda *a: None)  # pytest keeps its own handlers
    monkeypatch.setattr("sys.stdin", io.StringIO(""))
    assert cli.main([str(tmp_path), "--after-go"]) == 0
    assert os.listdir(tmp_path) == []  # not even figures/


def test_go_starts_the_drawing(monkeypatch: Any, tmp_path: Any) -> None:
    monkeypatch.setattr(cli.signal, "signal", lambda *a: None)
    monkeypatch.setattr("sys.stdin", io.StringIO("go\n"))
    assert cli.main([str(tmp_path), "--after-go"]) == 2  # no report.json to plot: bad input
    monkeypatch.setattr("sys.stdin", io.StringIO("gone\n"))
    assert cli.main([str(tmp_path), "--after-go"]) == 0
