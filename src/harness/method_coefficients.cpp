#include "harness/method_coefficients.hpp"

#include "methods/coefficient_checks.hpp"
#include "methods/runtime_methods.hpp"

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

void mark_refuted_methods(nlohmann::json& cases) {
    std::map<std::string, std::vector<std::string>> refuted; // per loaded method id, once
    for (auto& c : cases) {
        if (!c.contains("runs")) continue;
        for (auto& r : c["runs"]) {
            const std::string id = r.value("method", std::string());
            const MethodInfo* m = find_loaded_method(id);
            if (!m) continue;
            auto it = refuted.find(id);
            if (it == refuted.end())
                it = refuted.emplace(id, coefficient_verdict(*m).refuted).first;
            if (!it->second.empty()) r["coefficients_refuted"] = it->second;
        }
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
