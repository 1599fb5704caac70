#!/usr/bin/env bash
# Configures and builds dampsym. Usage: ci/build.sh [release|asan]  (default release)
#   release -> build/       (Release, -Werror)
#   asan    -> build-asan/  (AddressSanitizer + UndefinedBehaviorSanitizer)
set -euo pipefail
cd "$(dirname "$0")/.."
kind="${1:-release}"
jobs="$(nproc 2>/dev/null || echo 2)"
case "$kind" in
  release) cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DDAMPSYM_WERROR=ON >/dev/null
           cmake --build build -j"$jobs" ;;
  asan)    cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug "-DCMAKE_CXX_FLAGS_DEBUG=-O0 -g1" -DDAMPSYM_SANITIZE=ON -DDAMPSYM_WERROR=ON >/dev/null
           cmake --build build-asan -j"$jobs" ;;
  *) echo "usage: ci/build.sh [release|asan]" >&2; exit 2 ;;
esac
