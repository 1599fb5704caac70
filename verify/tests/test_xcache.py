"""The cross-check's cache of its own results (verify/xcache.py, crosscheck.py --cache) can never
make a changed report look like agreement, nor change a result.

    /usr/bin/python3 -m pytest verify/tests/test_xcache.py                     (the unit tests)
    /usr/bin/python3 -m pytest verify/tests/test_xcache.py::test_planted_after_cache \
        --report REPORT.json --workdir WORKDIR                               (ctest crosscheck.negative)

Unit tests: a key moves with every input (dt, z0 and a problem parameter by one ulp, the method,
the step count, the record flag), a result read back is bit for bit the computed one, an
unreadable entry is recomputed, a read-only cache adds nothing, an argument it cannot hash is
not cached.  test_planted_after_cache: a slice of the default suite's report is cross-checked
once writing the cache; then faults are planted in the report (a final state x (1 + 1e-7), a
metric x (1 + 1e-3), a flipped verdict) and the cross-check, reading the cache, must hit it and
still report each fault, with a result identical to a cross-check without any cache.
"""
from __future__ import annotations

import copy
import json
import os
import shutil
from typing import Any, Dict, Iterator, List

import numpy as np
import pytest

from verify import xcache
from verify import xproblems as xp
from verify import xrun
from verify.tests import test_crosscheck_negative as neg

Rep = Dict[str, Any]


@pytest.fixture
def cache_dir(tmp_path: Any) -> Iterator[str]:
    d = str(tmp_path / "xc-cache")
    xcache.configure(d)
    yield d
    xcache.configure(None)


def _osc(**kw: float) -> Any:
    p = dict(omega=1.0, gamma=0.1, q0=1.0, p0=0.0)
    p.update(kw)
    return xp.make_problem("oscillator", p)


def _key(method: str, prob: Any, h: float, n: int, record: bool = True) -> str:
    return xcache.key("verify.xrun.integrate", (method, prob, h, n, 0.0, record), {})


def test_key_moves_with_every_input() -> None:
    base = _key("rk4", _osc(), 0.1, 100)
    assert base == _key("rk4", _osc(), 0.1, 100)
    moved = [_key("rk3", _osc(), 0.1, 100), _key("rk4", _osc(), float(np.nextafter(0.1, 1.0)), 100),
             _key("rk4", _osc(), 0.1, 101), _key("rk4", _osc(), 0.1, 100, record=False),
             _key("rk4", _osc(gamma=float(np.nextafter(0.1, 1.0))), 0.1, 100)]
    kicked = _osc()
    kicked.z0 = kicked.z0 * (1 + 2.0 ** -52)
    moved.append(_key("rk4", kicked, 0.1, 100))
    assert base not in moved and len(set(moved)) == len(moved)


def test_read_back_bit_for_bit(cache_dir: str) -> None:
    prob = xp.make_problem("pendulum", dict(gamma=0.1, q0=1.0, p0=0.0))
    first = xrun.integrate("cimp", prob, 0.05, 200, 0.0, record=True)
    assert xcache.STATS == {"hits": 0, "misses": 1, "stored": 1}
    again = xrun.integrate("cimp", prob, 0.05, 200, 0.0, record=True)
    assert xcache.STATS["hits"] == 1
    assert again is not first and np.array_equal(again["traj"], first["traj"]) and again["z"].tobytes() == \
        first["z"].tobytes() and again["newton"] == first["newton"]
    xcache.configure(None)
    fresh = xrun.integrate("cimp", prob, 0.05, 200, 0.0, record=True)
    assert fresh["traj"].tobytes() == again["traj"].tobytes()


def test_unreadable_entry_is_recomputed(cache_dir: str) -> None:
    prob = _osc()
    good = xrun.integrate("heun", prob, 0.1, 50, 0.0, record=True)
    paths = [os.path.join(r, f) for r, _, fs in os.walk(cache_dir) for f in fs if f.endswith(".pkl")]
    assert len(paths) == 1
    with open(paths[0], "r+b") as fh:
        fh.truncate(20)
    again = xrun.integrate("heun", prob, 0.1, 50, 0.0, record=True)
    assert xcache.STATS["hits"] == 0 and xcache.STATS["misses"] == 2
    assert again["traj"].tobytes() == good["traj"].tobytes()


def test_read_only_adds_nothing(tmp_path: Any) -> None:
    d = str(tmp_path / "ro")
    xcache.configure(d, write=False)
    try:
        xrun.integrate("rk4", _osc(), 0.1, 20, 0.0, record=True)
        assert xcache.STATS["stored"] == 0 and not os.path.exists(d)
    finally:
        xcache.configure(None)


def test_unhashable_argument_not_cached(cache_dir: str) -> None:
    calls: List[int] = []

    @xcache.memo
    def f(x: Any) -> int:
        calls.append(1)
        return 1

    f(object())
    f(object())
    f(np.array([None]))
    assert len(calls) == 3 and xcache.STATS == {"hits": 0, "misses": 0, "stored": 0}


def _plant(report: Rep) -> List[str]:
    """Faults on the report's side only; the DISAGREE labels that must name them."""
    names = []
    for c in report["cases"]:
        r = neg.run_of(c, next(r["method"] for r in c["runs"]))
        if c["id"] == "pend-orders":
            r["final_state"] = [x * (1 + 1e-7) for x in r["final_state"]]
        else:
            r["metrics"]["error"]["final_abs"] *= 1 + 1e-3
        names.append(neg.rname(c["id"], r))
    chk = report["cases"][0]["checks"][0]
    chk["passed"] = not chk["passed"]
    names.append("%s / %s / check '%s'" % (report["cases"][0]["id"], chk["method"], chk["name"]))
    return names


def test_planted_after_cache(report_path: str, workdir: str) -> None:
    """A fault planted after the cache is written is still reported, the cache being read."""
    with open(report_path) as fh:
        base = neg.slice_of(json.load(fh), "pend-orders", "pend-table41-g0", "osc-orders")
    wd = os.path.join(workdir, "xcache")
    cache = os.path.join(wd, "cache")
    shutil.rmtree(cache, ignore_errors=True)     # written afresh: a cache of an earlier run would be read
    neg.OPTIONS["cache"] = None
    try:
        rc, lines, out = neg.run_crosscheck(base, wd, "write", extra=["--cache", cache])
        assert rc == 0 and not lines, out
        assert neg.result_of(wd, "write")["cache"]["stored"] > 0
        bad = copy.deepcopy(base)
        names = _plant(bad)
        rc, lines, out = neg.run_crosscheck(bad, wd, "read", extra=["--cache", cache, "--cache-read-only"])
        res = neg.result_of(wd, "read")
        assert res["cache"]["hits"] > 0, res["cache"]
        assert rc == 1, out
        for name in names:
            assert any(ln.startswith("DISAGREE " + name) for ln in lines), (name, lines)
        rc2, lines2, _ = neg.run_crosscheck(bad, wd, "none")
        assert (rc2, lines2) == (rc, lines)
        strip = lambda r: {k: v for k, v in r.items() if k not in ("elapsed_seconds", "timing", "cpu_seconds",
                                                                     "jit_warmup_seconds", "cache", "report")}
        assert strip(res) == strip(neg.result_of(wd, "none"))
    finally:
        xcache.configure(None)
