"""Suites over a Dask cluster (docs/python.md "Suites over a cluster").

``run(suite, client)`` is ``dampsym run --suite SUITE`` cut into shards, one task per shard: each
worker runs ``dampsym run --shard K/N`` in its own process (the existing sharding, docs/ci.md:
cases dealt out by their measured cost) and returns its report.json text; the client writes the
shard reports into a temporary directory and merges them with ``dampsym merge`` (the same merge,
which refuses shards of different builds or selections). The merged report equals the unsharded
run's byte for byte before ``"provenance"``.

Any ``distributed.Client`` will do: a ``LocalCluster``, a Slurm or PBS cluster from dask-jobqueue,
a Kubernetes cluster from dask-kubernetes. The workers need the same dampsym build (the merge
refuses reports of different commits) and the case files (``cases_dir``, or the build's default).
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Sequence
from typing import Any

from . import InputError, OutputError, Report, _report, cli


def _run_shard(index: int, count: int, args: Sequence[str]) -> tuple[int, str, str]:
    """On a worker: one shard of the selection; (exit status, report.json text, stderr)."""
    with tempfile.TemporaryDirectory(prefix="dampsym-shard-") as out:
        done = cli(["run", *args, "--shard", f"{index}/{count}", "--out", out, "--quiet"])
        text = ""
        if done.returncode in (0, 1):
            with open(os.path.join(out, "report.json"), encoding="utf-8") as f:
                text = f.read()
        return done.returncode, text, done.stderr


def _raise_for(status: int, what: str, stderr: str) -> None:
    message = f"{what}: " + (stderr.strip().removeprefix("dampsym: ") or f"exit status {status}")
    raise (InputError if status == 2 else OutputError)(message)


def _workers(client: Any) -> int:
    return max(1, len(client.scheduler_info().get("workers", {})))


def run(suite: str, client: Any, *, shards: int | None = None, select: Sequence[str] = (),
        cases_dir: str | None = None, out: str | None = None) -> Report:
    """Runs the suite's cases as ``shards`` tasks (default: one per worker) on the client's
    cluster and returns the merged report.json (written to ``out`` too when given, with report.md
    and junit.xml). ``select``: more selection options of ``dampsym run`` (e.g. ``["--filter",
    "osc-*"]``). Raises InputError / OutputError with the message of a shard or of the merge."""
    count = shards if shards is not None else _workers(client)
    if count < 1:
        raise InputError(f"shards: must be >= 1, got {count}")
    args = ["--suite", suite, *select]
    if cases_dir is not None:
        args = ["--cases", cases_dir, *args]
    futures = client.map(_run_shard, range(1, count + 1), count=count, args=args, pure=False)
    results: list[tuple[int, str, str]] = client.gather(futures)
    with tempfile.TemporaryDirectory(prefix="dampsym-merge-") as work:
        dirs = []
        for k, (status, text, stderr) in enumerate(results, start=1):
            if status not in (0, 1):
                _raise_for(status, f"shard {k}/{count}", stderr)
            d = os.path.join(work, f"shard-{k}")
            os.makedirs(d)
            with open(os.path.join(d, "report.json"), "w", encoding="utf-8") as f:
                f.write(text)
            dirs.append(d)
        merged = out or os.path.join(work, "merged")
        done = cli(["merge", merged, *dirs, "--quiet"])
        if done.returncode not in (0, 1):
            _raise_for(done.returncode, "merge", done.stderr)
        with open(os.path.join(merged, "report.json"), encoding="utf-8") as f:
            return _report(f.read(), done.returncode)
