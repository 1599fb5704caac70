#!/usr/bin/env bash
# Coefficient mutants of every built-in method whose coefficients are data (docs/mutation.md):
# builds dampsym (Release, build/), then ci/mutants.py: each coefficient of each exported built-in
# multiplied by (1 + 1e-6) in turn, each mutant through `methods --check`, `matrix` and the
# default-suite cases of its built-in (`run --substitute`), on 2 processes. Prints the per-stage
# and total scores and the survivors; writes build/mutants/results.json. Exit 1 if a coefficient
# mutant survives without a proof of equivalence, 2 on bad input. About 3 minutes on 2 cores
# (docs/mutation.md), so it runs in ci/bench.sh, not in .ci/run. Arguments go to ci/mutants.py
# (--method ID: one built-in only; --first-kill: stop at a mutant's first killing stage).
set -euo pipefail
cd "$(dirname "$0")/.."
bash ci/build.sh release dampsym
exec /usr/bin/python3 ci/mutants.py --dampsym build/dampsym --jobs "${DAMPSYM_MUTANT_JOBS:-2}" "$@"
