"""Options of the tests that read dampsym's outputs (ctest passes them; verify/CMakeLists.txt).
A test whose input is not given is skipped, so `python3 -m pytest verify` runs the unit tests."""
from __future__ import annotations

import os
from typing import Any, Generator, List, Optional

import pytest


def pytest_addoption(parser: pytest.Parser) -> None:
    g = parser.getgroup("dampsym")
    g.addoption("--report", action="append", default=[], help="a report.json (or a report directory)")
    g.addoption("--workdir", help="scratch directory of the test")
    g.addoption("--bin", help="the dampsym binary")
    g.addoption("--register", help="docs/claims.md")
    g.addoption("--ctest-build", help="the build directory (ctest --output-junit)")
    g.addoption("--xc-cache", help="the cross-check's cache of its own results (crosscheck.py --cache): "
                                   "read (never extended) by the negative controls")
    g.addoption("--no-skips", action="store_true",
                help="a skipped test fails (the ctests: an input they forgot to pass is an error)")


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item: pytest.Item, call: pytest.CallInfo[None]) -> Generator[None, Any, None]:
    outcome = yield
    rep = outcome.get_result()
    if rep.skipped and item.config.getoption("no_skips"):
        rep.outcome = "failed"
        rep.longrepr = "skipped under --no-skips: %s" % (rep.longrepr,)


def _opt(config: pytest.Config, name: str) -> Optional[str]:
    v = config.getoption(name)
    return str(v) if v else None


@pytest.fixture
def reports(request: pytest.FixtureRequest) -> List[str]:
    r: List[str] = list(request.config.getoption("report") or [])
    if not r:
        pytest.skip("no --report given")
    return r


@pytest.fixture
def report_path(reports: List[str]) -> str:
    return reports[0]


@pytest.fixture
def workdir(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> str:
    w = _opt(request.config, "workdir") or str(tmp_path_factory.mktemp("work"))
    os.makedirs(w, exist_ok=True)
    return w


@pytest.fixture
def dampsym_bin(request: pytest.FixtureRequest) -> str:
    b = _opt(request.config, "bin")
    if b is None:
        pytest.skip("no --bin given")
    return b


@pytest.fixture
def register_path(request: pytest.FixtureRequest) -> str:
    r = _opt(request.config, "register")
    if r is None:
        pytest.skip("no --register given")
    return r


@pytest.fixture
def ctest_build(request: pytest.FixtureRequest) -> Optional[str]:
    return _opt(request.config, "ctest_build")


@pytest.fixture
def xc_cache(request: pytest.FixtureRequest) -> Optional[str]:
    return _opt(request.config, "xc_cache")
