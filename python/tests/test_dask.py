"""dampsym.dask.run on a LocalCluster of worker processes: the shards' merged report equals the
unsharded run byte for byte before its provenance (a few small cases; seconds)."""

from __future__ import annotations

import pathlib

import pytest

import dampsym
import dampsym.dask
from conftest import before_provenance

distributed = pytest.importorskip("distributed")

SELECT = ["--filter", "stress-threshold-*"]


def test_merged_shards_equal_the_unsharded_run(tmp_path: pathlib.Path) -> None:
    whole = tmp_path / "whole"
    done = dampsym.cli(["run", "--suite", "stress", *SELECT, "--out", str(whole), "--quiet"])
    assert done.returncode == 0, done.stderr
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            merged = dampsym.dask.run("stress", client, shards=3, select=SELECT,
                                      out=str(tmp_path / "merged"))
    assert before_provenance(merged.text) == \
        before_provenance((whole / "report.json").read_text())
    assert (tmp_path / "merged" / "report.md").is_file()
    assert len(merged["cases"]) >= 3  # every shard had cases to run


def test_a_bad_selection_is_the_shards_message() -> None:
    class Inline:
        """A client that runs the tasks here (the error path needs no cluster)."""

        def scheduler_info(self) -> dict[str, dict[str, int]]:
            return {"workers": {"a": 1}}

        def map(self, f, items, **kw):  # type: ignore[no-untyped-def]
            kw.pop("pure")
            return [f(i, **kw) for i in items]

        def gather(self, xs):  # type: ignore[no-untyped-def]
            return xs

    with pytest.raises(dampsym.InputError, match="shard 1/1: .*no-such-case"):
        dampsym.dask.run("stress", Inline(), select=["--filter", "no-such-case"])
