#include "harness/ci/shard.hpp"

#include "harness/bounded_read.hpp"
#include "harness/case/case.hpp"
#include "harness/report/compare_input.hpp"
#include "harness/report/report.hpp"

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <map>
#include <numeric>
#include <set>

namespace dampsym {
namespace {

using json = nlohmann::json;

// A non-negative decimal integer, or nullopt.
std::optional<long> parse_count(const std::string& s) {
    if (s.empty() || s.size() > 9 || s.find_first_not_of("0123456789") != std::string::npos)
        return std::nullopt;
    return std::strtol(s.c_str(), nullptr, 10);
}

} // namespace

ShardSpec parse_shard(const std::string& text) {
    const auto slash = text.find('/');
    const auto k = slash == std::string::npos ? std::nullopt : parse_count(text.substr(0, slash));
    const auto n = slash == std::string::npos ? std::nullopt : parse_count(text.substr(slash + 1));
    if (!k || !n || *n < 1 || *k < 1 || *k > *n)
        throw InputError("--shard " + quote_for_message(text) +
                         ": expected K/N with 1 <= K <= N, e.g. 2/4");
    if (*n > kMaxShards)
        throw InputError("--shard " + text + ": at most " + std::to_string(kMaxShards) + " shards");
    return {static_cast<int>(*k), static_cast<int>(*n), "--shard"};
}

std::optional<ShardSpec> shard_from_env(const EnvLookup& env) {
    struct Convention {
        const char *total, *index;
        int base; // index of the first shard
    };
    const Convention conventions[] = {{"TEST_TOTAL_SHARDS", "TEST_SHARD_INDEX", 0},
                                      {"CI_NODE_TOTAL", "CI_NODE_INDEX", 1},
                                      {"SLURM_ARRAY_TASK_COUNT", "SLURM_ARRAY_TASK_ID", -1}};
    for (const auto& cv : conventions) {
        const char* total = env(cv.total);
        const char* index = env(cv.index);
        if (!total || !index) continue;
        const auto n = parse_count(total);
        const auto i = parse_count(index);
        const std::string names = std::string(cv.total) + "/" + cv.index;
        if (!n || *n < 1)
            throw InputError(std::string(cv.total) + "=" + quote_for_message(total) +
                             ": not a count");
        if (*n > kMaxShards)
            throw InputError(std::string(cv.total) + "=" + total + ": at most " +
                             std::to_string(kMaxShards) + " shards");
        if (!i)
            throw InputError(std::string(cv.index) + "=" + quote_for_message(index) +
                             ": not an index");
        long base = cv.base;
        if (base < 0) { // Slurm: task ids start at SLURM_ARRAY_TASK_MIN
            const char* min = env("SLURM_ARRAY_TASK_MIN");
            const auto m = min ? parse_count(min) : std::optional<long>(0);
            if (!m)
                throw InputError(std::string("SLURM_ARRAY_TASK_MIN=") + quote_for_message(min) +
                                 ": not an index");
            base = *m;
        }
        const long k = *i - base + 1;
        if (k < 1 || k > *n)
            throw InputError(std::string(cv.index) + "=" + index + ": outside the " +
                             std::to_string(*n) + " shards of " + cv.total);
        if (cv.base == 0)
            if (const char* status = env("TEST_SHARD_STATUS_FILE")) {
                // a FIFO would block the open until a reader comes: regular files only
                if (const auto why = not_regular_reason(status, true); !why.empty())
                    throw InputError("TEST_SHARD_STATUS_FILE=" + quote_for_message(status) + ": " +
                                     why);
                std::ofstream touch(status);
            }
        return ShardSpec{static_cast<int>(k), static_cast<int>(*n), names};
    }
    return std::nullopt;
}

std::vector<int> assign_shards(const std::vector<double>& costs,
                               const std::vector<std::string>& keys, int count) {
    std::vector<std::size_t> order(costs.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        if (costs[a] != costs[b]) return costs[a] > costs[b];
        return keys[a] < keys[b];
    });
    std::vector<double> load(static_cast<std::size_t>(count), 0.0);
    std::vector<int> shard(costs.size(), 0);
    for (const std::size_t i : order) {
        const auto best = std::min_element(load.begin(), load.end()) - load.begin();
        shard[i] = static_cast<int>(best);
        load[static_cast<std::size_t>(best)] += costs[i];
    }
    return shard;
}

std::vector<double> estimate_costs(const std::vector<std::string>& ids,
                                   const std::vector<double>& steps, const json& measured) {
    auto measured_of = [&](const std::string& id) -> std::optional<double> {
        if (measured.is_object() && measured.contains(id) && measured[id].is_number())
            return measured[id].get<double>();
        return std::nullopt;
    };
    std::vector<double> per_step;
    for (std::size_t i = 0; i < ids.size(); ++i)
        if (const auto m = measured_of(ids[i]); m && steps[i] > 0.0)
            per_step.push_back(*m / steps[i]);
    double k = 1e-7;
    if (!per_step.empty()) {
        std::sort(per_step.begin(), per_step.end());
        k = per_step[per_step.size() / 2];
    }
    std::vector<double> out;
    for (std::size_t i = 0; i < ids.size(); ++i) {
        const auto m = measured_of(ids[i]);
        out.push_back(m ? *m : k * std::max(steps[i], 1.0));
    }
    return out;
}

