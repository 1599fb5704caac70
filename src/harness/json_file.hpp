// Reading a JSON input file (a case file, a method file) as read_case_json does (case.hpp): a
// regular file of at most limits::max_file_bytes, checked before reading, then parse_json_checked;
// `kind` ("case file", "method file") names the file in every message.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace dampsym {

nlohmann::json read_json_file(const std::string& path, const std::string& kind);

} // namespace dampsym
