#!/usr/bin/python3
"""Hostile inputs of compare, merge, --costs, --plugin, plot, the shard options and variables,
GITHUB_STEP_SUMMARY and the numeric options (ctest hostile.inputs).

    /usr/bin/python3 tests/hostile/run_hostile.py DAMPSYM [--classify]

tests/hostile/inputs.json lists each input: the command (placeholders below), an optional
environment, how to make the hostile file {H} (a mutation of a real report, or a special file),
and the exit status expected. The real reports are made first by DAMPSYM itself (two fast cases,
unsharded and in two shards, plus shards run with --method and --set), so that every mutation
starts from a report the current schema describes. Every command runs with a 20 s timeout and a
1 GiB address-space limit: a hang or an unbounded read fails the input.

Placeholders: {A} the unsharded report.json, {S1} {S2} its two shards, {S2M} shard 2 run with
--method euler, {S2SET} shard 2 run with --set, {H} the hostile file (from a report, a
repository file (from_file) or special), {OUT} a fresh output
directory, {DIR} a fresh directory holding {H} as report.json.

--classify sorts the failures into the classes of the adversarial pass (crash: internal error or
signal; hang: timeout; unbounded: std::bad_alloc or the memory limit; silently accepted: exit 0
or 1 where 2 was expected; wrong exit: any other status; wrong message: the status expected,
but not the message, e.g. a 300 MiB file read whole and then called malformed) and prints the counts; run against the
binary before the fix, it says what each input found.
"""
import copy
import json
import os
import resource
import subprocess
import sys
import tempfile
from typing import Any, Dict, List, Optional, Tuple

HERE = os.path.dirname(os.path.abspath(__file__))
TIMEOUT_S = 20.0
MEMORY_LIMIT = 1 << 30
Json = Any


def limit_memory() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))


def run(binary: str, args: List[str], env: Optional[Dict[str, str]] = None,
        cwd: Optional[str] = None) -> Tuple[Optional[int], str]:
    """(exit status or None on timeout, stderr)."""
    full_env = dict(os.environ)
    for k in ("TEST_TOTAL_SHARDS", "TEST_SHARD_INDEX", "CI_NODE_TOTAL", "CI_NODE_INDEX",
              "SLURM_ARRAY_TASK_COUNT", "SLURM_ARRAY_TASK_ID", "GITHUB_STEP_SUMMARY"):
        full_env.pop(k, None)
    full_env.update(env or {})
    try:
        p = subprocess.run([binary] + args, env=full_env, cwd=cwd, capture_output=True,
                           timeout=TIMEOUT_S, preexec_fn=limit_memory, stdin=subprocess.DEVNULL)
    except subprocess.TimeoutExpired:
        return None, "timeout"
    return p.returncode, p.stderr.decode("utf-8", "replace")


def make_reports(binary: str, work: str) -> Dict[str, str]:
    """The real reports the mutations start from."""
    sel = ["--filter", "kepler-euler-*", "--time-budget", "0", "-q"]
    runs = {"A": ["--shard", "none"], "S1": ["--shard", "1/2"], "S2": ["--shard", "2/2"],
            "S2M": ["--shard", "2/2", "--method", "euler"],
            "S2SET": ["--shard", "2/2", "--set", "problem.e=0.5"]}
    out = {}
    for name, extra in runs.items():
        d = os.path.join(work, name)
        status, err = run(binary, ["run"] + sel + extra + ["--out", d])
        if status not in (0, 1):
            sys.exit(f"run_hostile: making {name} failed (exit {status}): {err}")
        out[name] = os.path.join(d, "report.json")
    return out


def pointer(doc: Json, path: str) -> Tuple[Json, Any]:
    """The parent of a JSON pointer's target and the last key (an int for arrays)."""
    parts = [p for p in path.split("/")[1:]]
    node = doc
    for p in parts[:-1]:
        node = node[int(p)] if isinstance(node, list) else node[p]
    last: Any = parts[-1]
    return node, int(last) if isinstance(node, list) and last != "-" else last


def resolve(doc: Json, value: Json) -> Json:
    """A value, or "@/pointer" for a copy of that part of the document."""
    if isinstance(value, str) and value.startswith("@/"):
        parent, key = pointer(doc, value[1:])
        return copy.deepcopy(parent[key])
    return value


def mutate(doc: Json, ops: List[List[Any]]) -> Json:
    """set / del / append (a value or "@/ptr") / flip (a boolean), in order."""
    for op in ops:
        parent, key = pointer(doc, op[1])
        if op[0] == "set":
            parent[key] = resolve(doc, op[2])
        elif op[0] == "del":  # (absent: nothing to delete; reports of older builds)
            if key in parent if isinstance(parent, dict) else key < len(parent):
                del parent[key]
        elif op[0] == "append":
            parent[key].append(resolve(doc, op[2]))
        elif op[0] == "flip":
            parent[key] = not parent[key]
        else:
            raise ValueError(f"unknown op {op[0]}")
    return doc


