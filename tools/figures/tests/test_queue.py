"""The workers' shared queue (cli.draw_all): every case is taken by exactly one worker, whatever
the timing, and the results are those of one process. A case index is read as one INDEX-sized
read of a pipe written in chunks of whole indices no longer than PIPE_BUF; the negative control
reads one byte too many and is caught by the same check."""

import os
import pickle
import select
from typing import Any, Callable, List, Optional

from dampfig import cli
from dampfig.render import Ctx


def taken_by_workers(count: int, workers: int,
                     reader: Callable[[int], Optional[int]]) -> List[List[int]]:
    """The indices each of `workers` forked readers takes from a queue of 0..count-1."""
    qr, qw = os.pipe()
    pipes = []
    for _ in range(workers):
        rfd, wfd = os.pipe()
        pid = os.fork()
        if pid == 0:
            os.close(rfd)
            os.close(qw)
            got = []
            while (i := reader(qr)) is not None:
                got.append(i)
            with os.fdopen(wfd, "wb") as f:
                f.write(pickle.dumps(got))
            os._exit(0)
        os.close(wfd)
        pipes.append((pid, rfd))
    os.close(qr)
    cli.fill_queue(qw, list(range(count)))
    out = []
    for pid, rfd in pipes:
        with os.fdopen(rfd, "rb") as f:
            out.append(pickle.loads(f.read()))
        os.waitpid(pid, 0)
    return out


def exactly_once(parts: List[List[int]], count: int) -> bool:
    taken = sorted(i for p in parts for i in p)
    return taken == list(range(count))


def test_chunks_hold_whole_indices() -> None:
    assert cli.QUEUE_CHUNK % cli.INDEX.size == 0
    assert 0 < cli.QUEUE_CHUNK <= select.PIPE_BUF


def test_every_index_taken_once_by_three_workers() -> None:
    count = 5 * cli.QUEUE_CHUNK // cli.INDEX.size + 3  # several chunks, more than a pipe holds
    parts = taken_by_workers(count, 3, cli.next_case)
    assert exactly_once(parts, count)


def test_a_misaligned_reader_is_caught() -> None:
    def reads_one_byte_too_many(queue: int) -> Optional[int]:
        data = os.read(queue, cli.INDEX.size + 1)
        return cli.INDEX.unpack(data[:cli.INDEX.size])[0] if len(data) >= cli.INDEX.size else None
    count = 3 * cli.QUEUE_CHUNK // cli.INDEX.size
    assert not exactly_once(taken_by_workers(count, 2, reads_one_byte_too_many), count)


def test_draw_all_with_workers_equals_one_process(monkeypatch: Any, tmp_path: Any) -> None:
    cases = [{"id": f"case-{i}", "dt_ladder": [0.1, 0.05] if i % 3 else []} for i in range(40)]
    ctx = Ctx(report={"cases": cases}, out=str(tmp_path), formats=["png"])
    monkeypatch.setattr(cli, "draw_case", lambda c, i: [
        (c.report["cases"][i]["id"], "series", [(f"f{i}", "caption", ["q"])], None, 0)])
    one = cli.draw_all(ctx, list(range(40)), 1, [])
    workers: List[int] = []
    two = cli.draw_all(ctx, list(range(40)), 2, workers)
    assert len(workers) == 2
    assert sorted(two) == sorted(one) and len(two) == 40


def test_largest_cases_first() -> None:
    cases = [{"id": f"c{i}", "dt_ladder": [0.1, 0.05] if i in (3, 7) else []} for i in range(9)]
    ctx = Ctx(report={"cases": cases}, out="/nonexistent", formats=["png"])
    assert cli.queue_order(ctx, list(range(9)))[:2] == [3, 7]
