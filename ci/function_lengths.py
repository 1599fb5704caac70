#!/usr/bin/env python3
"""Lists the C++ functions of src/ longer than a limit (the project's rule: at most 80 lines).

A function is a brace block opened at namespace or class scope after a parameter list; its
length counts from the line of its name to its closing brace. Lambdas and local classes count
in the function that holds them. Exit 1 when a function is longer than the limit.
Usage: ci/function_lengths.py [--limit N] [DIR...]
"""
from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

_STRIP = re.compile(r'//[^\n]*|/\*.*?\*/|"(?:\\.|[^"\\])*"|\'(?:\\.|[^\'\\])*\'', re.S)
_SCOPE = re.compile(r'\b(namespace|class|struct|union|enum)\b[^;{()]*$')
_FUNC = re.compile(r'\)\s*(const|noexcept|override|final|mutable|->[^{;]*|requires[^{;]*|\s)*$')


def _blank(text: str) -> str:
    """Comments, strings and preprocessor lines blanked, newlines kept."""
    text = _STRIP.sub(lambda m: re.sub(r'[^\n]', ' ', m.group(0)), text)
    return re.sub(r'(?m)^\s*#.*$', '', text)


def _name(head: str) -> str:
    m = re.search(r'([~\w:<>]+)\s*\([^()]*(?:\([^()]*\)[^()]*)*\)[^()]*$', head)
    return m.group(1) if m else head.strip()[-60:]


def long_functions(path: Path, limit: int) -> list[tuple[int, int, str]]:
    """(first line, length, name) of each function of `path` longer than `limit` lines."""
    text = _blank(path.read_text(encoding='utf-8'))
    found: list[tuple[int, int, str]] = []
    stack: list[tuple[str, int, str]] = []  # (kind, line, name)
    head_start = 0
    for i, ch in enumerate(text):
        if ch in ';}' or (ch == '{' and not stack) or ch == '{':
            pass
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


def self_test() -> int:
    """The scanner finds an 81-line function (a free one and a member) and passes an 80-line one."""
    import tempfile
    body = lambda n: '\n'.join('    x += %d; // "{" in a string, } in a comment' % i for i in range(n - 2))
    src = ('namespace a {\nint f81(int x) {\n%s\n}\nstruct S {\n    int g(int x) const {\n%s\n}\n};\n'
           'int f80(int x) {\n%s\n}\n} // namespace a\n' % (body(81), body(81), body(80)))
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / 'planted.cpp'
        path.write_text(src, encoding='utf-8')
        found = sorted((name, length) for _, length, name in long_functions(path, 80))
    ok = found == [('f81', 81), ('g', 81)]
    print('self-test: %s (found %s)' % ('ok' if ok else 'FAILED', found))
    return 0 if ok else 1


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--limit', type=int, default=80)
    ap.add_argument('--self-test', action='store_true')
    ap.add_argument('dirs', nargs='*', default=['src'])
    args = ap.parse_args()
    if args.self_test:
        return self_test()
    root = Path(__file__).resolve().parent.parent
    bad = 0
    for d in args.dirs:
        base = Path(d) if Path(d).is_absolute() else root / d
        for path in sorted(base.rglob('*.[ch]pp')):
            for first, length, name in long_functions(path, args.limit):
                print(f'{path.relative_to(root)}:{first}: {name}: {length} lines (limit {args.limit})')
                bad += 1
    return 1 if bad else 0


if __name__ == '__main__':
    sys.exit(main())
