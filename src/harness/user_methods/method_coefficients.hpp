// A method's coefficient-level checks (methods/coefficient_checks.hpp) as report JSON, shared by
// `dampsym methods --check`, the matrix's coefficient cell and `dampsym run` (which flags a loaded
// method whose coefficients refute its declaration): coefficients are part of every verdict.
#pragma once

#include "core/method.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace dampsym {

struct CoefficientVerdict {
    nlohmann::json checks = nlohmann::json::array(); // one entry per check (name, what, ...)
    int agree = 0, disagree = 0;
    std::vector<std::string> refuted; // the names of the checks that disagree
    bool checked() const { return agree + disagree > 0; }
};

CoefficientVerdict coefficient_verdict(const MethodInfo& m);

// `dampsym run`: marks every run of a method whose coefficients refute its declaration with
// "coefficients_refuted" (the check names; `dampsym methods --check [--methods FILE]` shows them
// in full). A loaded method is flagged only (a case may run a deliberately wrong one as a negative
// control); a built-in one is a defect of dampsym: every case running it gets a failing check.
void mark_refuted_methods(nlohmann::json& cases);

// The methods whose runs carry "coefficients_refuted" in a report's cases: id -> check names.
nlohmann::json refuted_methods(const nlohmann::json& cases);

} // namespace dampsym
