#!/usr/bin/env bash
# Measures every case's run time alone (Release binary, --jobs 1, the default --time-budget for
# ladder cases except the stress suite's) and writes verify/case_costs.json, the committed cost
# estimate `dampsym run --shard K/N` balances by. Run on a quiet machine after adding or changing
# cases; a case missing from the file falls back to its step count.
# Usage: bash ci/case_costs.sh [BUILD_DIR]   (default build)
set -euo pipefail
cd "$(dirname "$0")/.."
bin="${1:-build}/dampsym"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
"$bin" list --json > "$tmp/list.json"
/usr/bin/python3 - "$bin" "$tmp" <<'PY'
import json, subprocess, sys
bin_, tmp = sys.argv[1], sys.argv[2]
cases = json.load(open(tmp + "/list.json"))["cases"]
costs = {}
for c in cases:
    extra = ["--time-budget", "0"] if "stress" in c["suites"] else []
    subprocess.run([bin_, "run", c["id"], "--jobs", "1", "--quiet", "--shard", "none",
                    "--out", tmp + "/r"] + extra, check=False, stdout=subprocess.DEVNULL)
    costs[c["id"]] = round(json.load(open(tmp + "/r/report.json"))["timings"]["wall_seconds"], 4)
out = {"description": "seconds per case, run alone with --jobs 1 (ci/case_costs.sh); the cost "
                      "estimate of dampsym run --shard",
       "cases": dict(sorted(costs.items()))}
with open("verify/case_costs.json", "w") as fh:
    json.dump(out, fh, indent=2)
    fh.write("\n")
print("verify/case_costs.json: %d cases, %.1f s in total" % (len(costs), sum(costs.values())))
PY
