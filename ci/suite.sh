#!/usr/bin/env bash
# README command (a): set up, build, run the default suite with its figures (reports/report.json,
# reports/report.md with the figures embedded, reports/figures/, the gallery reports/figures.md;
# docs/reports.md "Figures"), then reproduce it independently with the Python cross-check
# (reports/crosscheck.{json,md}).
set -euo pipefail
cd "$(dirname "$0")/.."
bash ci/setup.sh
bash ci/build.sh release
jobs="$(nproc 2>/dev/null || echo 2)"
status=0
./build/dampsym run --out reports --jobs "$jobs" --figures || status=$?
if [ "$status" -ge 2 ]; then exit "$status"; fi
if [ -f verify/crosscheck.py ]; then
  /usr/bin/python3 -m verify.crosscheck reports/report.json --out reports || status=1
fi
exit "$status"