namespace {

const json* shard_of(const json& r) {
    if (r.contains("provenance") && r["provenance"].is_object() &&
        r["provenance"].contains("shard") && r["provenance"]["shard"].is_object())
        return &r["provenance"]["shard"];
    return nullptr;
}

// r at a path of object keys, or null.
json at_path(const json& r, std::initializer_list<const char*> path) {
    const json* p = &r;
    for (const char* k : path) {
        if (!p->is_object() || !p->contains(k)) return nullptr;
        p = &(*p)[k];
    }
    return *p;
}

// The shape merge_reports reads (schema/report.schema.json), checked before it reads anything, so
// that a damaged or hostile report is bad input naming the key (exit 2), never a crash.
void require_mergeable(const json& r, const std::string& name) {
    compare_detail::require_current_report(r, name);
    auto bad = [&](const std::string& key, const std::string& what) {
        throw InputError(name + ": " + key + ": " + what + "; not a dampsym report");
    };
    if (!r.contains("provenance") || !r["provenance"].is_object())
        bad("provenance", "missing or not an object");
    const json& p = r["provenance"];
    if (p.contains("shard")) {
        const json& s = p["shard"];
        if (!s.is_object()) bad("provenance.shard", "not an object");
        for (const char* k : {"count", "index"})
            if (!s.contains(k) || !s[k].is_number_integer() || s[k].get<std::int64_t>() < 1 ||
                s[k].get<std::int64_t>() > kMaxShards)
                bad(std::string("provenance.shard.") + k,
                    "missing or not a count from 1 to " + std::to_string(kMaxShards));
        if (s["index"].get<std::int64_t>() > s["count"].get<std::int64_t>())
            bad("provenance.shard.index", "larger than provenance.shard.count");
        if (!s.contains("selected") || !s["selected"].is_array())
            bad("provenance.shard.selected", "missing or not an array");
        for (const auto& id : s["selected"])
            if (!id.is_string()) bad("provenance.shard.selected", "not an array of ids");
    }
}

// What must agree between the reports merged: the build (commit, type) and what was run (the
// overrides and the selection; for reports that are not shards of one selection, only the
// overrides and methods, since their cases differ by design).
std::vector<std::pair<std::string, json>> merge_identity(const json& r, bool sharded) {
    std::vector<std::pair<std::string, json>> out{
        {"provenance.build.git_commit", at_path(r, {"provenance", "build", "git_commit"})},
        {"provenance.build.build_type", at_path(r, {"provenance", "build", "build_type"})},
        {"provenance.selection.sets", at_path(r, {"provenance", "selection", "sets"})},
        {"provenance.selection.methods", at_path(r, {"provenance", "selection", "methods"})}};
    if (sharded)
        for (const char* k :
             {"targets", "suites", "filters", "problems", "method_files", "plugins"})
            out.emplace_back(std::string("provenance.selection.") + k,
                             at_path(r, {"provenance", "selection", k}));
    return out;
}

// Each report against the first: schema, tool, then the identity (refused unless allow_mixed;
// the differences are returned, for the merged provenance's "mixed").
json check_reports(const std::vector<json>& reports, const std::vector<std::string>& names,
                   bool allow_mixed) {
    for (std::size_t i = 0; i < reports.size(); ++i) require_mergeable(reports[i], names[i]);
    const bool sharded = shard_of(reports[0]) != nullptr;
    const auto first = merge_identity(reports[0], sharded);
    json mixed = json::array();
    for (std::size_t i = 1; i < reports.size(); ++i) {
        const json& r = reports[i];
        if (r["tool"] != reports[0]["tool"])
            throw InputError(names[i] + ": tool: " + quote_for_message(r["tool"].dump()) +
                             " differs from " + names[0] + "'s " +
                             quote_for_message(reports[0]["tool"].dump()));
        const auto mine = merge_identity(r, sharded);
        for (std::size_t k = 0; k < mine.size(); ++k) {
            if (mine[k].second == first[k].second) continue;
            const std::string what = names[i] + ": " + mine[k].first + ": " +
                                     quote_for_message(mine[k].second.dump()) + " differs from " +
                                     names[0] + "'s " + quote_for_message(first[k].second.dump());
            if (!allow_mixed) throw InputError(what + " (--allow-mixed merges them, and says so)");
            mixed.push_back(what);
        }
    }
    return mixed;
}

// The case order: that of the unsharded selection when the reports are shards of one, else the
// reports' cases in turn.
std::vector<std::string> case_order(const std::vector<json>& reports,
                                    const std::vector<std::string>& names) {
    std::vector<std::string> order;
    if (!shard_of(reports[0])) {
        for (std::size_t i = 0; i < reports.size(); ++i) {
            if (shard_of(reports[i]))
                throw InputError(names[i] + ": provenance.shard: a shard, but " + names[0] +
                                 " is not");
            for (const auto& c : reports[i]["cases"]) order.push_back(c["id"].get<std::string>());
        }
        return order;
    }
    const json& first = *shard_of(reports[0]);
    const auto count = first["count"].get<std::int64_t>();
    std::map<std::int64_t, std::string> seen;
    for (std::size_t i = 0; i < reports.size(); ++i) {
        const json* s = shard_of(reports[i]);
        if (!s)
            throw InputError(names[i] + ": provenance.shard: missing, but " + names[0] +
                             " is a shard");
        if ((*s)["count"] != first["count"] || (*s)["selected"] != first["selected"])
            throw InputError(names[i] + ": provenance.shard: shard of another selection than " +
                             names[0]);
        const auto k = (*s)["index"].get<std::int64_t>();
        if (seen.count(k))
            throw InputError(names[i] + ": provenance.shard.index: shard " + std::to_string(k) +
                             "/" + std::to_string(count) + " is also " + seen[k]);
        seen[k] = names[i];
    }
    for (std::int64_t k = 1; k <= count; ++k)
        if (!seen.count(k))
            throw InputError("merge: shard " + std::to_string(k) + "/" + std::to_string(count) +
                             " is missing");
    for (const auto& id : first["selected"]) order.push_back(id.get<std::string>());
    return order;
}

// Case records and their timings entries, by id; every id once.
using CaseRecords = std::map<std::string, std::pair<const json*, const json*>>;
CaseRecords collect_cases(const std::vector<json>& reports, const std::vector<std::string>& names) {
    CaseRecords by_id;
    std::map<std::string, std::string> from;
    for (std::size_t i = 0; i < reports.size(); ++i) {
        const json& r = reports[i];
        const json& tc = r["timings"]["cases"];
        for (std::size_t ci = 0; ci < r["cases"].size(); ++ci) {
            const std::string id = r["cases"][ci]["id"].get<std::string>();
            if (by_id.count(id))
                throw InputError(names[i] + ": cases: '" + quote_for_message(id) + "' is also in " +
                                 from[id]);
            const json* t = ci < tc.size() && tc[ci]["id"] == id ? &tc[ci] : nullptr;
            by_id[id] = {&r["cases"][ci], t};
            from[id] = names[i];
        }
    }
    return by_id;
}

} // namespace

