// libFuzzer target: the report readers of `dampsym compare` and `dampsym merge`
// (compare_reports, merge_reports, and the renderers of their results). The input is read as
// report.json is (nlohmann::json::parse; malformed JSON is exit 2 before these readers), then
// compared with itself and with a small valid report, and merged with it; and, so that a valid
// shard (tests/fuzz/seeds/report holds real ones) reaches the merging itself, merged as shard 1
// of 2 with a copy as shard 2 (its case ids renamed), with and without --allow-mixed. Rejection
// must be an InputError; anything else is a finding.
#include "fuzz_support.hpp"

#include "harness/ci/shard.hpp"
#include "harness/report/compare.hpp"

#include <utility>

namespace {

// A minimal valid report (schema_version 2) with one case, one run, one check.
const char* kReport = R"({
  "schema_version": 2, "tool": {"name": "dampsym", "version": "0"},
  "summary": {"cases": 1, "failed_cases": 0, "runs": 1, "checks_passed": 1, "checks_failed": 0},
  "cases": [{"id": "a", "file": "a.json", "methods": ["csv1"], "dt_ladder": [0.1],
             "runs": [{"method": "csv1", "dt": 0.1, "status": "ok", "steps": 10,
                       "final_state": [1.0, 0.5], "metrics": {"error": {"final_abs": 1e-3}}}],
             "method_metrics": {}, "reference": {"kind": "exact"},
             "checks": [{"name": "e", "method": "csv1", "metric": "error.final_abs",
                         "passed": true, "value": 1e-3}]}],
  "provenance": {"version": "0"},
  "timings": {"wall_seconds": 0.1, "cases": [{"id": "a", "runs_wall_seconds": 0.1,
              "runs": [{"method": "csv1", "dt": 0.1, "wall_seconds": 0.1}]}]}
})";

// The input as two shards of two: itself as shard 1 and a copy as shard 2, the copy's case ids
// suffixed so that the two hold different cases, both selections listing both. (The input itself
// twice if it has no shard.)
std::pair<nlohmann::json, nlohmann::json> as_two_shards(const nlohmann::json& j) {
    nlohmann::json a = j, b = j;
    if (!j.is_object() || !j.contains("provenance") || !j["provenance"].is_object() ||
        !j["provenance"].contains("shard") || !j["provenance"]["shard"].is_object())
        return {a, b};
    if (b.contains("cases") && b["cases"].is_array())
        for (auto& c : b["cases"])
            if (c.is_object() && c.contains("id") && c["id"].is_string())
                c["id"] = c["id"].get<std::string>() + "-b";
    nlohmann::json& sa = a["provenance"]["shard"];
    nlohmann::json& sb = b["provenance"]["shard"];
    sa["index"] = 1;
    sb["index"] = 2;
    sa["count"] = sb["count"] = 2;
    if (sa.contains("selected") && sa["selected"].is_array()) {
        nlohmann::json both = sa["selected"];
        for (const auto& id : sa["selected"])
            if (id.is_string()) both.push_back(id.get<std::string>() + "-b");
        sa["selected"] = sb["selected"] = both;
    }
    return {a, b};
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
    if (j.is_discarded()) return 0; // `dampsym compare/merge`: "malformed JSON", exit 2
    static const nlohmann::json good = nlohmann::json::parse(kReport);
    using dampsym::fuzz::expect_input_error;
    for (bool ignore : {false, true}) {
        dampsym::CompareOptions opt;
        opt.ignore_timings = ignore;
        opt.rtol = ignore ? 1e-12 : 0.0;
        expect_input_error([&] {
            (void)dampsym::render_compare_markdown(dampsym::compare_reports(j, good, opt));
        });
        expect_input_error([&] {
            (void)dampsym::render_compare_markdown(dampsym::compare_reports(good, j, opt));
        });
        expect_input_error(
            [&] { (void)dampsym::render_compare_markdown(dampsym::compare_reports(j, j, opt)); });
    }
    const nlohmann::json prov = {{"version", "0"}};
    expect_input_error([&] { (void)dampsym::merge_reports({j}, {"r0"}, prov); });
    expect_input_error([&] { (void)dampsym::merge_reports({j, good}, {"r0", "r1"}, prov); });
    expect_input_error([&] { (void)dampsym::merge_reports({good, j}, {"r0", "r1"}, prov); });
    // named values, not a structured binding: clang 14 cannot capture one in the lambdas below
    const auto shards = as_two_shards(j);
    const nlohmann::json& s1 = shards.first;
    const nlohmann::json& s2 = shards.second;
    for (bool mixed : {false, true}) {
        expect_input_error([&] {
            (void)dampsym::merge_reports({s1, s2}, {"r0", "r1"}, prov, mixed);
        });
        expect_input_error([&] {
            (void)dampsym::merge_reports({s2, s1}, {"r0", "r1"}, prov, mixed);
        });
    }
    return 0;
}
