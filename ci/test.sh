#!/usr/bin/env bash
# README command (b): set up, build, and run every test, the clang-format check first:
#   - the Release build (only the dampsym binary): the default suite, the stress suite, the
#     method x property matrix (docs/matrix.md), the Python cross-check and the report tests
#     (schemas, JUnit, shards + merge, compare) on the suites' reports (ctest labels suite,
#     crosscheck and reports; the per-case tests, label "case", would only repeat the suites);
#   - the ASan/UBSan build: every unit test (Catch2, including the CLI tests) and the smaller
#     'sanitize' suite. The unit tests run once, under the sanitizers; building them a second
#     time in Release would only repeat them (ci/suite.sh builds them there for local use).
set -euo pipefail
cd "$(dirname "$0")/.."
bash ci/setup.sh
jobs="$(nproc 2>/dev/null || echo 2)"

echo "== clang-format (${SECONDS} s)"
files=$(git ls-files '*.cpp' '*.hpp' 2>/dev/null || find src reference tests -name '*.[ch]pp')
clang-format --dry-run -Werror $files

echo "== Release build: suites and cross-check (${SECONDS} s)"
bash ci/build.sh release dampsym
echo "== Release ctest (${SECONDS} s)"
(cd build && ctest --output-on-failure -j"$jobs" -L 'suite|crosscheck|reports')

echo "== ASan/UBSan build and unit tests (${SECONDS} s)"
bash ci/build.sh asan
(cd build-asan && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
   ctest --output-on-failure -j"$jobs" -LE 'crosscheck|stress|reports|case' -E '^(suite\.default|matrix\..*)$')
echo "== done (${SECONDS} s)"
