// The case key "figures" (docs/case-keys.md "figures"): which figures a case draws with
// `dampsym run --figures` and `dampsym plot` (tools/figures/plot.py).
//   absent                  the defaults: every kind the case's data allows
//   false, or []            none: with --figures the case keeps no series and draws nothing
//   ["convergence", ...]    exactly these kinds, each known, listed once and possible for the case
// report.json carries the key through unchanged (case "figures"), so that `dampsym plot` on a
// report honours it.
#pragma once

#include "harness/case/case.hpp"
#include "harness/problem_info.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <string>
#include <string_view>

namespace dampsym {

// Every kind of figure, as tools/figures/plot.py names them.
inline constexpr std::array<std::string_view, 7> kFigureKinds = {
    "convergence", "series", "orbit", "stability", "poincare", "snapshots", "portrait"};

// Validates j["figures"] of a parsed case c on problem p; throws InputError naming file and key
// ("figures" or "figures[i]"). Needs c's step sizes and diagnostics.
void validate_figures_key(const nlohmann::json& j, const std::string& file, const CaseSpec& c,
                          const ProblemInfo& p);

// Whether the case's figures draw the orbit of problem p (its "figures" key lists "orbit", or the
// key is absent and the problem draws its orbit by default): only then does a run with --figures
// keep orbit samples.
bool case_draws_orbit(const CaseSpec& c, OrbitFigure problem);

// Whether the case turned its figures off ("figures": false or []): it then keeps no series.
bool case_figures_off(const CaseSpec& c);

} // namespace dampsym
