// The dampsym command line (SPEC §7). Exit status: 0 all checks passed, 1 some check failed,
// 2 bad input or usage (one line on stderr naming the file and the key).
#pragma once

#include <iosfwd>

namespace dampsym {

int run_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err);

} // namespace dampsym
