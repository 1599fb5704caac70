// Shared by the libFuzzer targets in tests/fuzz/: what counts as a finding besides a crash or a
// sanitizer report. A reader may reject its input only with dampsym::InputError (the CLI turns it
// into exit status 2 with a message naming file and key); any other exception escaping a reader
// (a nlohmann::json type_error, std::out_of_range, ...) would be exit 3 "internal error" and is
// reported here as a finding by aborting with its message.
#pragma once

#include "harness/case/case.hpp"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

namespace dampsym::fuzz {

template <class F>
void expect_input_error(F&& f) {
    try {
        f();
    } catch (const InputError&) {
        // the documented rejection
    } catch (const std::exception& e) {
        std::fprintf(stderr, "fuzz finding: exception other than InputError: %s\n", e.what());
        std::abort();
    }
}

} // namespace dampsym::fuzz
