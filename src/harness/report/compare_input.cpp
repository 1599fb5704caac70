// The shape compare_reports and merge_reports read (schema/report.schema.json), checked before
// they read anything, so that a damaged or hostile report is bad input naming the key (exit 2),
// never a crash or an internal error.
#include "harness/report/compare_input.hpp"

#include "harness/bounded_read.hpp"
#include "harness/case/case.hpp"
#include "harness/report/report.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <set>
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

enum class T { string, number, count, boolean, object, array, strings, numbers, run_status };

bool has_type(const json& v, T t) {
    auto all = [&](auto pred) { return v.is_array() && std::all_of(v.begin(), v.end(), pred); };
    switch (t) {
    case T::string:
        return v.is_string();
    case T::number:
        return v.is_number();
    case T::count:
        return v.is_number_unsigned() || (v.is_number_integer() && v.get<long long>() >= 0);
    case T::boolean:
        return v.is_boolean();
    case T::object:
        return v.is_object();
    case T::array:
        return v.is_array();
    case T::strings:
        return all([](const json& x) { return x.is_string(); });
    case T::numbers:
        return all([](const json& x) { return x.is_number(); });
    case T::run_status: {
        static const std::set<std::string> ok{
            "ok", "diverged", "solve-failed", "not-applicable", "timeout", "interrupted", "error"};
        return v.is_string() && ok.count(v.get<std::string>()) > 0;
    }
    }
    return false;
}

const char* type_name(T t) {
    switch (t) {
    case T::string:
        return "a string";
    case T::number:
        return "a number";
    case T::count:
        return "a non-negative integer";
    case T::boolean:
        return "true or false";
    case T::object:
        return "an object";
    case T::array:
        return "an array";
    case T::strings:
        return "an array of strings";
    case T::numbers:
        return "an array of numbers";
    case T::run_status:
        return "a run status (ok, diverged, solve-failed, ...)";
    }
    return "";
}

struct Field {
    const char* key;
    T type;
    bool required;
};

// Keys of schema_version 1 (compare only): what compare matches by.
const std::vector<Field> kCase1{{"id", T::string, true},
                                {"runs", T::array, true},
                                {"checks", T::array, true},
                                {"method_metrics", T::object, false}};
const std::vector<Field> kRun1{{"method", T::string, true}, {"dt", T::number, true}};
const std::vector<Field> kCheck1{{"name", T::string, true},
                                 {"method", T::string, true},
                                 {"passed", T::boolean, true},
                                 {"dt", T::number, false}};
// The current schema's required keys, and the optional ones the renderers read.
const std::vector<Field> kCase{
    {"id", T::string, true},         {"title", T::string, true},
    {"source", T::string, true},     {"file", T::string, true},
    {"problem", T::object, true},    {"methods", T::strings, true},
    {"t0", T::number, true},         {"t_end", T::number, true},
    {"dt_ladder", T::numbers, true}, {"diagnostics", T::strings, true},
    {"overrides", T::object, true},  {"reference", T::object, true},
    {"runs", T::array, true},        {"method_metrics", T::object, true},
    {"checks", T::array, true},      {"no_checks_because", T::string, false},
    {"measures", T::object, false},  {"errors", T::strings, false}};
const std::vector<Field> kRun{{"method", T::string, true},         {"dt", T::number, true},
                              {"steps_planned", T::count, true},   {"status", T::run_status, true},
                              {"steps", T::count, true},           {"metrics", T::object, true},
                              {"failed_at_step", T::count, false}, {"error", T::string, false},
                              {"final_state", T::array, false},    {"observed", T::object, false}};
const std::vector<Field> kCheck{
    {"name", T::string, true},       {"metric", T::string, true},
    {"method", T::string, true},     {"op", T::string, true},
    {"expected", T::number, true},   {"negative_control", T::boolean, true},
    {"passed", T::boolean, true},    {"dt", T::number, false},
    {"tolerance", T::number, false}, {"note", T::string, false},
    {"message", T::string, false},   {"methods", T::strings, false}};

void require_fields(const json& v, const std::vector<Field>& fields, const std::string& where) {
    if (!v.is_object()) throw InputError(where + ": not an object");
    for (const auto& f : fields) {
        if (!v.contains(f.key)) {
            if (f.required) throw InputError(where + "." + f.key + ": missing");
            continue;
        }
        if (!has_type(v[f.key], f.type))
            throw InputError(where + "." + f.key + ": " + quote_for_message(v[f.key].dump(), 60) +
                             ", expected " + type_name(f.type));
    }
}

void require_case(const json& c, const std::string& where, bool current) {
    require_fields(c, current ? kCase : kCase1, where);
    std::set<std::string> runs, checks;
    for (std::size_t j = 0; j < c["runs"].size(); ++j) {
        const std::string w = where + ".runs[" + std::to_string(j) + "]";
        require_fields(c["runs"][j], current ? kRun : kRun1, w);
        if (!runs.insert(run_key(c["runs"][j])).second)
            throw InputError(w + ": run " + quote_for_message(run_key(c["runs"][j])) +
                             " given twice (method and dt identify a run)");
    }
    for (std::size_t j = 0; j < c["checks"].size(); ++j) {
        const std::string w = where + ".checks[" + std::to_string(j) + "]";
        require_fields(c["checks"][j], current ? kCheck : kCheck1, w);
        if (current && c["checks"][j].contains("value") && !c["checks"][j]["value"].is_number() &&
            !c["checks"][j]["value"].is_null())
            throw InputError(w + ".value: expected a number or null");
        if (!checks.insert(check_key(c["checks"][j])).second)
            throw InputError(w + ": check " + quote_for_message(check_key(c["checks"][j])) +
                             " given twice (name, method and dt identify a check)");
    }
    if (c.contains("method_metrics"))
        for (auto it = c["method_metrics"].begin(); it != c["method_metrics"].end(); ++it)
            if (!it.value().is_object())
                throw InputError(where + ".method_metrics." + quote_for_message(it.key()) +
                                 ": expected an object (per method)");
}

