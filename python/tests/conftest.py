"""Shared fixtures: the dampsym command line built beside the package (DAMPSYM_BIN, set by ctest)
and the repository root, whose cases and methods the tests run."""

from __future__ import annotations

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def dampsym_bin() -> str:
    path = os.environ.get("DAMPSYM_BIN", str(ROOT / "build" / "dampsym"))
    if not os.access(path, os.X_OK):
        pytest.fail(f"no dampsym binary at {path} (set DAMPSYM_BIN)")
    return path


def run_cli(binary: str, *args: str, cwd: pathlib.Path = ROOT) -> subprocess.CompletedProcess[str]:
    return subprocess.run([binary, *args], cwd=cwd, capture_output=True, text=True, check=False)


def before_provenance(text: str) -> str:
    """report.json's text up to its "provenance" key (what is identical between runs)."""
    cut = text.find('\n  "provenance": ')
    assert cut > 0, "no provenance in the report"
    return text[:cut]
