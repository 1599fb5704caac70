// The shape compare_reports reads (schema/report.schema.json), checked before it reads anything,
// so that a damaged or hostile report is bad input naming the key (exit 2), never a crash (issue
// 17).
#include "harness/compare_input.hpp"

#include "harness/case.hpp"

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

namespace dampsym::compare_detail {
namespace {

using json = nlohmann::json;

// Nesting depth of a document, without recursion (a report nests ~10 deep; the comparison in
// compare.cpp recurses, so a hostile document must not nest deeper than kMaxReportDepth).
constexpr std::size_t kMaxReportDepth = 64;
std::size_t nesting_depth(const json& root) {
    std::size_t deepest = 0;
    std::vector<std::pair<const json*, std::size_t>> stack{{&root, 1}};
    while (!stack.empty()) {
        const auto [node, depth] = stack.back();
        stack.pop_back();
        deepest = std::max(deepest, depth);
        if (depth > kMaxReportDepth) break;
        if (node->is_structured())
            for (const auto& child : *node) stack.emplace_back(&child, depth + 1);
    }
    return deepest;
}

} // namespace

void require_report(const json& r, const std::string& which) {
    if (nesting_depth(r) > kMaxReportDepth)
        throw InputError(which + ": nested deeper than " + std::to_string(kMaxReportDepth) +
                         " levels; not a dampsym report");
    if (!r.is_object() || !r.contains("cases") || !r["cases"].is_array() ||
        !r.contains("schema_version"))
        throw InputError(which + ": not a dampsym report (no schema_version or cases)");
    for (std::size_t i = 0; i < r["cases"].size(); ++i) {
        const json& c = r["cases"][i];
        const std::string where = which + ": cases[" + std::to_string(i) + "]";
        if (!c.is_object() || !c.contains("id") || !c["id"].is_string())
            throw InputError(where + ".id: missing or not a string");
        for (const char* k : {"runs", "checks"})
            if (!c.contains(k) || !c[k].is_array())
                throw InputError(where + "." + k + ": missing or not an array");
        for (const auto& run : c["runs"])
            if (!run.is_object() || !run.contains("method") || !run["method"].is_string() ||
                !run.contains("dt"))
                throw InputError(where + ".runs: a run without method (a string) or dt");
        for (const auto& ck : c["checks"])
            if (!ck.is_object() || !ck.contains("name") || !ck["name"].is_string() ||
                !ck.contains("method") || !ck["method"].is_string() || !ck.contains("passed"))
                throw InputError(where +
                                 ".checks: a check without name, method (strings) or passed");
        if (c.contains("method_metrics")) {
            const json& mm = c["method_metrics"];
            bool ok = mm.is_object();
            for (auto it = mm.begin(); ok && it != mm.end(); ++it) ok = it.value().is_object();
            if (!ok)
                throw InputError(where + ".method_metrics: not an object of objects (per method)");
        }
    }
    // timings (schema 2): only read for the information-only wall-time table
    if (r.contains("timings") && r["timings"].is_object() && r["timings"].contains("cases")) {
        const json& tc = r["timings"]["cases"];
        bool ok = tc.is_array();
        for (std::size_t i = 0; ok && i < tc.size(); ++i) {
            const json& c = tc[i];
            ok = c.is_object() && (!c.contains("id") || c["id"].is_string()) &&
                 (!c.contains("runs_wall_seconds") || c["runs_wall_seconds"].is_number());
        }
        if (!ok)
            throw InputError(which + ": timings.cases: not an array of {id (string), "
                                     "runs_wall_seconds (number)}");
    }
}

} // namespace dampsym::compare_detail
