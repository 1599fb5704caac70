#!/usr/bin/python3
"""Hostile inputs of compare, merge, --costs, --plugin and the plugins' own faults, plot, the
shard options and variables, GITHUB_STEP_SUMMARY, case ids (--set id=, clashing case files),
--max-memory, method files and the numeric options (ctest hostile.inputs).

    /usr/bin/python3 tests/hostile/run_hostile.py DAMPSYM [--plugins DIR] [--example-plugin LIB]
                                                  [--jobs N] [--classify] [--verbose]

tests/hostile/inputs.json lists each input: the command (placeholders below), an optional
environment, how to make the hostile file {H} (a mutation of a real report or of a repository
file, a JSON value, or a special file), extra files, the exit status expected, and its class: the
defect the input would show if it were not handled (crash, hang, unbounded, silently-accepted,
wrong-exit; "control" for inputs that must succeed). The real reports are made first by DAMPSYM
itself (two fast cases, unsharded and in two shards, plus shards run with --method and --set), so
that every mutation starts from a report the current schema describes. Every command runs with a
20 s timeout and a 1 GiB address-space limit: a hang or an unbounded read fails the input.

Placeholders: {A} the unsharded report.json, {S1} {S2} its two shards, {S2M} shard 2 run with
--method euler, {S2SET} shard 2 run with --set, {H} the hostile file, {X:NAME} an extra file of
the input, {OUT} a fresh output directory, {DIR} a fresh directory holding {H} as report.json,
{PLUGINS} the directory of the bad plugins (tests/plugins; --plugins), {EXAMPLE_PLUGIN} the
example plugin, {REPO} the repository. Inputs naming a plugin placeholder need those options.

The runner prints, per class, how many inputs it has and how many failed, and sorts each failure
into the class it showed (crash: internal error or signal; hang: timeout; unbounded:
std::bad_alloc or the memory limit; silently accepted: exit 0 or 1 where 2 was expected; wrong
exit: any other status; wrong message: the status expected, but not the message). --classify
exits 0 whatever failed: run against the binary before a fix, it says what each input found.
--jobs N runs N inputs at once (default 2); the order of the output does not depend on it.
"""
import concurrent.futures
import copy
import json
import os
import resource
import subprocess
import sys
import tempfile
from typing import Any, Dict, List, Optional, Tuple

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
CLASSES = ("crash", "hang", "unbounded", "silently-accepted", "wrong-exit", "control")
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
    """set / del / append (a value or "@/ptr") / flip (a boolean) / repeat (a string: prefix, text
    repeated n times, optional suffix), in order."""
    for op in ops:
        parent, key = pointer(doc, op[1])
        if op[0] == "set":
            parent[key] = resolve(doc, op[2])
        elif op[0] == "repeat":
            parent[key] = str(op[2]) + str(op[3]) * int(op[4]) + (str(op[5]) if len(op) > 5 else "")
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
    if "json" in spec:  # a JSON value (a case file, a --costs file)
        with open(path, "w") as f:
            json.dump(mutate(spec["json"], spec.get("ops", [])), f)
        return path
    if "from_file" in spec:  # a file of the repository (a method or case file), mutated
        source = os.path.join(REPO, spec["from_file"])
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


def value_at(path: str, ptr: str) -> Json:
    """The value at the JSON pointer ptr of the JSON file at path (None if there is none)."""
    try:
        with open(path) as f:
            parent, key = pointer(json.load(f), ptr)
        return parent[key]
    except (OSError, ValueError, KeyError, IndexError, TypeError):
        return None


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


def write_extra(item: Dict[str, Any], work: str, table: Dict[str, str]) -> None:
    """The input's extra files ({X:NAME}), JSON values written into the work directory."""
    for name, value in item.get("extra", {}).items():
        path = os.path.join(work, name)
        with open(path, "w") as f:
            json.dump(value, f)
        table["X:" + name] = path


def judge(item: Dict[str, Any], status: Optional[int], err: str, out: str) -> bool:
    """Whether the input was handled as expected: status, no internal error, the message (its
    text, its size, one line), and the output directory (a value present or equal to or containing
    a given one, a file absent)."""
    ok = status == item["expect"] and "internal error" not in err
    if ok and "stderr_has" in item:
        ok = all(t in err for t in ([item["stderr_has"]] if isinstance(item["stderr_has"], str)
                                    else item["stderr_has"]))
    if ok and "stderr_lacks" in item:
        ok = item["stderr_lacks"] not in err
    if ok and len(err) > int(item.get("stderr_max", 2000)):
        ok = False
    if ok and item.get("one_line"):
        ok = len(err.strip().splitlines()) == 1
    if ok and "out_has" in item:
        ok = has_pointer(os.path.join(out, "report.json"), item["out_has"])
    if ok and "out_absent" in item:
        ok = not os.path.exists(os.path.join(out, item["out_absent"]))
    for ptr, want in item.get("out_value", {}).items():
        ok = ok and value_at(os.path.join(out, "report.json"), ptr) == want
    for ptr, text in item.get("out_contains", {}).items():
        ok = ok and text in str(value_at(os.path.join(out, "report.json"), ptr))
    return ok


