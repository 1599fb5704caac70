#include "harness/shard.hpp"

#include "harness/case.hpp"
#include "harness/report.hpp"

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
        throw InputError("--shard " + text + ": expected K/N with 1 <= K <= N, e.g. 2/4");
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
        if (!n || *n < 1) throw InputError(std::string(cv.total) + "=" + total + ": not a count");
        if (!i) throw InputError(std::string(cv.index) + "=" + index + ": not an index");
        long base = cv.base;
        if (base < 0) { // Slurm: task ids start at SLURM_ARRAY_TASK_MIN
            const char* min = env("SLURM_ARRAY_TASK_MIN");
            const auto m = min ? parse_count(min) : std::optional<long>(0);
            if (!m) throw InputError(std::string("SLURM_ARRAY_TASK_MIN=") + min + ": not an index");
            base = *m;
        }
        const long k = *i - base + 1;
        if (k < 1 || k > *n)
            throw InputError(std::string(cv.index) + "=" + index + ": outside the " +
                             std::to_string(*n) + " shards of " + cv.total);
        if (cv.base == 0)
            if (const char* status = env("TEST_SHARD_STATUS_FILE")) std::ofstream touch(status);
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

// The shape merge_reports reads (schema/report.schema.json), checked before it reads anything, so
// that a damaged or hostile report is bad input naming the key (exit 2), never a crash.
void require_mergeable(const json& r, const std::string& name) {
    auto bad = [&](const std::string& key, const std::string& what) {
        throw InputError(name + ": " + key + ": " + what + "; not a dampsym report");
    };
    if (!r.is_object()) bad("(top level)", "not an object");
    if (!r.contains("cases") || !r["cases"].is_array()) bad("cases", "missing or not an array");
    if (!r.contains("schema_version") || !r["schema_version"].is_number_integer())
        bad("schema_version", "missing or not an integer");
    if (!r.contains("tool")) bad("tool", "missing");
    for (std::size_t i = 0; i < r["cases"].size(); ++i) {
        const json& c = r["cases"][i];
        const std::string where = "cases[" + std::to_string(i) + "]";
        if (!c.is_object() || !c.contains("id") || !c["id"].is_string())
            bad(where + ".id", "missing or not a string");
        if (!c.contains("runs") || !c["runs"].is_array())
            bad(where + ".runs", "missing or not an array");
        if (!c.contains("checks") || !c["checks"].is_array())
            bad(where + ".checks", "missing or not an array");
        for (const auto& ck : c["checks"])
            if (!ck.is_object() || !ck.contains("passed") || !ck["passed"].is_boolean())
                bad(where + ".checks", "a check without passed (true/false)");
    }
    if (r.contains("provenance")) {
        const json& p = r["provenance"];
        if (!p.is_object()) bad("provenance", "not an object");
        if (p.contains("shard") && p["shard"].is_object()) {
            const json& s = p["shard"];
            for (const char* k : {"count", "index"})
                if (!s.contains(k) || !s[k].is_number_integer() || s[k].get<std::int64_t>() < 1 ||
                    s[k].get<std::int64_t>() > 1000000)
                    bad(std::string("provenance.shard.") + k, "missing or not a count");
            if (!s.contains("selected") || !s["selected"].is_array())
                bad("provenance.shard.selected", "missing or not an array");
            for (const auto& id : s["selected"])
                if (!id.is_string()) bad("provenance.shard.selected", "not an array of ids");
        }
    }
    if (r.contains("timings")) {
        const json& t = r["timings"];
        if (!t.is_object()) bad("timings", "not an object");
        if (t.contains("wall_seconds") && !t["wall_seconds"].is_number())
            bad("timings.wall_seconds", "not a number");
        if (t.contains("cases")) {
            if (!t["cases"].is_array()) bad("timings.cases", "not an array");
            for (const auto& c : t["cases"])
                if (!c.is_object() || !c.contains("id"))
                    bad("timings.cases", "an entry without id");
        }
    }
}

} // namespace

