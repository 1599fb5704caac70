#include "harness/case/figures_key.hpp"

#include "diagnostics/attractor_diagnostic.hpp"
#include "diagnostics/pde_error_diagnostic.hpp"
#include "diagnostics/poincare_diagnostic.hpp"
#include "diagnostics/stability_sweep_diagnostic.hpp"
#include "harness/case/util.hpp"

#include <algorithm>

namespace dampsym {

using case_detail::fail;

void validate_figures_key(const nlohmann::json& j, const std::string& file, const CaseSpec& c,
                          const ProblemInfo& p) {
    if (!j.contains("figures")) return;
    const nlohmann::json& v = j["figures"];
    if (v.is_boolean()) {
        if (v.get<bool>())
            fail(file, "figures",
                 "true is the default: omit the key, give false (none) or a list of kinds");
        return;
    }
    std::string known;
    for (auto k : kFigureKinds) known += (known.empty() ? "" : ", ") + std::string(k);
    if (!v.is_array())
        fail(file, "figures", "must be false or an array of figure kinds (" + known + ")");
    std::vector<std::string> seen;
    for (std::size_t i = 0; i < v.size(); ++i) {
        const std::string key = "figures[" + std::to_string(i) + "]";
        const std::string k = case_detail::string_of(v[i], file, key);
        if (std::find(kFigureKinds.begin(), kFigureKinds.end(), k) == kFigureKinds.end())
            fail(file, key, "unknown figure kind '" + brief(k) + "' (known: " + known + ")");
        if (std::find(seen.begin(), seen.end(), k) != seen.end())
            fail(file, key, "figure kind '" + k + "' listed twice");
        seen.push_back(k);
        // what each kind needs of the case (tools/figures/plot.py draws from exactly this)
        if (k == "convergence" && c.dts.size() < 2)
            fail(file, key, "a convergence figure needs a dt_ladder of >= 2 step sizes");
        const auto needs = [&](std::string_view diag) {
            if (!c.wants(diag))
                fail(file, key,
                     "a " + k + " figure needs the " + std::string(diag) + " diagnostic");
        };
        if (k == "stability") needs(StabilitySweepDiagnostic::name);
        if (k == "poincare") needs(PoincareDiagnostic::name);
        if (k == "snapshots") needs(PdeErrorDiagnostic::name);
        if (k == "portrait" && (!c.wants(AttractorDiagnostic::name) || !p.probe_plane))
            fail(file, key,
                 "a portrait figure needs the attractor diagnostic on a problem whose probe is a "
                 "point of a plane (nls-driven)");
        if (k == "orbit" && p.figure_orbit == OrbitFigure::none)
            fail(file, key, "problem '" + c.problem_id + "' has no orbit figure");
    }
}

bool case_draws_orbit(const CaseSpec& c, OrbitFigure problem) {
    if (problem == OrbitFigure::none) return false;
    if (!c.raw.is_object() || !c.raw.contains("figures")) return problem == OrbitFigure::by_default;
    const nlohmann::json& v = c.raw["figures"];
    if (!v.is_array()) return false; // false: no figures
    for (const auto& k : v)
        if (k.is_string() && k.get<std::string>() == "orbit") return true;
    return false;
}

bool case_figures_off(const CaseSpec& c) {
    if (!c.raw.is_object() || !c.raw.contains("figures")) return false;
    const nlohmann::json& v = c.raw["figures"];
    return (v.is_boolean() && !v.get<bool>()) || (v.is_array() && v.empty());
}

} // namespace dampsym
