#!/usr/bin/env python3
"""Renders dampsym's Markdown reports with a real GFM renderer (cmark-gfm, Debian package
cmark-gfm) and checks what a reader on GitHub or GitLab would see:

- every table of the source (a header row, then a delimiter row `|---|...`) comes out as a table,
  at the same line, with the same number of rows and of columns;
- every row of it has exactly the intended cells: each source row is rendered again as the header
  of a one-row table whose delimiter row has the intended number of cells, and GFM makes a table
  of that only if the row splits into that many cells (an unescaped `|` in a cell, even inside a
  code span, adds a cell; GFM silently drops the excess of a body row, so the table alone does
  not show it);
- every relative link and image (Markdown or inline HTML) resolves: a file next to the document
  exists, and a `#fragment` names an `<a id>` or a heading of the target document.

Usage: check_gfm.py FILE_OR_DIR... [--optional FILE]...   (a DIR stands for its report.md,
figures.md and crosscheck.md, those present; report.md must be). Exit 0 all good, 1 a problem
(each named with file:line), 2 usage or no cmark-gfm. --self-test plants the defects this must
catch and checks that each is caught (and that the escaped forms pass).
"""
import os
import re
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET
from typing import Dict, List, Optional, Set, Tuple

NS = "{http://commonmark.org/xml/1.0}"
DELIM = re.compile(r"^\s*\|?\s*:?-+:?\s*(\|\s*:?-+:?\s*)*\|?\s*$")
FENCE = re.compile(r"^\s{0,3}(```|~~~)")


def render_xml(text: str) -> ET.Element:
    """The document tree cmark-gfm makes of `text` (tables and autolinks on, source positions)."""
    out = subprocess.run(["cmark-gfm", "-e", "table", "-e", "autolink", "--sourcepos",
                          "-t", "xml"], input=text.encode(), capture_output=True, check=True)
    return ET.fromstring(out.stdout)


def start_line(node: ET.Element) -> int:
    return int(node.get("sourcepos", "0:0").split(":")[0])


def source_tables(lines: List[str]) -> List[Tuple[int, int, List[int]]]:
    """(header line, intended columns, line numbers of header and body rows), 1-based, outside
    fenced code blocks."""
    tables = []
    fenced = False
    i = 0
    while i < len(lines):
        if FENCE.match(lines[i]):
            fenced = not fenced
        elif (not fenced and i + 1 < len(lines) and lines[i].lstrip().startswith("|")
              and DELIM.match(lines[i + 1]) and "-" in lines[i + 1]):
            ncols = len([c for c in lines[i + 1].strip().strip("|").split("|")])
            rows = [i + 1]
            j = i + 2
            while j < len(lines) and lines[j].lstrip().startswith("|"):
                rows.append(j + 1)
                j += 1
            tables.append((i + 1, ncols, rows))
            i = j
            continue
        i += 1
    return tables


def rendered_tables(doc: ET.Element) -> Dict[int, Tuple[int, int]]:
    """Header line -> (rows, columns) of every table cmark-gfm made."""
    out = {}
    for t in doc.iter(NS + "table"):
        rows = [r for r in t if r.tag in (NS + "table_header", NS + "table_row")]
        header = [r for r in t if r.tag == NS + "table_header"]
        out[start_line(t)] = (len(rows), len(list(header[0])) if header else 0)
    return out


def row_problems(lines: List[str], tables: List[Tuple[int, int, List[int]]]) -> List[int]:
    """Source lines of rows that do not split into the intended cells (one render for all)."""
    probes: List[Tuple[int, int]] = []  # (probe's header line, source line)
    chunks: List[str] = []
    at = 1
    for _, ncols, rows in tables:
        for ln in rows:
            if ln == rows[0]:
                continue  # the header: checked by the table itself
            chunks.append(lines[ln - 1] + "\n|" + "---|" * ncols + "\n\n")
            probes.append((at, ln))
            at += 3
    if not probes:
        return []
    made = rendered_tables(render_xml("".join(chunks)))
    return [ln for probe, ln in probes if probe not in made]


def anchors_of(path: str, cache: Dict[str, Set[str]]) -> Set[str]:
    if path not in cache:
        ids: Set[str] = set()
        try:
            with open(path, encoding="utf-8") as f:
                text = f.read()
        except OSError:
            text = ""
        ids.update(re.findall(r'<a\s+(?:id|name)="([^"]+)"', text))
        for h in re.findall(r"^#{1,6}\s+(.*)$", text, re.M):  # GitHub's heading anchors
            ids.add(re.sub(r"[^\w\- ]", "", h.strip().lower()).replace(" ", "-"))
        cache[path] = ids
    return cache[path]