json merge_reports(const std::vector<json>& reports, const std::vector<std::string>& names,
                   const json& merge_provenance) {
    if (reports.empty()) throw InputError("merge: no shard reports given");
    for (std::size_t i = 0; i < reports.size(); ++i) {
        const json& r = reports[i];
        require_mergeable(r, names[i]);
        if (r.value("schema_version", 0) != kReportSchemaVersion)
            throw InputError(names[i] +
                             ": schema_version: " + r.value("schema_version", json()).dump() +
                             ", expected " + std::to_string(kReportSchemaVersion));
        if (r["tool"] != reports[0]["tool"])
            throw InputError(names[i] + ": tool: " + r["tool"].dump() + " differs from " +
                             names[0] + "'s " + reports[0]["tool"].dump());
    }
    auto shard_of = [](const json& r) -> const json* {
        if (r.contains("provenance") && r["provenance"].contains("shard") &&
            r["provenance"]["shard"].is_object())
            return &r["provenance"]["shard"];
        return nullptr;
    };
    // The case order: that of the unsharded selection when the reports are shards of one.
    std::vector<std::string> order;
    const bool sharded = shard_of(reports[0]) != nullptr;
    if (sharded) {
        const json& first = *shard_of(reports[0]);
        const int count = first.value("count", 0);
        std::map<int, std::string> seen;
        for (std::size_t i = 0; i < reports.size(); ++i) {
            const json* s = shard_of(reports[i]);
            if (!s)
                throw InputError(names[i] + ": provenance.shard: missing, but " + names[0] +
                                 " is a shard");
            if (s->value("count", 0) != count || (*s)["selected"] != first["selected"])
                throw InputError(names[i] +
                                 ": provenance.shard: shard of another selection "
                                 "than " +
                                 names[0]);
            const int k = s->value("index", 0);
            if (seen.count(k))
                throw InputError(names[i] + ": provenance.shard.index: shard " + std::to_string(k) +
                                 "/" + std::to_string(count) + " is also " + seen[k]);
            seen[k] = names[i];
        }
        for (int k = 1; k <= count; ++k)
            if (!seen.count(k))
                throw InputError("merge: shard " + std::to_string(k) + "/" + std::to_string(count) +
                                 " is missing");
        for (const auto& id : first["selected"]) order.push_back(id.get<std::string>());
    } else {
        for (std::size_t i = 0; i < reports.size(); ++i) {
            if (shard_of(reports[i]))
                throw InputError(names[i] + ": provenance.shard: a shard, but " + names[0] +
                                 " is not");
            for (const auto& c : reports[i]["cases"]) order.push_back(c["id"].get<std::string>());
        }
    }
    // Case records and their timings, by id.
    std::map<std::string, std::pair<const json*, const json*>> by_id;
    std::map<std::string, std::string> from;
    for (std::size_t i = 0; i < reports.size(); ++i) {
        const json& r = reports[i];
        for (std::size_t ci = 0; ci < r["cases"].size(); ++ci) {
            const std::string id = r["cases"][ci]["id"].get<std::string>();
            if (by_id.count(id))
                throw InputError(names[i] + ": cases: '" + id + "' is also in " + from[id]);
            const json* t = nullptr;
            if (r.contains("timings") && r["timings"].contains("cases") &&
                ci < r["timings"]["cases"].size() && r["timings"]["cases"][ci]["id"] == id)
                t = &r["timings"]["cases"][ci];
            by_id[id] = {&r["cases"][ci], t};
            from[id] = names[i];
        }
    }
    if (by_id.size() != order.size())
        throw InputError("merge: the shards hold " + std::to_string(by_id.size()) +
                         " cases, their selection " + std::to_string(order.size()));
    json cases = json::array(), tcases = json::array();
    for (const auto& id : order) {
        const auto it = by_id.find(id);
        if (it == by_id.end()) throw InputError("merge: case '" + id + "' is in no shard");
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
        if (r.contains("timings") && r["timings"].contains("wall_seconds")) {
            entry["wall_seconds"] = r["timings"]["wall_seconds"];
            wall = std::max(wall, r["timings"]["wall_seconds"].get<double>());
        }
        shards.push_back(entry);
    }
    timings["wall_seconds"] = wall; // the slowest shard: the elapsed time of a parallel run
    timings["shards"] = shards;
    if (reports[0].contains("timings"))
        for (const char* k : {"time_budget_seconds", "protocol"})
            if (reports[0]["timings"].contains(k)) timings[k] = reports[0]["timings"][k];
    json prov = merge_provenance;
    json parts = json::array();
    for (const auto& r : reports) parts.push_back(r.value("provenance", json::object()));
    prov["merged_from"] = parts;
    json summary = summarize(cases);
    return {{"schema_version", reports[0]["schema_version"]},
            {"tool", reports[0]["tool"]},
            {"summary", summary},
            {"cases", cases},
            {"provenance", prov},
            {"timings", timings}};
}

} // namespace dampsym
