// Splitting a selection of cases over CI jobs or cluster nodes, and putting the pieces together.
//
// `--shard K/N` (1 <= K <= N) runs a deterministic, cost-balanced share of the selected cases:
// cases are taken in decreasing estimated cost (ties by id) and each goes to the shard with the
// least estimated cost so far (ties: lowest index), so every case is in exactly one shard and
// every shard computes the same assignment. The estimate is the committed measured run time of
// the case (verify/case_costs.json, written by ci/case_costs.sh), else its step count scaled by
// the median seconds per step of the cases that have both.
//
// Without --shard, the conventions of existing engines are read (both variables of a pair must
// be set): Bazel TEST_TOTAL_SHARDS / TEST_SHARD_INDEX (0-based; TEST_SHARD_STATUS_FILE is
// touched), GitLab CI_NODE_TOTAL / CI_NODE_INDEX (1-based), Slurm job arrays
// SLURM_ARRAY_TASK_COUNT / SLURM_ARRAY_TASK_ID (minus SLURM_ARRAY_TASK_MIN).
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace dampsym {

// The most shards --shard and the engines' variables may ask for: assign_shards keeps a load per
// shard, and 999999999 shards once cost 7.5 GB before any case ran.
constexpr long kMaxShards = 10000;

struct ShardSpec {
    int index = 1; // 1-based
    int count = 1;
    std::string source; // "--shard", "TEST_TOTAL_SHARDS/TEST_SHARD_INDEX", ...
};

using EnvLookup = std::function<const char*(const char*)>;

// Parses "K/N". Throws InputError naming --shard.
ShardSpec parse_shard(const std::string& text);

// The shard from the environment, or none. Throws InputError naming the variable.
std::optional<ShardSpec> shard_from_env(const EnvLookup& env);

// Shard (0-based) of each item, balancing the sum of costs (LPT; ties by key).
std::vector<int> assign_shards(const std::vector<double>& costs,
                               const std::vector<std::string>& keys, int count);

// Estimated cost (seconds) of each case: measured[id] if present, else steps[i] times the median
// seconds per step of the cases that have both (1e-7 s per step when none has).
std::vector<double> estimate_costs(const std::vector<std::string>& ids,
                                   const std::vector<double>& steps,
                                   const nlohmann::json& measured);

// Merges the report.json of each shard (names: for messages) into one report whose byte-stable
// part is that of the unsharded run. Throws InputError if a report is malformed (the keys
// compare_detail::require_current_report checks), holds no case, if a shard is missing or
// repeated, or if the reports differ in commit, build type, overrides (--set) or selection
// (--method, --filter, --problem, --suite, case ids); with allow_mixed the last four are allowed
// and listed in the merged provenance's "mixed". An "interrupted" mark of any report is kept.
nlohmann::json merge_reports(const std::vector<nlohmann::json>& reports,
                             const std::vector<std::string>& names,
                             const nlohmann::json& merge_provenance, bool allow_mixed = false);

} // namespace dampsym