def link_problems(path: str, doc: ET.Element) -> List[str]:
    dests: List[Tuple[int, str]] = []
    for tag in ("link", "image"):
        for n in doc.iter(NS + tag):
            dests.append((start_line(n), n.get("destination", "")))
    for n in list(doc.iter(NS + "html_inline")) + list(doc.iter(NS + "html_block")):
        for d in re.findall(r'(?:href|src)="([^"]*)"', n.text or ""):
            dests.append((start_line(n), d))
    problems = []
    cache: Dict[str, Set[str]] = {}
    base = os.path.dirname(os.path.abspath(path))
    for line, d in dests:
        if re.match(r"^[a-zA-Z][a-zA-Z0-9+.-]*:", d):
            continue  # http:, mailto: ...: not checked here
        file, _, frag = d.partition("#")
        target = os.path.normpath(os.path.join(base, file)) if file else os.path.abspath(path)
        if not os.path.exists(target):
            problems.append(f"{path}:{line}: link or image {d!r}: {file} does not exist")
        elif frag and target.endswith(".md") and frag not in anchors_of(target, cache):
            problems.append(f"{path}:{line}: link {d!r}: no anchor {frag!r} in {file or path}")
    return problems


def check_file(path: str) -> List[str]:
    with open(path, encoding="utf-8") as f:
        text = f.read()
    lines = text.split("\n")
    doc = render_xml(text)
    tables = source_tables(lines)
    made = rendered_tables(doc)
    problems = []
    for header, ncols, rows in tables:
        got = made.get(header)
        if got is None:
            problems.append(f"{path}:{header}: not rendered as a table: {lines[header - 1][:100]}")
        elif got != (len(rows), ncols):
            problems.append(f"{path}:{header}: rendered as {got[0]} rows x {got[1]} columns, "
                            f"intended {len(rows)} x {ncols}")
    for ln in row_problems(lines, tables):
        problems.append(f"{path}:{ln}: row does not split into the table's cells: "
                        f"{lines[ln - 1][:100]}")
    problems += link_problems(path, doc)
    return problems


def self_test() -> int:
    """Each planted defect is caught; the escaped forms pass."""
    good = ("# t\n\n<a id=\"x\"></a>\n\n| a | b |\n|---|---|\n| `p \\| q` | \\|x\\| ≤ 1 |\n"
            "| [go](#x) | ok |\n")
    bad = {
        "pipe in a header": "| a | max |H| |\n|---|---|\n| 1 | 2 |\n",
        "pipe in a cell": "| a | b |\n|---|---|\n| |x| ≤ 1 | 2 |\n",
        "pipe in a code span": "| a | b |\n|---|---|\n| `|H - H0|` | 2 |\n",
        "missing anchor": "| a | b |\n|---|---|\n| [go](#nowhere) | 2 |\n",
        "missing file": "![fig](figures/none.png)\n",
        "missing html image": '<img src="none.png">\n',
    }
    failed = 0
    with tempfile.TemporaryDirectory() as d:
        p = os.path.join(d, "good.md")
        with open(p, "w", encoding="utf-8") as f:
            f.write(good)
        if check_file(p):
            print("self-test: the escaped table is flagged:", check_file(p))
            failed += 1
        for name, text in bad.items():
            p = os.path.join(d, "bad.md")
            with open(p, "w", encoding="utf-8") as f:
                f.write(text)
            if not check_file(p):
                print(f"self-test: planted defect not caught: {name}")
                failed += 1
    print("self-test:", "ok" if not failed else f"{failed} failed")
    return 1 if failed else 0


def inputs(args: List[str]) -> Tuple[List[str], Optional[str]]:
    files: List[str] = []
    for a in args:
        if os.path.isdir(a):
            if not os.path.exists(os.path.join(a, "report.md")):
                return [], f"{a}: no report.md"
            files += [os.path.join(a, n) for n in ("report.md", "figures.md", "crosscheck.md")
                      if os.path.exists(os.path.join(a, n))]
        elif os.path.exists(a):
            files.append(a)
        else:
            return [], f"{a}: does not exist"
    return files, None


def main(argv: List[str]) -> int:
    try:
        subprocess.run(["cmark-gfm", "--version"], capture_output=True, check=True)
    except (OSError, subprocess.CalledProcessError):
        print("check_gfm.py: cmark-gfm not found (Debian package cmark-gfm; ci/setup.sh)",
              file=sys.stderr)
        return 2
    if argv[1:] == ["--self-test"]:
        return self_test()
    optional = [argv[i + 1] for i, a in enumerate(argv) if a == "--optional" and i + 1 < len(argv)]
    rest = [a for i, a in enumerate(argv[1:], 1)
            if a != "--optional" and argv[i - 1] != "--optional"]
    files, err = inputs(rest)
    if err or not files:
        print(f"check_gfm.py: {err or 'nothing to check'}", file=sys.stderr)
        return 2
    files += [o for o in optional if os.path.exists(o)]
    problems: List[str] = []
    for f in files:
        found = check_file(f)
        ntables = len(source_tables(open(f, encoding="utf-8").read().split("\n")))
        print(f"{f}: {ntables} tables, {len(found)} problems")
        problems += found
    for p in problems[:60]:
        print(p)
    if len(problems) > 60:
        print(f"... {len(problems) - 60} more")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
