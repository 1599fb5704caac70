#!/usr/bin/env bash
# README command (b): set up, build, and run every test, the clang-format check first:
#   - the Release build (only the dampsym binary): the default suite, the stress suite, the
#     method x property matrix (docs/matrix.md), the Python cross-check and the report tests
#     (schemas, JUnit, shards + merge, compare) on the suites' reports (ctest labels suite,
#     crosscheck and reports; the per-case tests, label "case", would only repeat the suites);
#   - in the Release build too: the Python package (python/: one extension unit linked with the
#     same library; its pytest, mypy and examples/python/verify_my_method.py, label python) and
#     the CMake package (ctest package.consumer: cmake --install into a temporary prefix, then
#     examples/consumer configured, built and tested against it, label package);
#   - the type check of the Python side (mypy on the package verify, verify/mypy.ini; ~16 CPU s
#     on a cold cache, 1 s warm), in the background beside the builds;
#   - the ASan/UBSan build: every unit test (Catch2, including the CLI tests) and the smaller
#     'sanitize' suite. The unit tests run once, under the sanitizers; building them a second
#     time in Release would only repeat them (ci/suite.sh builds them there for local use).
#     The ASan/UBSan build and its tests run in the background from the start (below); their
#     log is printed when they are waited for.
set -euo pipefail
cd "$(dirname "$0")/.."
bash ci/setup.sh
jobs="$(nproc 2>/dev/null || echo 2)"
# mypy's incremental cache (the verify package here, figures.mypy and python.mypy in ctest): kept
# under ~/.cache, outside the checkout, so that a fresh clone does not type-check numpy's and the
# standard library's stubs again (about 30 CPU s); in the build tree when ~/.cache is not writable.
DAMPSYM_MYPY_CACHE="${XDG_CACHE_HOME:-${HOME:-/nonexistent}/.cache}/dampsym-mypy"
if mkdir -p "$DAMPSYM_MYPY_CACHE" 2>/dev/null && [ -w "$DAMPSYM_MYPY_CACHE" ]; then
  export DAMPSYM_MYPY_CACHE
else
  unset DAMPSYM_MYPY_CACHE
fi

echo "== clang-format (${SECONDS} s)"
files=$(git ls-files '*.cpp' '*.hpp' 2>/dev/null || find src reference tests -name '*.[ch]pp')
clang-format --dry-run -Werror $files

# The ASan/UBSan build and then its unit tests run at once, in the background and at a lower
# priority: each build and test phase alone leaves a core idle now and then (a last compile or a
# link alone, the last long test), and the background phase fills those gaps instead of running
# after them (with a warm compiler cache the sanitizer build is only its links, which finish while
# the Release tests run; at the Release phase's priority the whole run took longer: 330 s against
# 313 s on a fresh clone, docs/ci.md).
asan_phase() {
  bash ci/build.sh asan || return
  echo "== ASan/UBSan unit tests (${SECONDS} s)"
  (cd build-asan && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
     ctest --output-on-failure -j"$jobs" -LE 'crosscheck|stress|reports|case' \
           -E '^(suite\.default|matrix\..*)$')
}
echo "== ASan/UBSan build and unit tests in the background (${SECONDS} s)"
asan_log="$(mktemp)"
trap 'rm -f "$asan_log"' EXIT
(renice -n 10 "$BASHPID" >/dev/null; asan_phase) >"$asan_log" 2>&1 &
asan_pid=$!
asan_status=0

echo "== mypy (verify) in the background (${SECONDS} s)"
mypy_log="$(mktemp)"
trap 'rm -f "$asan_log" "$mypy_log"' EXIT
/usr/bin/python3 -m mypy --config-file verify/mypy.ini -p verify \
  --cache-dir "${DAMPSYM_MYPY_CACHE:-build/mypy-cache}/verify" >"$mypy_log" 2>&1 &
mypy_pid=$!

echo "== Release build: suites and cross-check (${SECONDS} s)"
release_status=0
bash ci/build.sh release dampsym dampsym_test_plugins dampsym_python || release_status=$?
if [ "$release_status" -eq 0 ]; then
  echo "== Release ctest (${SECONDS} s)"
  (cd build && ctest --output-on-failure -j"$jobs" -L 'suite|crosscheck|reports|python|package') ||
    release_status=$?
fi

echo "== mypy: waiting for it (${SECONDS} s)"
mypy_status=0
wait "$mypy_pid" || mypy_status=$?
cat "$mypy_log"
if [ "$mypy_status" -ne 0 ] && [ "$release_status" -eq 0 ]; then release_status=$mypy_status; fi

echo "== ASan/UBSan build and unit tests: waiting for them (${SECONDS} s)"
wait "$asan_pid" || asan_status=$?
cat "$asan_log"
if [ "$release_status" -ne 0 ]; then exit "$release_status"; fi
if [ "$asan_status" -ne 0 ]; then exit "$asan_status"; fi
echo "== done (${SECONDS} s)"
