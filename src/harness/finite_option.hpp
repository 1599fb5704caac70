// A CLI11 check that a numeric option is a finite number: CLI::Range and CLI::NonNegativeNumber
// compare with < and >, which NaN passes (every comparison with NaN is false), so `--rtol nan`
// was accepted; inf is meaningless for every option that takes it (tolerances, seconds).
#pragma once

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdlib>
#include <string>

namespace dampsym {

inline CLI::Validator finite_number() {
    return CLI::Validator(
        [](std::string& text) -> std::string {
            const char* begin = text.c_str();
            char* end = nullptr;
            const double v = std::strtod(begin, &end);
            if (end == begin || *end != '\0' || !std::isfinite(v))
                return "expected a finite number, got '" +
                       (text.size() > 40 ? text.substr(0, 40) + "…" : text) + "'";
            return "";
        },
        "FINITE");
}

} // namespace dampsym
