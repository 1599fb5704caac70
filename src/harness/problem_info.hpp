// Runtime facts about the registered problems and kernels, for validation, `dampsym list` and
// reports, without the templates of registry.hpp (which includes every problem and kernel).
#pragma once

#include "core/method.hpp"
#include "core/problem.hpp"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace dampsym {

// What the case validator learns from an instance built from a case's parameters.
struct ProblemFacts {
    int dim = 0;
    int dof = -1; // degrees of freedom of a canonical z = [q; p], else -1
    std::optional<double> forcing_period;
};

struct ProblemInfo {
    std::string id, title;
    std::vector<ParamSpec> params;
    std::vector<std::string> invariants;
    bool is_linear, has_exact, has_energy, constant_gamma;
    // The diagnostics the problem supports: each diagnostic's `supports<P>` concept
    // (src/diagnostics/diagnostic_list.hpp).
    std::vector<std::string> diagnostics;
    // Builds the problem from validated parameters (throws std::invalid_argument when the
    // problem rejects them) and reports its facts.
    ProblemFacts (*facts)(const ParamMap&) = nullptr;
    // Whether its figures draw the orbit (`static constexpr OrbitFigure figure_orbit`,
    // core/problem.hpp; the case key "figures": harness/case/figures_key.hpp).
    OrbitFigure figure_orbit = OrbitFigure::none;
    // Its probe is a point of a plane (HasProbePlane, diagnostics/attractor_diagnostic.hpp): the
    // case can draw the `portrait` figure.
    bool probe_plane = false;
    bool supports(std::string_view diagnostic) const;
};
const std::vector<ProblemInfo>& problem_catalog();
const ProblemInfo* find_problem(std::string_view id);

// The kernel_id of the kernel that steps `info` (for listings and reports; "" if none).
std::string_view kernel_name(const MethodInfo& info);

// Whether `method` can run on problem `problem_id` (false if not applicable).
bool method_applies(std::string_view method_id, std::string_view problem_id);

} // namespace dampsym
