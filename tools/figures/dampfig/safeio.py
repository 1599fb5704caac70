"""How tools/figures/plot.py reads its inputs and writes its outputs (docs/reports.md
"Figures"): every read is of a regular file (a symbolic link is not followed) of bounded size,
checked before parsing; every output is a plain name inside the report directory (a case id only
through output_name); a file is replaced atomically (FILE.dampsym-tmp, then renamed) and only
when it is a regular file or absent; and only files listed in the directory's manifest
(.dampsym-manifest, written by dampsym's earlier runs) are ever removed.

Plain Python (os, json, re, stat): no matplotlib, so verify/figures/test_outputs.py tests it
without drawing."""

import errno
import json
import os
import re
import stat
from typing import Any, Dict, List, Optional

# Size limits checked before a file is parsed: JSON in Python takes about 10 bytes of memory per
# byte of file (a 400 MB series file took 3.7 GB). A default-suite report.json is about 2 MB, and
# all its series files together (--figures) about 33 MB (docs/reports.md: an orbit keeps at most
# 40 000 values, a time series at most 2000 points).
REPORT_LIMIT = 256 << 20
SERIES_LIMIT = 64 << 20
MANIFEST_LIMIT = 4 << 20

TMP_SUFFIX = ".dampsym-tmp"  # as write_file_atomic (src/harness/report/report.cpp)
MANIFEST = ".dampsym-manifest"  # as src/harness/figures/figures.cpp
MANIFEST_HEADER = "# dampsym: the files it wrote here; its next run into this directory removes them\n"

# A case id (valid_case_id, src/harness/case/case.cpp): at most 100 characters of A-Z a-z 0-9 . _ -,
# the first a letter or digit. A plain file name: the same characters, any length up to 255.
CASE_ID = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]{0,99}")
PLAIN_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]{0,254}")


class InputProblem(Exception):
    """Bad input (a malformed or oversized file, a directory that is a file): exit 2."""


class OutputProblem(Exception):
    """An output that cannot or must not be written (a symbolic link in its place): exit 3."""


def output_name(case_id: Any, suffix: str) -> str:
    """The file name of a case's output: the id (a valid case id) + suffix; any other id is
    refused, so a name never leads out of its directory (no '/', no '..', not absolute)."""
    if not isinstance(case_id, str) or not CASE_ID.fullmatch(case_id):
        raise InputProblem(f"{str(case_id)[:80]!r} is not a valid case id: it names no file")
    return case_id + suffix


def read_bounded(path: str, limit: int) -> bytes:
    """The bytes of `path`, a regular file (not a symbolic link) of at most `limit` bytes;
    FileNotFoundError if absent, InputProblem naming the path otherwise."""
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_CLOEXEC)
    except FileNotFoundError:
        raise
    except OSError as e:
        why = "is a symbolic link (only a regular file is read)" if e.errno == errno.ELOOP else e.strerror
        raise InputProblem(f"{path}: {why}") from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise InputProblem(f"{path}: is not a regular file")
        if st.st_size > limit:
            raise InputProblem(f"{path}: too large ({st.st_size} bytes; the limit is {limit})")
        chunks, total = [], 0
        # the whole file in one read where it is as large as stat said (one buffer: chunks
        # joined afterwards were a copy of every series file); then until the end, bounded
        size = min(st.st_size + 1, limit + 1)
        while True:
            b = os.read(fd, size)
            size = 1 << 20
            if not b:
                break
            total += len(b)
            if total > limit:
                raise InputProblem(f"{path}: too large (it grew while read; limit {limit})")
            chunks.append(b)
        return b"".join(chunks)
    finally:
        os.close(fd)


def load_json(path: str, limit: int) -> Any:
    """read_bounded, parsed; InputProblem naming the path if it is not JSON."""
    data = read_bounded(path, limit)
    try:
        return json.loads(data)
    except (ValueError, RecursionError) as e:
        raise InputProblem(f"{path}: malformed JSON ({str(e)[:100]})") from None


def own_directory(path: str) -> None:
    """`path` as one of dampsym's directories (DIR/figures): created if absent; InputProblem if
    it is a file or a symbolic link (which would lead the figures out of DIR)."""
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        os.mkdir(path)
        return
    if stat.S_ISLNK(st.st_mode):
        raise InputProblem(f"{path}: is a symbolic link, not a directory")
    if not stat.S_ISDIR(st.st_mode):
        raise InputProblem(f"{path}: exists and is not a directory")


def check_replaceable(path: str) -> None:
    """OutputProblem naming `path` unless it is absent or a regular file."""
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        return
    if not stat.S_ISREG(st.st_mode):
        kind = ("a symbolic link" if stat.S_ISLNK(st.st_mode) else
                "a directory" if stat.S_ISDIR(st.st_mode) else "not a regular file")
        raise OutputProblem(f"{path}: exists and is {kind}: only a regular file is replaced "
                            "(remove it or choose another directory)")


def create_fresh(path: str) -> int:
    """A new file at `path` for writing: never through a symbolic link, never into an existing
    file (a leftover of that name is unlinked first, which removes the name only)."""
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | os.O_CLOEXEC
    try:
        return os.open(path, flags, 0o666)
    except FileExistsError:
        os.unlink(path)
        return os.open(path, flags, 0o666)


def write_atomic(path: str, data: bytes) -> None:
    """Replaces `path` (absent or a regular file) by `data`: written to path + TMP_SUFFIX, then
    renamed over it. OutputProblem naming the path if it cannot."""
    check_replaceable(path)
    tmp = path + TMP_SUFFIX
    try:
        fd = create_fresh(tmp)
        try:
            view = memoryview(data)
            while view:
                view = view[os.write(fd, view):]
        finally:
            os.close(fd)
        os.rename(tmp, path)
    except OSError as e:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise OutputProblem(f"{path}: cannot write: {e.strerror}") from None


