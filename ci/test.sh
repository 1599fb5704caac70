#!/usr/bin/env bash
# README command (b): set up, build, and run every test: the Release build's ctest (unit tests,
# CLI tests, the default suite and the Python cross-check), the ASan/UBSan build's unit tests and
# its smaller 'sanitize' suite, and
# the clang-format check.
set -euo pipefail
cd "$(dirname "$0")/.."
bash ci/setup.sh
jobs="$(nproc 2>/dev/null || echo 2)"

echo "== clang-format"
files=$(git ls-files '*.cpp' '*.hpp' 2>/dev/null || find src reference tests -name '*.[ch]pp')
clang-format --dry-run -Werror $files

echo "== Release build and tests"
bash ci/build.sh release
(cd build && ctest --output-on-failure -j"$jobs")

echo "== ASan/UBSan build and unit tests"
bash ci/build.sh asan
(cd build-asan && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
   ctest --output-on-failure -j"$jobs" -LE 'crosscheck|stress' -E '^suite\.default$')
