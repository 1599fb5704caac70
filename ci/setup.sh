#!/usr/bin/env bash
# Installs the Debian packages dampsym needs (idempotent, non-interactive; run as root or with sudo).
set -euo pipefail
packages=(
  g++ cmake make
  ccache # ci/build.sh: a compiler cache, shared between checkouts (a cold cache only costs time)
  python3-numba # verify/xjit.py: the cross-check's compiled step loops (optional, faster)
  libeigen3-dev libgsl-dev nlohmann-json3-dev catch2 libcli11-dev libboost-dev libbenchmark-dev
  python3 python3-numpy python3-scipy python3-mpmath python3-jsonschema python3-junitparser
  python3-matplotlib
  python3-pytest python3-mypy # verify/tests (pytest) and the type check of verify/ (ci/test.sh)
  python3-dev pybind11-dev python3-pybind11 # the Python package dampsym (python/, docs/python.md)
  python3-distributed # dampsym.dask (its test runs a LocalCluster)
  clang-format
  cmark-gfm # tests/markdown/check_gfm.py: report.md, figures.md as GitHub renders them
  clang-14 libclang-rt-14-dev libfuzzer-14-dev # the sanitizer build (ci/build.sh asan; libclang-rt: its ASan/UBSan runtime, only recommended by clang-14) and ci/fuzz.sh
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "ci/setup.sh: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