def listed(directory: str) -> List[str]:
    """The plain names the directory's manifest lists (any other line is ignored)."""
    try:
        text = read_bounded(os.path.join(directory, MANIFEST), MANIFEST_LIMIT)
    except (OSError, InputProblem):
        return []
    lines = text.decode("utf-8", "replace").splitlines()
    return [n for n in lines if PLAIN_NAME.fullmatch(n)]


def remove_listed(directory: str) -> None:
    """Removes the regular files the manifest lists (and their temporary files), then starts an
    empty manifest: what dampsym's earlier runs wrote goes, nothing else."""
    for name in listed(directory):
        for n in (name, name + TMP_SUFFIX):
            p = os.path.join(directory, n)
            try:
                if stat.S_ISREG(os.lstat(p).st_mode):
                    os.unlink(p)
            except FileNotFoundError:
                pass
    write_manifest(directory, [])


def write_manifest(directory: str, names: List[str]) -> None:
    write_atomic(os.path.join(directory, MANIFEST),
                 (MANIFEST_HEADER + "".join(n + "\n" for n in names)).encode())


def note_written(directory: str, name: str) -> None:
    """Adds `name` to the manifest before the file is written (so a run killed while writing it
    still removes it next time). One O_APPEND write per name: workers may add at once."""
    p = os.path.join(directory, MANIFEST)
    try:
        fd = os.open(p, os.O_WRONLY | os.O_APPEND | os.O_NOFOLLOW | os.O_CLOEXEC)
    except OSError as e:
        raise OutputProblem(f"{p}: cannot write: {e.strerror}") from None
    try:
        os.write(fd, (name + "\n").encode())
    finally:
        os.close(fd)


def validate_ids(report: Any, path: str) -> Optional[str]:
    """What is wrong with the ids of report.json's cases (a valid case id each, each once), or
    None."""
    if not isinstance(report, dict) or not isinstance(report.get("cases"), list):
        return f"{path}: cases: missing or not an array (not a dampsym report)"
    seen = set()
    for i, c in enumerate(report["cases"]):
        cid = c.get("id") if isinstance(c, dict) else None
        if not isinstance(cid, str) or not CASE_ID.fullmatch(cid):
            return (f"{path}: cases[{i}].id: {str(cid)[:80]!r} is not a valid case id (at most "
                    "100 characters of A-Z a-z 0-9 . _ -, starting with a letter or digit)")
        if cid in seen:
            return f"{path}: cases[{i}].id: {cid!r} listed twice"
        seen.add(cid)
    return None


# The keys of a case that plot.py reads outside a figure's own error handling (planning, the
# gallery, the workers' order), with their types (schema/report.schema.json); what a figure reads
# deeper is its own: a figure that cannot be drawn from it is reported and the others drawn.
CASE_KEYS: Dict[str, type] = {"title": str, "source": str, "dt_ladder": list, "checks": list, "runs": list,
             "method_metrics": dict}
ITEM_KEYS: Dict[str, Dict[str, type]] = {"checks": {"name": str, "passed": bool},
                                         "runs": {"method": str, "dt": float}}


def type_error(value: Any, want: type) -> Optional[str]:
    """None if value is a `want` (float: any number, not a bool), else what it should be."""
    ok = (isinstance(value, (int, float)) and not isinstance(value, bool)) if want is float \
        else isinstance(value, want)
    names = {str: "a string", list: "an array", dict: "an object", bool: "true or false",
             float: "a number"}
    return None if ok else f"missing or not {names[want]}"


def case_error(c: Dict[str, Any]) -> Optional[str]:
    """What is wrong with the keys CASE_KEYS of one case record, as "key: problem", or None."""
    for key, kind in CASE_KEYS.items():
        problem = type_error(c.get(key), kind)
        if problem:
            return f"{key}: {problem}"
    for j, h in enumerate(c["dt_ladder"]):
        if type_error(h, float):
            return f"dt_ladder[{j}]: not a number"
    for key, fields in ITEM_KEYS.items():
        for j, item in enumerate(c[key]):
            for f, want in fields.items():
                problem = type_error(item.get(f) if isinstance(item, dict) else None, want)
                if problem:
                    return f"{key}[{j}].{f}: {problem}"
    for m, v in c["method_metrics"].items():
        if not isinstance(v, dict):
            return f"method_metrics.{m}: not an object"
    fig = c.get("figures", None)
    if not (fig is None or fig is False or
            isinstance(fig, list) and all(isinstance(k, str) for k in fig)):
        return "figures: not false or an array of figure kinds"
    return None


def validate_report(report: Any, path: str) -> Optional[str]:
    """What is wrong with report.json for drawing, as one line naming the file and key, or None:
    the case ids (validate_ids), the keys of each case that plot.py reads (case_error), and
    timings.cases (an array of objects, when present): 24 ms for a default-suite report, where
    the whole schema (jsonschema) took 1 s."""
    problem = validate_ids(report, path)
    if problem:
        return problem
    for i, c in enumerate(report["cases"]):
        problem = case_error(c)
        if problem:
            return f"{path}: cases[{i}].{problem}"
    timings = report.get("timings", {})
    if not isinstance(timings, dict) or not isinstance(timings.get("cases", []), list) or \
            not all(isinstance(t, dict) for t in timings.get("cases", [])):
        return f"{path}: timings.cases: not an array of objects"
    return None
