// Reading files that the user names (reports for compare/merge/plot, --costs, --plugin,
// GITHUB_STEP_SUMMARY) without hanging or exhausting memory: only regular files are opened (a
// FIFO, device, socket or directory is bad input naming it, decided by stat and then fstat of a
// descriptor opened with O_NONBLOCK, so that a FIFO never blocks the open), and at most a stated
// number of bytes is read before parsing.
#pragma once

#include <cstddef>
#include <string>

namespace dampsym {

// Upper limit of a report.json read by compare, merge and plot (docs/reports.md). The stress
// suite's report is about 2 MiB; 256 MiB leaves room for much larger suites while bounding memory.
constexpr std::size_t kMaxReportBytes = std::size_t{256} << 20;
// Upper limit of a --costs file (a map from case id to seconds).
constexpr std::size_t kMaxCostsBytes = std::size_t{16} << 20;

// The whole content of `path`. Throws InputError "<what> <path>: ..." if it is not a regular
// file, cannot be opened or is larger than max_bytes.
std::string read_regular_file(const std::string& path, std::size_t max_bytes,
                              const std::string& what);

// "" if `path` is a regular file (or, when may_be_missing, does not exist), else the reason
// ("a FIFO", "a character device", "a directory", "not found", ...). Never opens the file.
std::string not_regular_reason(const std::string& path, bool may_be_missing);

// A user-supplied text for a one-line message: control characters escaped (\n, \x01), and cut
// after max_chars characters with "… (N more characters)" (an id or expression may be megabytes
// long).
std::string quote_for_message(const std::string& text, std::size_t max_chars = 200);

} // namespace dampsym
