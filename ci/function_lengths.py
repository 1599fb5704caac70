#!/usr/bin/env python3
"""Lists the C++ and Python functions longer than a limit (the project's rule: at most 80 lines).

C++ and C (the .cpp/.hpp/.c/.h files under each DIR, default src): a function is a brace block opened at
namespace or class scope after a parameter list; its length counts from the line of its name to
its closing brace. Lambdas and local classes count in the function that holds them.
Python (--python, instead of the DIRs: every .py file git tracks): every def, nested ones too, from its def line to
its last line (the rule verify/tests/test_style.py checks for verify/ alone).
Exit 1 when a function is longer than the limit.
Usage: ci/function_lengths.py [--limit N] [DIR... | --python] | --self-test
"""
from __future__ import annotations

import argparse
import ast
import re
import subprocess
import sys
from pathlib import Path
from typing import Iterator

# Raw strings first (R"(...)" holds quotes and braces: the test files' JSON texts), then
# comments, strings and character literals (not a digit separator: 50'000'000).
_STRIP = re.compile(r'(?<!\w)(?:u8|[uUL])?R"([^()\\\s]{0,16})\(.*?\)\1"|//[^\n]*|/\*.*?\*/'
                    r'|"(?:\\.|[^"\\])*"|(?<![0-9A-Fa-f])\'(?:\\.|[^\'\\])*\'', re.S)
_PREPROCESSOR = re.compile(r'(?m)^[ \t]*#(?:[^\n]*\\\n)*[^\n]*')
_CXX_SUFFIXES = ('.cpp', '.hpp', '.c', '.h')
_SCOPE = re.compile(r'\b(namespace|class|struct|union|enum)\b[^;{()]*$')
_FUNC = re.compile(r'\)\s*(const|noexcept|override|final|mutable|->[^{;]*|requires[^{;]*|\s)*$')


def _blank(text: str) -> str:
    """Comments, strings and preprocessor lines blanked, newlines kept."""
    def blank(m: re.Match[str]) -> str:
        return re.sub(r'[^\n]', ' ', m.group(0))

    return _PREPROCESSOR.sub(blank, _STRIP.sub(blank, text))


def _name(head: str) -> str:
    m = re.search(r'([~\w:<>]+)\s*\([^()]*(?:\([^()]*\)[^()]*)*\)[^()]*$', head)
    return m.group(1) if m else head.strip()[-60:]


def long_functions(path: Path, limit: int) -> list[tuple[int, int, str]]:
    """(first line, length, name) of each function of `path` longer than `limit` lines."""
    text = _blank(path.read_text(encoding='utf-8'))
    found: list[tuple[int, int, str]] = []
    stack: list[tuple[str, int, str]] = []  # (kind, line, name)
    head_start = 0
    for m in re.finditer(r'[{};:]', text):
        i, ch = m.start(), m.group(0)
        if ch == '{':
            inside = any(k == 'fn' for k, _, _ in stack)
            head = text[head_start:i]
            kind = 'other'
            if not inside:
                if _SCOPE.search(head.strip().split('\n')[-1] if head.strip() else ''):
                    kind = 'scope'
                elif _FUNC.search(head):
                    kind = 'fn'
                elif re.search(r'\b(namespace|class|struct|union|enum)\b', head):
                    kind = 'scope'
            first = text.count('\n', 0, head_start + len(head) - len(head.lstrip())) + 1
            stack.append((kind, first, _name(head) if kind == 'fn' else ''))
            head_start = i + 1
        elif ch == '}':
            if stack:
                kind, first, name = stack.pop()
                last = text.count('\n', 0, i) + 1
                if kind == 'fn' and not any(k == 'fn' for k, _, _ in stack):
                    if last - first + 1 > limit:
                        found.append((first, last - first + 1, name))
            head_start = i + 1
        elif ch == ';' or (ch == ':' and text[max(0, i - 7):i].strip() in ('public', 'private', 'protected')):
            head_start = i + 1
    return found


def long_python_functions(path: Path, limit: int) -> list[tuple[int, int, str]]:
    """(first line, length, name) of each Python function of `path` (nested ones too) longer than
    `limit` lines, counted from its `def` line to its last line."""
    text = path.read_text(encoding='utf-8')
    if text.count('\n') < limit:  # no function can be longer than its file
        return []
    return [(n.lineno, (n.end_lineno or n.lineno) - n.lineno + 1, n.name)
            for n in _python_defs(ast.parse(text, str(path)))
            if (n.end_lineno or n.lineno) - n.lineno + 1 > limit]


