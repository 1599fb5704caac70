// Helpers of the case parser shared by its files (case.cpp: public entry points, ids, costs;
// case/json.cpp: strict JSON, case files, --set; case/parse.cpp: the case's keys; case/util.cpp:
// typed values and key checks; case/expect.cpp: checks and measures).
#pragma once

#include "harness/case/case.hpp"
#include "harness/problem_info.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <set>
#include <string>
#include <vector>

namespace dampsym::case_detail {

using json = nlohmann::json;

// A validation error with its key kept apart, so that parse_case can say when the value came
// from --set rather than from the file.
struct KeyedError : InputError {
    KeyedError(const std::string& file, const std::string& key, const std::string& what)
        : InputError(file + ": " + key + ": " + what), file_(file), key_(key), what_(what) {}
    std::string file_, key_, what_;
};

[[noreturn]] inline void fail(const std::string& file, const std::string& key,
                              const std::string& what) {
    throw KeyedError(file, key, what);
}

std::string format_number(double x);
double number(const json& v, const std::string& file, const std::string& key);
std::string string_of(const json& v, const std::string& file, const std::string& key);
bool boolean(const json& v, const std::string& file, const std::string& key);
std::string describe(const Range& r);
void only_keys(const json& obj, const std::set<std::string>& allowed, const std::string& file,
               const std::string& prefix);
// Steps of size dt in [t0, t_end]; t_end − t0 must be an integer multiple of dt to 1e-9 relative.
std::int64_t step_count(double span, double dt, const std::string& file, const std::string& key,
                        double limit);
Range3 parse_range(const json& v, const std::string& file, const std::string& key);
std::vector<std::string> metric_names(const std::string& diagnostic,
                                      const std::vector<std::string>& invariants);

// case/json.cpp: sets the value at a dotted key (--set problem.gamma=0.3), creating objects.
void set_path(json& root, const std::string& dotted, const json& value);

// case/parse.cpp: the case without the --set attribution of errors (parse_case adds it);
// `applied` receives each override as typed.
CaseSpec parse_case_unchecked(const json& input, const std::string& file,
                              const std::vector<std::string>& overrides, json& applied);

// case/expect.cpp
void parse_check_methods(const json& cj, const CaseSpec& c, const std::string& diag,
                         const std::string& file, const std::string& base, CheckSpec& cs);
void parse_measures(const json& mj, const ProblemInfo& prob, const std::string& file, CaseSpec& c);
// The "expect" object: the case's named checks.
void parse_expect(const json& ej, const ProblemInfo& prob, const std::string& file, CaseSpec& c);

} // namespace dampsym::case_detail
