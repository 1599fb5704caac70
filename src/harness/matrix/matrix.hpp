// The method × property matrix (docs/matrix.md): a fixed battery of cases — order
// on the damped pendulum, E_n on the pendulum and Hill, the conformal law of H_γ on the oscillator,
// the momentum laws of the damped N-body problem (B Table 3.1), the drift of d(t) on the
// oscillator and the stability threshold on the oscillator against F's closed forms (F ch. 3) or
// the tableau's stability function — generated in code from one table (matrix_battery) as ordinary
// case JSON, validated by parse_case and run by the ordinary runner (run_cases, --jobs), so every
// number comes from the suites' diagnostics. Each method × property cell gets the measured value, a
// verdict (holds / fails / n/a) and its role: claimed (from MethodInfo::claims and order, or a
// closed form for the threshold), a negative control (not claimed, in the battery as a comparison)
// or n/a.
#pragma once

#include "core/method.hpp"
#include "harness/case/case.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace dampsym {

// The methods of the matrix: every row of the built-in catalog, then every loaded row (method
// files, and the plugin rows that join the same runtime catalog), whose id matches one of the
// globs (all when empty), in catalog order.
std::vector<const MethodInfo*> matrix_methods(const std::vector<std::string>& globs);

// The battery's cases for these methods (each method only in the cases of the problems it applies
// to); ids "matrix-*".
std::vector<CaseSpec> matrix_battery(const std::vector<const MethodInfo*>& methods);

// The matrix from the battery's report (run_cases on matrix_battery): {"properties": [...],
// "methods": [...], "summary": {...}}; each method has "cells": {property id: {"value", "verdict",
// "role", "claimed", "detail", ...}} (docs/matrix.md).
nlohmann::json judge_matrix(const std::vector<const MethodInfo*>& methods,
                            const nlohmann::json& battery_report);

// The matrix as a Markdown table with a legend.
std::string render_matrix_markdown(const nlohmann::json& matrix);

// Exit status of `dampsym matrix`: 1 if a claimed property fails or a negative control of a
// property whose controls must fail passes (matrix["summary"]), else 0.
int matrix_exit_status(const nlohmann::json& matrix);

} // namespace dampsym
