#!/usr/bin/env bash
# Builds the libFuzzer targets of tests/fuzz/ with clang-14 (ASan + UBSan + libFuzzer; Debian
# clang-14 and libfuzzer-14-dev, installed by ci/setup.sh) into build-fuzz/, and runs each for a
# time budget, seeded with its committed corpus (tests/fuzz/corpus/<target>) plus verify/cases and
# tests/data/bad. New interesting inputs are merged back into the committed corpus; a crash stops
# the run and leaves its reproducer in build-fuzz/findings/<target>/ (commit it under
# tests/fuzz/regressions/<target>/ once fixed: CI replays it).
#
# Usage: ci/fuzz.sh [SECONDS_PER_TARGET (default 600)] [TARGET...]
#        (targets: case set report method plugin)
#        ci/fuzz.sh build                                             (build only)
# Runs at nice 19 (the machine may be shared). Not part of CI: CI replays the corpus instead
# (ctest -L fuzz in the ASan/UBSan build, seconds; tests/fuzz/CMakeLists.txt).
set -euo pipefail
cd "$(dirname "$0")/.."
root="$PWD"
out="$root/build-fuzz"
mkdir -p "$out/obj"
# The diagnostic registry's generated list (src/diagnostics/diagnostic_list.hpp), as the CMake build
# writes it (only when it changes).
cmake -DSRC_DIR="$root" -DOUT="$out/include/diagnostic_registry_generated.hpp" \
      -P "$root/cmake/diagnostic_registry.cmake"
# The (kernel, problem) pairs in one shard, as CMake generates the shards (the registry reads them:
# which kernel applies to which problem); rewritten only when it changes.
sed -e 's/@DAMPSYM_SHARD@/0/g' -e 's/@DAMPSYM_CASE_SHARDS@/1/g' \
    src/harness/run/kernel_shard.cpp.in > "$out/kernel_shard_0.cpp.new"
if cmp -s "$out/kernel_shard_0.cpp.new" "$out/kernel_shard_0.cpp"; then
  rm "$out/kernel_shard_0.cpp.new"
else
  mv "$out/kernel_shard_0.cpp.new" "$out/kernel_shard_0.cpp"
fi
cxx="${CXX_FUZZ:-clang++-14}"
launcher="${CMAKE_CXX_COMPILER_LAUNCHER:-}"
flags=(-std=c++20 -O1 -g -fno-omit-frame-pointer -fsanitize=address,undefined
       -fno-sanitize-recover=all -I"$root/src" -I"$root" -I"$root/include" -I"$out/include" -isystem /usr/include/eigen3
       -DDAMPSYM_VERSION=\"fuzz\" -DDAMPSYM_SOURCE_DIR=\"$root\" -DDAMPSYM_CASE_SHARDS=1)
# The library sources the readers need (no case shards, runner or CLI: nothing here runs a case;
# the kernel shard because the registry asks which kernel applies to which problem).
lib=(src/harness/case/case.cpp src/harness/case/json.cpp src/harness/case/parse.cpp
     src/harness/case/expect.cpp src/harness/case/util.cpp src/harness/case/figures_key.cpp
     src/harness/user_methods/method_files.cpp src/harness/user_methods/method_file_parse.cpp
     src/harness/run/limits.cpp src/harness/run/memory_limits.cpp src/harness/registry.cpp
     src/harness/bounded_read.cpp build-fuzz/kernel_shard_0.cpp src/harness/run/kernel_ops.cpp
     src/harness/user_methods/method_coefficients.cpp src/methods/partitioned_program.cpp
     src/pde/periodic_grid.cpp src/pde/burgers/schemes.cpp src/pde/klein_gordon/schemes.cpp
     src/pde/nls/schemes.cpp src/methods/families.cpp src/methods/exponential_checks.cpp
     src/harness/report/compare.cpp src/harness/report/compare_input.cpp
     src/harness/report/report.cpp src/harness/report/tables.cpp
     src/harness/ci/shard.cpp src/harness/ci/junit.cpp
     src/diagnostics/*.cpp
     src/methods/catalog.cpp src/methods/tableaux.cpp src/methods/exponential_tableaux.cpp
     src/methods/glm_coefficients.cpp src/methods/coefficient_checks.cpp
     src/methods/exponential_conditions.cpp src/methods/coefficient_expr.cpp
     reference/gsl_reference.cpp reference/kepler_exact.cpp reference/oscillator_exact.cpp
     reference/rigid_body_exact.cpp)
compile() { # source object extra-flags...
  local src="$1" obj="$2"; shift 2
  if [ ! -f "$obj" ] || [ "$src" -nt "$obj" ] || [ -n "$(find src reference tests/fuzz -name '*.hpp' -newer "$obj" -print -quit)" ]; then
    echo "fuzz build: $src"
    nice -n 19 $launcher "$cxx" "${flags[@]}" "$@" -c "$src" -o "$obj"
  fi
}
build() {
  local objs=() running=0
  for s in "${lib[@]}"; do
    local o="$out/obj/$(echo "$s" | tr / _).o"
    # FUZZ_BUILD_JOBS compiles at once (default 2; the machine-wide compiler throttle still applies)
    compile "$s" "$o" -fsanitize=fuzzer-no-link &
    running=$((running + 1))
    if [ "$running" -ge "${FUZZ_BUILD_JOBS:-2}" ]; then wait -n || exit 1; running=$((running - 1)); fi
    objs+=("$o")
  done
  while [ "$running" -gt 0 ]; do wait -n || exit 1; running=$((running - 1)); done
  for t in case set report method plugin; do
    compile "tests/fuzz/fuzz_$t.cpp" "$out/obj/fuzz_$t.o" -fsanitize=fuzzer-no-link
    nice -n 19 "$cxx" -fsanitize=fuzzer,address,undefined -o "$out/fuzz_$t" "$out/obj/fuzz_$t.o" \
      "${objs[@]}" -lgsl -lgslcblas -lquadmath
  done
}
build
[ "${1:-}" = build ] && exit 0
seconds="${1:-600}"
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(case set report method plugin)
for t in "${targets[@]}"; do
  corpus="tests/fuzz/corpus/$t"
  mkdir -p "$corpus" "$out/findings/$t" "$out/scratch/$t"
  seeds=()
  case "$t" in
    case|set) seeds=(verify/cases tests/data/bad tests/data/cases) ;;
    report)   seeds=(tests/fuzz/seeds/report) ;;
    method)   seeds=(examples/methods tests/fuzz/seeds/method) ;;
    plugin)   seeds=() ;; # its committed corpus (dimension, flags, indices written)
  esac
  [ -d tests/fuzz/regressions/$t ] && seeds+=(tests/fuzz/regressions/$t)
  echo "fuzz: $t for ${seconds} s"
  # -max_len: cases are small; 64 KiB lets the fuzzer grow deep nesting and long arrays.
  nice -n 19 "$out/fuzz_$t" "$out/scratch/$t" "$corpus" "${seeds[@]}" -max_total_time="$seconds" \
    -max_len=65536 -timeout=20 -rss_limit_mb=4096 -print_final_stats=1 \
    -artifact_prefix="$out/findings/$t/" 2>&1 | tee "$out/fuzz_$t.log" | grep -E "^#|ERROR|finding|stat::" | tail -n 40
  # Keep the committed corpus small: merge what this run found into it, a set cover of the new
  # coverage edges (without hit counters: -merge=1 would keep every input with a new counter
  # bucket, thousands of files).
  nice -n 19 "$out/fuzz_$t" -set_cover_merge=1 -use_counters=0 "$corpus" "$out/scratch/$t" \
    >/dev/null 2>&1 || true
done
