#!/usr/bin/env bash
# Configures and builds dampsym. Usage: ci/build.sh [release|asan] [target...]
#   release -> build/       (Release, -Werror)            default: every target
#   asan    -> build-asan/  (AddressSanitizer + UndefinedBehaviorSanitizer, clang 14)
set -euo pipefail
cd "$(dirname "$0")/.."
kind="${1:-release}"
shift || true
targets=()
for t in "$@"; do targets+=(--target "$t"); done
jobs="$(nproc 2>/dev/null || echo 2)"
# A compiler cache when ccache is installed and its cache is writable (ci/setup.sh installs it):
# paths are hashed relative to this checkout (CCACHE_BASEDIR) and without the working directory
# (CCACHE_NOHASHDIR), so a fresh clone anywhere reuses the objects of any earlier build of the same
# sources with the same compiler and flags. Every object still comes from that compiler: a cold
# cache (a new machine) only costs the full compile time.
launcher=()
cache_dir="$(ccache -k cache_dir 2>/dev/null || true)"
if [ -n "$cache_dir" ] && mkdir -p "$cache_dir" 2>/dev/null && [ -w "$cache_dir" ]; then
  export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=1
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
# mypy's cache for the type-check tests, outside the checkout like the compiler cache (ci/test.sh
# sets DAMPSYM_MYPY_CACHE; mypy re-checks whatever differs from what it recorded, by content hash).
mypy_cache=()
if [ -n "${DAMPSYM_MYPY_CACHE:-}" ]; then mypy_cache=("-DDAMPSYM_MYPY_CACHE=$DAMPSYM_MYPY_CACHE"); fi
case "$kind" in
  release) cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DDAMPSYM_WERROR=ON "${launcher[@]}" \
             "${mypy_cache[@]}" >/dev/null
           cmake --build build -j"$jobs" "${targets[@]}" ;;
  # The sanitizer build with clang 14 (the fuzz targets' compiler, ci/setup.sh): with every check
  # of -fsanitize=address,undefined it compiles this code base in about 45 % of g++ 12's time
  # (a library batch: 11.3 s against 25.1 s of CPU), and it adds a second compiler's -Werror.
  # -ffile-prefix-map: __FILE__ (assert, Catch2) and the debug information name files relative to
  # the checkout; a unity batch includes its files by absolute path, and without the map their
  # __FILE__ strings made each checkout's objects differ (no compiler cache between checkouts).
  # -O1, as the AddressSanitizer documentation advises: the sanitized tests took 158 CPU-s at -O0
  # (Eigen's expression templates unoptimised) and 48 at -O1; every check stays on.
  asan)    cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug "-DCMAKE_CXX_FLAGS_DEBUG=-O1 -g1" \
             "-DCMAKE_CXX_FLAGS=-ffile-prefix-map=$PWD=." \
             -DCMAKE_CXX_COMPILER="${CXX_ASAN:-clang++-14}" -DCMAKE_C_COMPILER="${CC_ASAN:-clang-14}" \
             -DDAMPSYM_SANITIZE=ON -DDAMPSYM_WERROR=ON -DDAMPSYM_UNIT_TESTS_PER_FILE=ON "${launcher[@]}" >/dev/null
           cmake --build build-asan -j"$jobs" "${targets[@]}" ;;
  *) echo "usage: ci/build.sh [release|asan] [target...]" >&2; exit 2 ;;
esac
