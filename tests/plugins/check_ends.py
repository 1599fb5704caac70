#!/usr/bin/python3
"""A plugin that ends dampsym's process from inside its own code (tests/plugins/bad_plugin.c,
EXIT_STEP, QUICK_EXIT_STEP, CRASH_STEP, EXIT_ENTRY; docs/plugins.md "Containment"): the exit status
is never 0 (3 for exit/quick_exit; the crash signal, or the sanitizer's status, for a crash), the
message names the plugin, and no report is written — also when the output directory held a report
of an earlier successful run, which must not pass for this run's.

    /usr/bin/python3 tests/plugins/check_ends.py DAMPSYM LIB KIND CASE OUT_DIR   (exit 0 = as expected)

KIND: exit, quick_exit, crash (a `run` of CASE) or entry (`methods --plugin LIB`).
"""
import os
import shutil
import subprocess
import sys
from typing import List


def main(argv: List[str]) -> int:
    if len(argv) != 6:
        sys.exit(__doc__)
    dampsym, lib, kind, case, out = argv[1:]
    shutil.rmtree(out, ignore_errors=True)
    if kind == "entry":
        args = [dampsym, "methods", "--plugin", lib]
    else:
        args = [dampsym, "run", case, "--plugin", lib, "--out", out, "-q", "--jobs", "1"]
    p = subprocess.run(args, capture_output=True, timeout=60, stdin=subprocess.DEVNULL)
    err = p.stderr.decode("utf-8", "replace")
    where = "entry" if kind == "entry" else "method 'bad-ends-process'"
    said = "crashed" if kind == "crash" else "ended the process"
    results = {
        "exit status not 0": p.returncode != 0,
        "exit status 3 (exit, quick_exit)": kind == "crash" or p.returncode == 3,
        "the message names the plugin": f"plugin {where}" in err and said in err,
        "no report written": not os.path.exists(os.path.join(out, "report.json")),
    }
    for k, v in results.items():
        print(("ok   " if v else "FAIL ") + k)
    print(f"exit status {p.returncode}; stderr: {err.strip()[:500]}")
    return 0 if all(results.values()) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
