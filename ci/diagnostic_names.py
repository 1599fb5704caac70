#!/usr/bin/env python3
"""No diagnostic named by a string literal outside its own file (docs/extending.md).

Each diagnostic declares its name once, `static constexpr std::string_view name = "..."` in
src/diagnostics/<name>_diagnostic.hpp; everything else names it through that constant
(`OrderDiagnostic::name`). This scanner reads the declared names and flags, in every C++ file of
the given folders except the diagnostics' own files, a string literal used as a diagnostic name:
an argument of `wants(...)`/`method_metric(...)`/`order_table(...)`, an operand of `==`/`!=`
with a variable named like a diagnostic (`diag`, `d`), an entry of a case's "diagnostics" list,
or a metric path "<name>.<metric>". Other literals that happen to spell a name (a method's
"order" field, a run's "error" status, an invariant called "energy") are not diagnostic names
and are not flagged. `--self-test` plants one of each form and checks all are found.
"""
from __future__ import annotations

import re
import sys
from pathlib import Path
from typing import List, Set, Tuple

ROOT = Path(__file__).resolve().parent.parent
NAME_DECL = re.compile(r'static constexpr std::string_view name = "([a-z-]+)";')
OWN_FILES = re.compile(r"src/diagnostics/[a-z_]+_diagnostic\.(hpp|cpp)$")


def declared_names() -> Set[str]:
    names: Set[str] = set()
    for header in sorted((ROOT / "src" / "diagnostics").glob("*_diagnostic.hpp")):
        names.update(NAME_DECL.findall(header.read_text(encoding="utf-8")))
    return names


def patterns(names: Set[str]) -> List[re.Pattern[str]]:
    alt = "|".join(sorted((re.escape(n) for n in names), key=len, reverse=True))
    lit = rf'"(?:{alt})"'
    return [
        re.compile(rf"\b(?:wants|method_metric|order_table|find_diagnostic)\([^()]*{lit}"),
        re.compile(rf"\b(?:diag|d|part)\s*[!=]=\s*{lit}"),
        re.compile(rf'"diagnostics",\s*\{{[^{{}}]*{lit}'),
        re.compile(rf'"(?:{alt})\.[A-Za-z_][A-Za-z0-9_.]*"'),
    ]


def scan_text(text: str, pats: List[re.Pattern[str]]) -> List[Tuple[int, str]]:
    found: List[Tuple[int, str]] = []
    for number, line in enumerate(text.splitlines(), start=1):
        code = line.split("//", 1)[0]
        if any(p.search(code) for p in pats):
            found.append((number, line.strip()))
    return found


def scan(folders: List[str]) -> List[str]:
    pats = patterns(declared_names())
    out: List[str] = []
    for folder in folders:
        for path in sorted((ROOT / folder).rglob("*")):
            rel = path.relative_to(ROOT).as_posix()
            if path.suffix not in (".cpp", ".hpp", ".h") or OWN_FILES.search(rel):
                continue
            for number, line in scan_text(path.read_text(encoding="utf-8"), pats):
                out.append(f"{rel}:{number}: {line}")
    return out


def self_test() -> int:
    pats = patterns(declared_names())
    planted = [
        'if (c.wants("order")) return;',
        'const json* f = method_metric(c, m, "stability-sweep");',
        'if (diag == "invariants") x();',
        'json j = {{"diagnostics", {"error", "order"}}};',
        'const json* e = lookup(r, "error.final_abs");',
    ]
    clean = ['out["order"] = m.order;', 'if (st == "error") n++;', 'names{"momentum", "mass"}']
    missed = [p for p in planted if not scan_text(p, pats)]
    false_hits = [c for c in clean if scan_text(c, pats)]
    for m in missed:
        print(f"self-test: planted literal not found: {m}")
    for f in false_hits:
        print(f"self-test: not a diagnostic name, flagged: {f}")
    return 1 if missed or false_hits else 0


def main(argv: List[str]) -> int:
    if argv[1:] == ["--self-test"]:
        return self_test()
    if len(declared_names()) < 10:
        print("diagnostic_names: fewer than 10 declared names found (pattern out of date?)")
        return 1
    hits = scan(argv[1:] or ["src"])
    for h in hits:
        print(h)
    if hits:
        print(f"{len(hits)} diagnostic name(s) as string literals: use <Name>Diagnostic::name")
    return 1 if hits else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