def make_hostile(spec: Dict[str, Any], reports: Dict[str, str], work: str) -> str:
    """The hostile file {H} of one input ("" if the input has none)."""
    path = os.path.join(work, "h.json")
    if "special" in spec:
        kind = spec["special"]
        if kind == "fifo":
            os.mkfifo(path)
        elif kind == "dev_zero":
            return "/dev/zero"
        elif kind == "sparse_300m":
            with open(path, "wb") as f:
                f.truncate(300 << 20)
        elif kind == "text":  # parts: [[text, times], ...]
            with open(path, "w") as f:
                f.write("".join(t * int(n) for t, n in spec["parts"]))
        elif kind == "directory":
            os.mkdir(path)
        return path
    if "from_file" in spec:  # a file of the repository (a method file), mutated
        source = os.path.join(os.path.dirname(os.path.dirname(HERE)), spec["from_file"])
    elif "from" in spec:
        source = reports[spec["from"]]
    else:
        return ""
    with open(source) as f:
        doc = json.load(f)
    with open(path, "w") as f:
        json.dump(mutate(doc, spec.get("ops", [])), f)
    return path


def substitute(text: str, table: Dict[str, str]) -> str:
    for k, v in table.items():
        text = text.replace("{" + k + "}", v)
    return text


def has_pointer(path: str, ptr: str) -> bool:
    """Whether the JSON file at path has a value at the JSON pointer ptr."""
    try:
        with open(path) as f:
            parent, key = pointer(json.load(f), ptr)
        return bool(key in parent if isinstance(parent, dict) else 0 <= key < len(parent))
    except (OSError, ValueError, KeyError, IndexError, TypeError):
        return False


def classify(status: Optional[int], err: str, expected: int) -> str:
    if status is None:
        return "hang"
    if "bad_alloc" in err or "memory" in err.lower() and status == 3:
        return "unbounded"
    if status < 0 or "internal error" in err:
        return "crash"
    if expected == 2 and status in (0, 1):
        return "silently accepted"
    return "wrong message" if status == expected else "wrong exit"


def run_input(binary: str, item: Dict[str, Any], reports: Dict[str, str]) -> Tuple[bool, str]:
    """(passed, description) of one hostile input."""
    with tempfile.TemporaryDirectory(prefix="dampsym-hostile-") as work:
        h = make_hostile(item.get("input", {}), reports, work)
        table = {"A": reports["A"], "S1": reports["S1"], "S2": reports["S2"],
                 "S2M": reports["S2M"], "S2SET": reports["S2SET"], "H": h,
                 "OUT": os.path.join(work, "out"), "DIR": os.path.join(work, "dir")}
        if "{DIR}" in json.dumps(item["cmd"]):
            os.mkdir(table["DIR"])
            os.rename(h, os.path.join(table["DIR"], "report.json"))
        args = [substitute(a, table) for a in item["cmd"]]
        env = {k: substitute(v, table) for k, v in item.get("env", {}).items()}
        status, err = run(binary, args, env, cwd=work)
        ok = status == item["expect"] and "internal error" not in err
        if ok and "stderr_has" in item:
            ok = item["stderr_has"] in err
        if ok and len(err) > int(item.get("stderr_max", 2000)):
            ok = False
        if ok and "out_has" in item:
            ok = has_pointer(os.path.join(table["OUT"], "report.json"), item["out_has"])
        what = "ok" if ok else classify(status, err, int(item["expect"]))
        return ok, f"{item['id']}: exit {status}, expected {item['expect']} ({what}): " + \
            err.strip().replace("\n", " | ")[:300]


def main() -> int:
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    binary = os.path.abspath(sys.argv[1])
    with open(os.path.join(HERE, "inputs.json")) as f:
        items: List[Dict[str, Any]] = json.load(f)["inputs"]
    with tempfile.TemporaryDirectory(prefix="dampsym-hostile-reports-") as work:
        reports = make_reports(binary, work)
        counts: Dict[str, int] = {}
        failed = 0
        for item in items:
            ok, text = run_input(binary, item, reports)
            if not ok:
                failed += 1
                cls = text.split("(")[1].split(")")[0] if "(" in text else "?"
                counts[cls] = counts.get(cls, 0) + 1
                print("FAIL " + text)
            elif "--verbose" in sys.argv:
                print("ok   " + text)
    print(f"{len(items)} hostile inputs, {failed} failed"
          + ("" if not counts else ": " + ", ".join(f"{k} {v}" for k, v in sorted(counts.items()))))
    return 0 if "--classify" in sys.argv or failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
