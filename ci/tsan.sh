#!/usr/bin/env bash
# ThreadSanitizer run of the parallel runner (not part of CI: a third full build of the case
# shards would lengthen it; docs/ci.md). Builds dampsym and the unit tests with -fsanitize=thread
# into build-tsan/, then:
#   - runs the 'sanitize' suite (every kernel family, every diagnostic kind, each problem family;
#     shared reference cache, task pool, report assembly) with --jobs 1, 2 and 8, and checks that
#     the three reports are identical (dampsym compare) — any data race aborts the run
#     (TSAN_OPTIONS halt_on_error=1, exit code 66);
#   - runs the unit tests of the runner and its limits (timeouts, stop requests, faults in one
#     task while others run, the CLI) under TSan.
# Usage: ci/tsan.sh   (environment: DAMPSYM_BUILD_JOBS, default nproc)
set -euo pipefail
cd "$(dirname "$0")/.."
jobs="${DAMPSYM_BUILD_JOBS:-$(nproc 2>/dev/null || echo 2)}"
cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=Debug "-DCMAKE_CXX_FLAGS_DEBUG=-O1 -g1" \
  "-DCMAKE_CXX_FLAGS=-fsanitize=thread" "-DCMAKE_EXE_LINKER_FLAGS=-fsanitize=thread" \
  -DDAMPSYM_WERROR=OFF -DDAMPSYM_BUILD_BENCH=OFF >/dev/null
cmake --build build-tsan -j"$jobs" --target dampsym dampsym_tests
export TSAN_OPTIONS="halt_on_error=1 exitcode=66 second_deadlock_stack=1"
status=0
for j in 1 2 8; do
  echo "== tsan: dampsym run --suite sanitize --jobs $j"
  s=0
  build-tsan/dampsym run --suite sanitize --jobs "$j" --time-budget 0 --quiet \
    --out "build-tsan/report-jobs$j" || s=$?
  if [ "$s" -ne 0 ] && [ "$s" -ne 1 ]; then echo "ci/tsan.sh: --jobs $j: exit $s" >&2; status=1; fi
done
for j in 2 8; do
  build-tsan/dampsym compare build-tsan/report-jobs1 "build-tsan/report-jobs$j" --ignore-timings \
    >/dev/null || { echo "ci/tsan.sh: --jobs $j report differs from --jobs 1" >&2; status=1; }
done
echo "== tsan: unit tests of the runner, its limits and the CLI"
build-tsan/tests/dampsym_tests "[limits],[cli],[report]" || status=1
exit "$status"
