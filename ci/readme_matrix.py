#!/usr/bin/python3
"""Regenerate (or check) the method x property matrix in README.md (docs/matrix.md).

    /usr/bin/python3 ci/readme_matrix.py [--dampsym build/dampsym] [--check]

Runs `dampsym matrix --jobs 2` for the built-in methods and replaces the table and legend between
the README's `<!-- matrix:begin -->` and `<!-- matrix:end -->` markers with those of matrix.md.
With --check nothing is written: exit 1 when the README's table differs from the generated one.
Exit 2 when dampsym fails (its matrix exit status 1 included: the README shows an agreeing table).
"""
import argparse
import pathlib
import subprocess
import sys
import tempfile

BEGIN, END = "<!-- matrix:begin -->", "<!-- matrix:end -->"


def generated_block(dampsym: str) -> str:
    with tempfile.TemporaryDirectory() as out:
        r = subprocess.run([dampsym, "matrix", "--jobs", "2", "--quiet", "--out", out],
                           capture_output=True, text=True)
        if r.returncode != 0:
            sys.stderr.write(r.stdout + r.stderr)
            sys.exit(2)
        md = pathlib.Path(out, "matrix.md").read_text(encoding="utf-8").splitlines()
    table = [line for line in md if line.startswith("|")]
    legend = [line for line in md if line.startswith("✓ claimed")]
    legend = [line.replace(" Criteria:", "") for line in legend]
    return "\n".join(table) + "\n\n" + "\n".join(legend) + "\n"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    root = pathlib.Path(__file__).resolve().parent.parent
    ap.add_argument("--dampsym", default=str(root / "build" / "dampsym"))
    ap.add_argument("--readme", default=str(root / "README.md"))
    ap.add_argument("--check", action="store_true")
    a = ap.parse_args()
    readme = pathlib.Path(a.readme)
    text = readme.read_text(encoding="utf-8")
    if text.count(BEGIN) != 1 or text.count(END) != 1 or text.index(BEGIN) > text.index(END):
        sys.stderr.write(f"{readme}: expected one {BEGIN} ... {END} block\n")
        return 2
    head, rest = text.split(BEGIN, 1)
    old, tail = rest.split(END, 1)
    new = "\n" + generated_block(a.dampsym)
    if a.check:
        if old != new:
            sys.stderr.write(f"{readme}: the matrix table is stale; run "
                             "/usr/bin/python3 ci/readme_matrix.py\n")
            return 1
        return 0
    readme.write_text(head + BEGIN + new + END + tail, encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
