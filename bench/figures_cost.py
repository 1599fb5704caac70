#!/usr/bin/python3
"""The cost of figures (docs/reports.md "Cost": a run with figures costs at most 2x one without): the default suite with
`--figures` against the same suite without, side by side in one run.

    /usr/bin/python3 bench/figures_cost.py build/dampsym [--rounds 3] [--jobs 2] [--out-json F]

Each round runs `dampsym run --jobs J` and then `dampsym run --jobs J --figures` (series kept, every
figure drawn, report.md written again) into fresh directories and takes their wall times; the ratio
is that of the medians over the rounds. Prints the table and exits 1 when the ratio exceeds the
bound (2), 2 on a usage error or a bad suite (exit 2 of dampsym)."""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from typing import List

BOUND = 2.0


def timed(cmd: List[str]) -> float:
    t = time.perf_counter()
    r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    wall = time.perf_counter() - t
    if r.returncode in (2, 3):  # a bad input or an output/figure failure: not a timing
        sys.stderr.write(r.stderr)
        raise SystemExit(f"figures_cost.py: {' '.join(cmd)}: exit {r.returncode}")
    return wall


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dampsym")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--out-json", default="")
    a = ap.parse_args()
    if a.rounds < 1 or a.jobs < 1 or not os.access(a.dampsym, os.X_OK):
        print("figures_cost.py: give an executable dampsym, --rounds >= 1, --jobs >= 1",
              file=sys.stderr)
        return 2
    plain: List[float] = []
    figures: List[float] = []
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(a.rounds):
            base = [a.dampsym, "run", "--jobs", str(a.jobs)]
            plain.append(timed(base + ["--out", os.path.join(tmp, f"plain{k}")]))
            figures.append(timed(base + ["--out", os.path.join(tmp, f"fig{k}"), "--figures"]))
        with open(os.path.join(tmp, f"fig{a.rounds - 1}", "figures", "manifest.json")) as f:
            count = sum(len(v) for v in json.load(f)["cases"].values())
    ratio = statistics.median(figures) / statistics.median(plain)
    ok = ratio <= BOUND
    out = {"jobs": a.jobs, "rounds": a.rounds, "plain_seconds": plain,
           "figures_seconds": figures, "figures": count, "ratio": ratio, "bound": BOUND,
           "pass": ok}
    print(f"default suite, --jobs {a.jobs}, {a.rounds} rounds (median wall s): without figures "
          f"{statistics.median(plain):.2f}, with --figures {statistics.median(figures):.2f} "
          f"({count} figures): {ratio:.2f}x (bound {BOUND:g}x) {'pass' if ok else 'FAIL'}")
    if a.out_json:
        with open(a.out_json, "w") as f:
            json.dump(out, f, indent=1)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