def _python_defs(node: ast.AST) -> Iterator[ast.FunctionDef | ast.AsyncFunctionDef]:
    """The defs under `node`, found through statements only (a def is a statement; walking the
    expressions too, like ast.walk, takes three times as long)."""
    for child in ast.iter_child_nodes(node):
        if isinstance(child, (ast.stmt, ast.excepthandler, ast.match_case)):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)):
                yield child
            yield from _python_defs(child)


def tracked_python(root: Path) -> list[Path]:
    """Every .py file git tracks in `root`; outside a git checkout (a source archive), every .py
    file outside hidden and build* folders."""
    try:
        out = subprocess.run(['git', 'ls-files', '-z', '--', '*.py'], cwd=root, check=True,
                             capture_output=True, text=True).stdout
        return sorted(root / f for f in out.split('\0') if f)
    except (OSError, subprocess.CalledProcessError):
        return sorted(p for p in root.rglob('*.py') if not any(
            part.startswith(('.', 'build')) for part in p.relative_to(root).parts[:-1]))


_PLANTED_CPP = """#include <vector>

#define TWO_LINES(x) \\
    ((x) + 1)
namespace a {
int f81(int x) {
%s
}
struct S {
    int g(int x) const {
%s
}
};
int f80(int x) {
    const char* text = R"({"brace": "}", "quote": "\\"})";
    const long n = 50'000'000;
    const char open = '{';
%s
}
} // namespace a
"""

_PLANTED_PY = """def f81() -> None:
%s


class C:
    async def m81(self) -> None:
%s


def f80() -> None:
%s
"""


def self_test() -> int:
    """The scanners find an 81-line function and pass an 80-line one: C++ (a free function and a
    member; a raw string with a brace and a quote, a digit separator, a character literal '{' and a
    continued #define that must not shift the line numbers) and Python (an async method too)."""
    import tempfile
    def body(n: int) -> str:
        return '\n'.join('    x += %d; // "{" in a string, } in a comment' % i for i in range(n))

    def py(n: int, indent: int) -> str:
        return '\n'.join('%sx = %d' % (' ' * indent, i) for i in range(n))

    with tempfile.TemporaryDirectory() as d:
        cpp, pyf = Path(d) / 'planted.cpp', Path(d) / 'planted.py'
        cpp.write_text(_PLANTED_CPP % (body(79), body(79), body(75)), encoding='utf-8')
        pyf.write_text(_PLANTED_PY % (py(80, 4), py(80, 8), py(79, 4)), encoding='utf-8')
        found_cpp = sorted((name, first, length) for first, length, name in long_functions(cpp, 80))
        found_py = sorted((name, first, length)
                          for first, length, name in long_python_functions(pyf, 80))
    ok = (found_cpp == [('f81', 6, 81), ('g', 88, 81)]
          and found_py == [('f81', 1, 81), ('m81', 85, 81)])
    print('self-test: %s (C++ found %s; Python found %s)' % ('ok' if ok else 'FAILED', found_cpp,
                                                            found_py))
    return 0 if ok else 1


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--limit', type=int, default=80)
    ap.add_argument('--self-test', action='store_true')
    ap.add_argument('--python', action='store_true',
                    help='every Python function of the tracked .py files instead of C/C++ DIRs')
    ap.add_argument('dirs', nargs='*', default=['src'])
    args = ap.parse_args()
    if args.self_test:
        return self_test()
    root = Path(__file__).resolve().parent.parent
    found: list[tuple[Path, int, int, str]] = []
    for d in [] if args.python else args.dirs:
        base = Path(d) if Path(d).is_absolute() else root / d
        for path in sorted(p for p in base.rglob('*') if p.suffix in _CXX_SUFFIXES):
            found += [(path, *f) for f in long_functions(path, args.limit)]
    if args.python:
        for path in tracked_python(root):
            found += [(path, *f) for f in long_python_functions(path, args.limit)]
    for path, first, length, name in found:
        print(f'{path.relative_to(root)}:{first}: {name}: {length} lines (limit {args.limit})')
    return 1 if found else 0


if __name__ == '__main__':
    sys.exit(main())