def run_input(binary: str, item: Dict[str, Any], reports: Dict[str, str],
              places: Dict[str, str]) -> Tuple[bool, str]:
    """(passed, description) of one hostile input."""
    with tempfile.TemporaryDirectory(prefix="dampsym-hostile-") as work:
        h = make_hostile(item.get("input", {}), reports, work)
        table = dict(places)
        table.update({"A": reports["A"], "S1": reports["S1"], "S2": reports["S2"],
                      "S2M": reports["S2M"], "S2SET": reports["S2SET"], "H": h,
                      "OUT": os.path.join(work, "out"), "DIR": os.path.join(work, "dir")})
        write_extra(item, work, table)
        if "{DIR}" in json.dumps(item["cmd"]):
            os.mkdir(table["DIR"])
            os.rename(h, os.path.join(table["DIR"], "report.json"))
        args = [substitute(a, table) for a in item["cmd"]]
        env = {k: substitute(v, table) for k, v in item.get("env", {}).items()}
        status, err = run(binary, args, env, cwd=work)
        ok = judge(item, status, err, table["OUT"])
        what = "ok" if ok else classify(status, err, int(item["expect"]))
        return ok, f"{item['id']}: exit {status}, expected {item['expect']} ({what}): " + \
            err.strip().replace("\n", " | ")[:300]


def option(name: str) -> str:
    """The value of a --name VALUE option on the command line ("" if absent)."""
    return sys.argv[sys.argv.index(name) + 1] if name in sys.argv[:-1] else ""


def check_items(items: List[Dict[str, Any]], places: Dict[str, str]) -> None:
    """Every input has a known class and a unique id; plugin inputs need their options."""
    ids = set()
    for item in items:
        if item.get("class") not in CLASSES:
            sys.exit(f"run_hostile: {item.get('id')}: class must be one of {CLASSES}")
        if item["id"] in ids:
            sys.exit(f"run_hostile: {item['id']}: given twice")
        ids.add(item["id"])
        text = json.dumps(item["cmd"])
        for p in ("PLUGINS", "EXAMPLE_PLUGIN"):
            if "{" + p + "}" in text and not places[p]:
                sys.exit(f"run_hostile: {item['id']} needs --{p.lower().replace('_', '-')}")


def report_counts(items: List[Dict[str, Any]], failures: Dict[str, List[str]]) -> int:
    """Prints the inputs and failures per class and the failures by what they showed."""
    shown: Dict[str, int] = {}
    for item in items:
        for text in failures.get(item["id"], []):
            cls = text.split("(")[1].split(")")[0] if "(" in text else "?"
            shown[cls] = shown.get(cls, 0) + 1
    for cls in CLASSES:
        n = sum(1 for i in items if i["class"] == cls)
        bad = sum(1 for i in items if i["class"] == cls and i["id"] in failures)
        print(f"  {cls:18} {n:4} inputs, {bad} failed")
    failed = len(failures)
    print(f"{len(items)} hostile inputs, {failed} failed"
          + ("" if not shown else ": " + ", ".join(f"{k} {v}" for k, v in sorted(shown.items()))))
    return failed


def main() -> int:
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    binary = os.path.abspath(sys.argv[1])
    places = {k: os.path.abspath(v) if v else "" for k, v in
              (("PLUGINS", option("--plugins")), ("EXAMPLE_PLUGIN", option("--example-plugin")),
               ("REPO", REPO))}
    with open(os.path.join(HERE, "inputs.json")) as f:
        items: List[Dict[str, Any]] = json.load(f)["inputs"]
    check_items(items, places)
    failures: Dict[str, List[str]] = {}
    jobs = int(option("--jobs") or "2")  # the inputs are independent; each is one dampsym process
    with tempfile.TemporaryDirectory(prefix="dampsym-hostile-reports-") as work:
        reports = make_reports(binary, work)
        with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
            results = list(pool.map(lambda i: run_input(binary, i, reports, places), items))
        for item, (ok, text) in zip(items, results):
            if not ok:
                failures[item["id"]] = [text]
                print("FAIL " + text)
            elif "--verbose" in sys.argv:
                print("ok   " + text)
    failed = report_counts(items, failures)
    return 0 if "--classify" in sys.argv or failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
