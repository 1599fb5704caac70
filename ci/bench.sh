#!/usr/bin/env bash
# Benchmarks: set up, build dampsym and dampsym_bench (Release, in build/), time the default suite
# with --jobs 1 and --jobs 2, run dampsym_bench (raw output: reports/bench-raw.json), then
# bench/bench_report.py, which writes reports/bench.json and reports/bench.md and prints the
# acceptance table, then bench/run_timing.py (the kernel ratios through `dampsym run`) and
# bench/figures_cost.py (the default suite with --figures against without), then
# bench/python_api.py (the Python API against the CLI), then the work-precision comparison
# (dampsym_bench's wp/ benchmarks and scipy, bench/work_precision.py:
# reports/work-precision.{json,png}, about a minute), then the coefficient mutants
# (ci/mutants.py, docs/mutation.md). Exits 1 if an acceptance row fails (2 on a usage or input
# error). Takes several minutes; run it on a quiet machine.
# Environment: DAMPSYM_BUILD_DIR (default build), DAMPSYM_BUILD_JOBS (default nproc).
set -euo pipefail
cd "$(dirname "$0")/.."
bash ci/setup.sh
build="${DAMPSYM_BUILD_DIR:-build}"
jobs="${DAMPSYM_BUILD_JOBS:-$(nproc 2>/dev/null || echo 2)}"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DDAMPSYM_WERROR=ON -DDAMPSYM_BUILD_BENCH=ON >/dev/null
cmake --build "$build" -j"$jobs" --target dampsym dampsym_bench dampsym_python
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
mkdir -p reports
# The suite's own exit status (a failing check) is reported by ci/suite.sh; here only its wall time
# is used, but a bad input (exit 2) stops the benchmark.
for j in 1 2; do
  s=0
  "$build/dampsym" run --out "$tmp/suite-jobs$j" --jobs "$j" >/dev/null || s=$?
  if [ "$s" -eq 2 ]; then echo "ci/bench.sh: dampsym run --jobs $j: bad input" >&2; exit 2; fi
done
# The work-precision benchmarks (wp/) have their own run below.
"$build/dampsym_bench" --benchmark_filter='-^wp/' --benchmark_out=reports/bench-raw.json \
  --benchmark_out_format=json
status=0
/usr/bin/python3 bench/bench_report.py reports/bench-raw.json \
  --suite-jobs1 "$tmp/suite-jobs1/report.json" --suite-jobs2 "$tmp/suite-jobs2/report.json" \
  --out-json reports/bench.json --out-md reports/bench.md || status=$?
if [ "$status" -eq 2 ]; then exit 2; fi
# The explicit Klein-Gordon scheme (5.3) against scipy's RK45, work-precision on the same
# semi-discrete system (docs/benchmarks.md): reports/pde-scipy.json.
/usr/bin/python3 bench/pde_scipy.py reports/bench-raw.json > reports/pde-scipy.json || {
  s=$?; if [ "$s" -eq 2 ]; then exit 2; fi; status=1; }
/usr/bin/python3 -c 'import json
for r in json.load(open("reports/pde-scipy.json")):
    for m in r["matched"]:
        k = m["rk45"]
        print("KG M=%d %-10s csv1 h=%.1f dx err %.2e | RK45 %s" % (r["M"], r["initial"],
              m["csv1_h_over_dx"], m["error"], "none as accurate" if not k else
              "rtol %.0e err %.2e: rhs evals x%.2f, cpu x%.1f" % (k["rtol"], k["error"],
              k["rhs_ratio_rk45_over_csv1"], k["cpu_ratio_rk45_over_csv1"])))'
# The same kernel ratios through `dampsym run` (each method alone, 10^7 pendulum steps, no
# diagnostic, the run's own wall time): reports/run-timing.json.
/usr/bin/python3 bench/run_timing.py "$build/dampsym" --bench-json reports/bench-raw.json \
  --out-json reports/run-timing.json || {
  s=$?; if [ "$s" -eq 2 ]; then exit 2; fi; status=1; }
# The default suite with --figures against without (at most 2x): reports/figures-cost.json.
/usr/bin/python3 bench/figures_cost.py "$build/dampsym" --out-json reports/figures-cost.json || {
  s=$?; if [ "$s" -eq 2 ]; then exit 2; fi; status=1; }
# The Python API against the command line on the same case (at most 1.05x) and a Python callable
# step's cost per step (docs/python.md "Cost"): reports/python-api.json.
PYTHONPATH="$build/python" /usr/bin/python3 bench/python_api.py "$build/dampsym" \
  --out-json reports/python-api.json || {
  s=$?; if [ "$s" -eq 2 ]; then exit 2; fi; status=1; }
# Work-precision (docs/benchmarks.md "Work-precision"): dampsym's conformal methods beside
# Boost.Odeint and GSL (the wp/ benchmarks) and scipy's DOP853 and Radau (bench/work_precision.py),
# one after the other on this machine: reports/work-precision.json and reports/work-precision.png
# (docs/img/work-precision.png is a committed copy).
"$build/dampsym_bench" --benchmark_filter='^wp/' --benchmark_out=reports/wp-raw.json \
  --benchmark_out_format=json >/dev/null
s=0
/usr/bin/python3 bench/work_precision.py reports/wp-raw.json --out-json reports/work-precision.json ||
  s=$?
if [ "$s" -eq 2 ]; then exit 2; fi
if [ "$s" -eq 0 ]; then
  /usr/bin/python3 tools/figures/work_precision_plot.py reports/work-precision.json \
    --out reports/work-precision.png || s=$?
  if [ "$s" -eq 2 ]; then exit 2; fi
fi
if [ "$s" -ne 0 ]; then status=1; fi
# Coefficient mutants (docs/mutation.md): every coefficient of every exportable built-in method
# multiplied by (1 + 1e-6) must be killed by `methods --check`, the matrix or its default-suite
# cases (about 3 minutes on 2 cores): reports/mutants/results.json.
/usr/bin/python3 ci/mutants.py --dampsym "$build/dampsym" --jobs 2 --out reports/mutants --quiet || {
  s=$?; if [ "$s" -eq 2 ]; then exit 2; fi; status=1; }
exit "$status"
