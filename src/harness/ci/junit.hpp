// JUnit XML from a report, as Jenkins, GitLab and GitHub test reporters read it: one <testsuite>
// per case (properties: title, source paper and figure, problem, case file), one <testcase> per
// check (classname = case id, name = "check [method, dt=...]"). A failing check is a <failure>
// carrying value, expected and tolerance; a check whose run diverged or whose Newton solve failed
// (or whose reference failed) is an <error>. Times come from the report's timings section.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace dampsym {

std::string render_junit(const nlohmann::json& report);

// The testcase name of a check: "name [method, dt=0.01]" ("name [method]" for method-level).
std::string junit_test_name(const nlohmann::json& check);

} // namespace dampsym
