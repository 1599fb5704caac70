// The dampsym command line (run, list, compare, merge, methods). Exit status: 0 all checks passed
// (compare: nothing moved), 1 some check failed (compare: something moved), 2 bad input or usage
// (one line on stderr naming the file and the key), 3 internal or I/O error (e.g. --out not
// writable; one line on stderr).
#pragma once

#include <iosfwd>

namespace dampsym {

int run_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err);

} // namespace dampsym
