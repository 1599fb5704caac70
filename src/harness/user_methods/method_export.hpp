// Export of a built-in method whose coefficients are data as a method file (docs/method-files.md,
// `dampsym methods --export ID --as NEW_ID`): the file, loaded, steps bit for bit like the
// built-in row (ci/mutants.py checks every exportable row on random states). Numbers are written
// as the shortest decimal that reads back to the same double (at most 17 significant digits).
//
// Exportable: the RK, integrating-factor and partitioned tableaux, the GLM glm4 with its starting
// method and its G-symplecticity certificate, and the exponential rows whose coefficient
// functions the φ-vocabulary writes with the built-in's own floating-point operations (etdrk2,
// cse-if, cse-etd, csv1-perk, etdprk2). Not exportable: the hand-written schemes (their kernel is
// code) and csv2-perk, whose Cayley factors (4 ± x_B)^{-1} of B(2.21) the vocabulary has no term
// for.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <string_view>

namespace dampsym {

// The method file of built-in `id` under the id `new_id`. Throws InputError naming the option
// (--export, --as) if `id` is not a built-in row with exportable coefficients or `new_id` is not a
// valid method-file id (a built-in id, or not of A-Z a-z 0-9 . _ -).
nlohmann::json export_method_file(std::string_view id, const std::string& new_id);

} // namespace dampsym