json merge_reports(const std::vector<json>& reports, const std::vector<std::string>& names,
                   const json& merge_provenance, bool allow_mixed) {
    if (reports.empty()) throw InputError("merge: no shard reports given");
    const json mixed = check_reports(reports, names, allow_mixed);
    const std::vector<std::string> order = case_order(reports, names);
    const CaseRecords by_id = collect_cases(reports, names);
    if (by_id.size() != order.size())
        throw InputError("merge: the shards hold " + std::to_string(by_id.size()) +
                         " cases, their selection " + std::to_string(order.size()));
    if (order.empty()) throw InputError("merge: the reports hold no case; nothing to merge");
    json cases = json::array(), tcases = json::array();
    for (const auto& id : order) {
        const auto it = by_id.find(id);
        if (it == by_id.end())
            throw InputError("merge: case '" + quote_for_message(id) + "' is in no shard");
        cases.push_back(*it->second.first);
        tcases.push_back(it->second.second ? *it->second.second
                                           : json{{"id", id}, {"runs", json::array()}});
    }
    json timings = {{"cases", tcases}};
    json shards = json::array();
    double wall = 0.0;
    for (std::size_t i = 0; i < reports.size(); ++i) {
        const json& r = reports[i];
        json entry = {{"report", names[i]}};
        if (const json* s = shard_of(r)) entry["shard"] = (*s)["index"];
        entry["wall_seconds"] = r["timings"]["wall_seconds"];
        wall = std::max(wall, r["timings"]["wall_seconds"].get<double>());
        shards.push_back(entry);
    }
    timings["wall_seconds"] = wall; // the slowest shard: the elapsed time of a parallel run
    timings["shards"] = shards;
    for (const char* k : {"time_budget_seconds", "protocol"})
        if (reports[0]["timings"].contains(k)) timings[k] = reports[0]["timings"][k];
    json prov = merge_provenance;
    json parts = json::array();
    for (const auto& r : reports) parts.push_back(r["provenance"]);
    prov["merged_from"] = parts;
    if (!mixed.empty()) prov["mixed"] = mixed; // --allow-mixed: what differed
    json merged = {{"schema_version", reports[0]["schema_version"]},
                   {"tool", reports[0]["tool"]},
                   {"summary", summarize(cases)},
                   {"cases", cases},
                   {"provenance", prov},
                   {"timings", timings}};
    for (const auto& r : reports) // a shard stopped by a signal leaves the merged run incomplete
        if (r.contains("interrupted")) {
            merged["interrupted"] = r["interrupted"];
            break;
        }
    return merged;
}

} // namespace dampsym