void require_timings(const json& r, const std::string& which, bool current) {
    if (!r.contains("timings")) {
        if (current) throw InputError(which + ": timings: missing");
        return;
    }
    const json& t = r["timings"];
    if (!t.is_object()) throw InputError(which + ": timings: expected an object");
    if (current || t.contains("wall_seconds"))
        require_fields(t, {{"wall_seconds", T::number, true}}, which + ": timings");
    if (!t.contains("cases")) {
        if (current) throw InputError(which + ": timings.cases: missing");
        return;
    }
    if (!t["cases"].is_array()) throw InputError(which + ": timings.cases: expected an array");
    for (std::size_t i = 0; i < t["cases"].size(); ++i) {
        const std::string w = which + ": timings.cases[" + std::to_string(i) + "]";
        require_fields(t["cases"][i],
                       {{"id", T::string, true},
                        {"runs", T::array, current},
                        {"runs_wall_seconds", T::number, false}},
                       w);
        if (current)
            for (const auto& run : t["cases"][i]["runs"])
                require_fields(run, {{"method", T::string, true}, {"dt", T::number, true}},
                               w + ".runs[]");
    }
}

void require_header(const json& r, const std::string& which, bool merge) {
    if (nesting_depth(r) > kMaxReportDepth)
        throw InputError(which + ": nested deeper than " + std::to_string(kMaxReportDepth) +
                         " levels; not a dampsym report");
    if (!r.is_object() || !r.contains("cases") || !r.contains("schema_version"))
        throw InputError(which + ": not a dampsym report (no schema_version or cases)");
    const json& v = r["schema_version"];
    const bool known = v.is_number_integer() && (v.get<long long>() == kReportSchemaVersion ||
                                                 (!merge && v.get<long long>() == 1));
    if (!known)
        throw InputError(which + ": schema_version: " + quote_for_message(v.dump(), 60) +
                         ", expected " + std::to_string(kReportSchemaVersion) +
                         (merge ? "" : " (or 1, the format before the timings section)"));
    if (v.get<long long>() >= 2) {
        if (!r.contains("tool") || !r["tool"].is_object() ||
            r["tool"].value("name", json()) != "dampsym")
            throw InputError(which + ": tool: missing or not {\"name\": \"dampsym\", ...}");
    }
    if (!r["cases"].is_array()) throw InputError(which + ": cases: expected an array");
}

void require(const json& r, const std::string& which, bool merge) {
    require_header(r, which, merge);
    const bool current = r["schema_version"].get<long long>() == kReportSchemaVersion;
    std::set<std::string> ids;
    for (std::size_t i = 0; i < r["cases"].size(); ++i) {
        const std::string where = which + ": cases[" + std::to_string(i) + "]";
        require_case(r["cases"][i], where, current);
        // ids become file names (plot, --figures) and keys: validated as a case file's are
        if (!valid_case_id(r["cases"][i]["id"].get<std::string>()))
            throw InputError(where +
                             ".id: " + quote_for_message(r["cases"][i]["id"].get<std::string>()) +
                             " is not a valid case id (1 to 100 characters of A-Z a-z 0-9 . _ -, "
                             "starting with a letter or digit)");
        if (!ids.insert(r["cases"][i]["id"].get<std::string>()).second)
            throw InputError(where +
                             ".id: " + quote_for_message(r["cases"][i]["id"].get<std::string>()) +
                             " given twice");
    }
    require_timings(r, which, current);
    if (r.contains("interrupted") && !r["interrupted"].is_object())
        throw InputError(which + ": interrupted: expected an object");
}

// The shortest of %.15g..%.17g that reads back as the same double (dt=0.05, not
// 0.050000000000000003): run and check keys stay exact and readable.
std::string dt_text(const json& dt) {
    if (!dt.is_number()) return dt.dump();
    const double x = dt.get<double>();
    char buf[40];
    for (int digits = 15; digits <= 17; ++digits) {
        std::snprintf(buf, sizeof buf, "%.*g", digits, x);
        if (std::strtod(buf, nullptr) == x) break;
    }
    return buf;
}

} // namespace

std::string run_key(const json& r) {
    return r["method"].get<std::string>() + " dt=" + dt_text(r["dt"]);
}

std::string check_key(const json& ck) {
    std::string k = ck["name"].get<std::string>() + " [" + ck["method"].get<std::string>();
    if (ck.contains("dt")) k += ", dt=" + dt_text(ck["dt"]);
    return k + "]";
}

void require_report(const json& r, const std::string& which) {
    require(r, which, false);
}

void require_current_report(const json& r, const std::string& which) {
    require(r, which, true);
}

} // namespace dampsym::compare_detail
