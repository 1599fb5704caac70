"""Rules of the Python side (docs/extending.md): every function of verify/ at most 80 lines and no
sys.path edit (verify is a package). That every function is typed is mypy's part
(disallow_untyped_defs in verify/mypy.ini, ci/test.sh)."""
from __future__ import annotations

import ast
import os
from typing import List, Tuple

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
LIMIT = 80


def sources() -> List[str]:
    out = []
    for d, _, files in os.walk(os.path.join(ROOT, "verify")):
        out += [os.path.join(d, f) for f in files if f.endswith(".py")]
    return sorted(out)


def functions(path: str) -> List[Tuple[str, int, ast.FunctionDef]]:
    with open(path) as fh:
        tree = ast.parse(fh.read(), path)
    return [(path, n.lineno, n) for n in ast.walk(tree) if isinstance(n, ast.FunctionDef)]


def long_functions(paths: List[str]) -> List[str]:
    return ["%s:%d %s: %d lines" % (os.path.relpath(p, ROOT), ln, f.name, (f.end_lineno or ln) - ln + 1)
            for path in paths for p, ln, f in functions(path) if (f.end_lineno or ln) - ln + 1 > LIMIT]


def test_functions_at_most_80_lines() -> None:
    assert long_functions(sources()) == []


def test_a_long_function_is_seen(tmp_path: "os.PathLike[str]") -> None:
    """Negative control: an 81-line function is reported."""
    p = os.path.join(str(tmp_path), "long.py")
    with open(p, "w") as fh:
        fh.write("def f() -> None:\n" + "    x = 1\n" * 80)
    assert len(long_functions([p])) == 1


def test_no_sys_path_edits() -> None:
    bad = [os.path.relpath(p, ROOT) for p in sources() if "sys.path.insert" in open(p).read()
           and not p.endswith("test_style.py")]
    assert bad == []
