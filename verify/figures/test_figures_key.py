#!/usr/bin/python3
"""The case key "figures" and --figure-format (docs/case-keys.md "figures",
docs/reports.md "Figures"), through the dampsym binary:

- bad values of "figures" (not false/array, unknown kind, a kind twice, a kind the case cannot
  draw, true) and of --figure-format are rejected with exit 2 and a message naming the file and
  the key (or the option);
- "figures": false keeps no series file and draws nothing for that case, while the other case of
  the same run draws its figures (negative control: the same case without the key draws);
- "figures": ["convergence"] draws only the convergence figure of a case that would also draw its
  time series;
- --figure-format svg writes SVG figures and report.md embeds them; pdf writes PDFs and links
  them.

    test_figures_key.py DAMPSYM WORKDIR"""
from typing import Any

import json
import os
import shutil
import subprocess
import sys

DAMPSYM, WORK = sys.argv[1], sys.argv[2]
problems = []


def case(cid: str, **extra: Any) -> Any:
    c = {"id": cid, "title": "figures key test",
         "problem": {"id": "oscillator", "omega": 1.0, "gamma": 0.1, "q0": 1.0, "p0": 0.0},
         "methods": ["csv1", "cimp"], "t_end": 2.0, "dt_ladder": [0.02, 0.01],
         "output_dt": 0.02, "diagnostics": ["error", "energy"],
         "expect": {"small final error": {"metric": "error.final_abs", "methods": "all",
                                          "le": 1e-2}}}
    c.update(extra)
    return c


def write(cid: str, c: Any) -> Any:
    d = os.path.join(WORK, "cases")
    os.makedirs(d, exist_ok=True)
    p = os.path.join(d, cid + ".json")
    with open(p, "w") as f:
        json.dump(c, f)
    return p


def run(*args: Any) -> Any:
    return subprocess.run([DAMPSYM, *args], capture_output=True, text=True)


def expect(what: Any, ok: bool, detail: Any = "") -> None:
    if not ok:
        problems.append(f"{what}: {detail}")


shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)

# bad values: exit 2, naming file and key
bad = [("figures", True, "figures"), ("figures", "all", "figures"),
       ("figures", ["convergence", "plots"], "figures[1]"),
       ("figures", ["series", "series"], "figures[1]"),
       ("figures", ["stability"], "figures[0]"), ("figures", ["poincare"], "figures[0]"),
       ("figures", [3], "figures[0]")]
for i, (key, value, named) in enumerate(bad):
    cid = f"bad-figures-{i}"
    path = write(cid, case(cid, **{key: value}))
    r = run("run", path, "--out", os.path.join(WORK, "bad"), "-q", "--shard", "none")
    msg = r.stderr + r.stdout
    expect(f"figures = {json.dumps(value)}", r.returncode == 2 and path in msg
           and f"{named}:" in msg, f"exit {r.returncode}, {msg.strip()[:300]}")
# a convergence figure needs a ladder
path = write("bad-figures-ladder", case("bad-figures-ladder", dt_ladder=[0.01],
                                        figures=["convergence"]))
r = run("run", path, "--out", os.path.join(WORK, "bad"), "-q", "--shard", "none")
expect("convergence without a ladder", r.returncode == 2 and "figures[0]" in r.stderr,
       f"exit {r.returncode}, {r.stderr.strip()[:300]}")
for fmt in ("gif", "png,png", ""):
    r = run("run", path, "--figures", "--figure-format", fmt, "--out",
            os.path.join(WORK, "bad"), "-q", "--shard", "none")
    expect(f"--figure-format {fmt!r}", r.returncode == 2 and "--figure-format" in r.stderr,
           f"exit {r.returncode}, {r.stderr.strip()[:300]}")

# off, selected, default in one run
off = write("fig-off", case("fig-off", figures=False))
sel = write("fig-sel", case("fig-sel", figures=["convergence"]))
dflt = write("fig-default", case("fig-default"))
out = os.path.join(WORK, "good")
r = run("run", off, sel, dflt, "--figures", "--out", out, "-q", "--jobs", "2", "--shard", "none")
expect("run --figures", r.returncode == 0, r.stderr[-500:])
if r.returncode == 0:
    with open(os.path.join(out, "figures", "manifest.json")) as f:
        man = json.load(f)["cases"]
    expect("figures: false keeps no series", not os.path.exists(
        os.path.join(out, "series", "fig-off.json")))
    expect("figures: false draws nothing", "fig-off" not in man, str(man.get("fig-off")))
    expect("the default case draws convergence and series (negative control)",
           [f["kind"] for f in man.get("fig-default", [])] == ["convergence", "series"],
           str(man.get("fig-default")))
    expect("figures: [convergence] draws only that", [f["kind"] for f in man.get("fig-sel", [])]
           == ["convergence"], str(man.get("fig-sel")))
    with open(os.path.join(out, "report.json")) as f:
        rep = json.load(f)
    keys = {c["id"]: c.get("figures") for c in rep["cases"]}
    expect("report.json carries the key", keys == {"fig-off": False, "fig-sel": ["convergence"],
                                                   "fig-default": None}, str(keys))

# formats
for fmt, ext, embedded in (("svg", ".svg", True), ("pdf", ".pdf", False)):
    r = run("plot", out, "--figure-format", fmt)
    expect(f"plot --figure-format {fmt}", r.returncode == 0, r.stderr[-300:])
    files = sorted(os.listdir(os.path.join(out, "figures")))
    expect(f"{fmt} files", any(f.endswith(ext) for f in files)
           and not any(f.endswith(".png") for f in files), str(files))
    with open(os.path.join(out, "report.md")) as f:
        md = f.read()
    img = f"![fig-default: convergence and work-precision](figures/fig-default-convergence{ext})"
    link = f"[fig-default: convergence and work-precision](figures/fig-default-convergence{ext})"
    expect(f"report.md {'embeds' if embedded else 'links'} {fmt}",
           (img in md) if embedded else (link in md and img not in md), md[:0])

for p in problems:
    print("FAIL", p)
print(f"test_figures_key: {len(problems)} failures")
sys.exit(1 if problems else 0)
