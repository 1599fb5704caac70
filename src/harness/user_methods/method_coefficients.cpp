#include "harness/user_methods/method_coefficients.hpp"

#include "methods/coefficient_checks.hpp"
#include "methods/runtime_methods.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace dampsym {

CoefficientVerdict coefficient_verdict(const MethodInfo& m) {
    CoefficientVerdict v;
    for (const auto& c : method_checks(m)) {
        (c.agrees() ? v.agree : v.disagree) += 1;
        if (!c.agrees()) v.refuted.push_back(c.name);
        nlohmann::json j = {
            {"name", c.name},
            {"what", c.what},
            {"expected", c.expected},
            {"holds", c.holds},
            {"passed", c.agrees()},
            {"value", std::isfinite(c.value) ? nlohmann::json(c.value) : nlohmann::json(nullptr)},
            {"tolerance", c.tolerance}};
        if (c.inconclusive()) j["inconclusive"] = "a sufficient condition only: E_n decides";
        v.checks.push_back(j);
    }
    return v;
}

namespace {

// A built-in method whose coefficients refute its own declaration is a defect of dampsym itself
// (a mistyped coefficient in catalog.cpp or a coefficient function): every case that runs it fails
// this check, so that no suite passes on a method that is not what the harness says it is.
nlohmann::json builtin_refuted_check(const std::string& id, const std::vector<std::string>& names) {
    std::string list;
    for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
    return {{"name", "built-in coefficients agree with their declaration"},
            {"metric", "coefficients.refuted"},
            {"method", id},
            {"op", "le"},
            {"expected", 0},
            {"negative_control", false},
            {"value", names.size()},
            {"passed", false},
            {"message",
             "the coefficients refute the declaration: " + list + " (dampsym methods --check)"}};
}

} // namespace

void mark_refuted_methods(nlohmann::json& cases) {
    std::map<std::string, std::vector<std::string>> refuted; // per method id, once
    for (auto& c : cases) {
        if (!c.contains("runs")) continue;
        std::vector<std::string> builtin_refuted;
        for (auto& r : c["runs"]) {
            const std::string id = r.value("method", std::string());
            const MethodInfo* loaded = find_loaded_method(id);
            const MethodInfo* m = loaded ? loaded : find_method(id);
            if (!m) continue;
            auto it = refuted.find(id);
            if (it == refuted.end())
                it = refuted.emplace(id, coefficient_verdict(*m).refuted).first;
            if (it->second.empty()) continue;
            r["coefficients_refuted"] = it->second;
            if (!loaded && std::find(builtin_refuted.begin(), builtin_refuted.end(), id) ==
                               builtin_refuted.end())
                builtin_refuted.push_back(id);
        }
        for (const auto& id : builtin_refuted)
            c["checks"].push_back(builtin_refuted_check(id, refuted[id]));
    }
}

nlohmann::json refuted_methods(const nlohmann::json& cases) {
    nlohmann::json out = nlohmann::json::object();
    for (const auto& c : cases) {
        if (!c.contains("runs") || !c["runs"].is_array()) continue;
        for (const auto& r : c["runs"])
            if (r.is_object() && r.contains("coefficients_refuted") && r.contains("method") &&
                r["method"].is_string())
                out[r["method"].get<std::string>()] = r["coefficients_refuted"];
    }
    return out;
}

} // namespace dampsym
