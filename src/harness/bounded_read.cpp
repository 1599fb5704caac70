#include "harness/bounded_read.hpp"

#include "harness/case/case.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace dampsym {
namespace {

std::string kind_of(mode_t mode) {
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    if (S_ISDIR(mode)) return "a directory";
    return "not a regular file";
}

// Closes the descriptor on every path out of read_regular_file.
struct Fd {
    int fd;
    ~Fd() {
        if (fd >= 0) ::close(fd);
    }
};

} // namespace

std::string not_regular_reason(const std::string& path, bool may_be_missing) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) {
        if (errno == ENOENT && may_be_missing) return "";
        return std::strerror(errno);
    }
    return S_ISREG(st.st_mode) ? "" : kind_of(st.st_mode) + ", not a regular file";
}

std::string read_regular_file(const std::string& path, std::size_t max_bytes,
                              const std::string& what) {
    const std::string name = what + " " + quote_for_message(path);
    if (const std::string why = not_regular_reason(path, false); !why.empty())
        throw InputError(name + ": " + why);
    // O_NONBLOCK: if the path was replaced by a FIFO after the stat, the open does not wait for a
    // writer; fstat of the descriptor is then the decisive test.
    const Fd f{::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC)};
    if (f.fd < 0) throw InputError(name + ": cannot open: " + std::strerror(errno));
    struct stat st {};
    if (::fstat(f.fd, &st) != 0 || !S_ISREG(st.st_mode))
        throw InputError(name + ": " + kind_of(st.st_mode) + ", not a regular file");
    const auto limit_text = std::to_string(max_bytes >> 20) + " MiB";
    if (static_cast<std::size_t>(st.st_size) > max_bytes)
        throw InputError(name + ": " + std::to_string(st.st_size) + " bytes, more than the " +
                         limit_text + " limit");
    std::string out;
    out.resize(static_cast<std::size_t>(st.st_size));
    std::size_t got = 0;
    for (;;) { // a file that grows while read is cut off at max_bytes + 1 and refused
        if (got == out.size()) {
            if (out.size() > max_bytes) break;
            out.resize(std::min(max_bytes + 1, std::max<std::size_t>(out.size() * 2, 4096)));
        }
        const ssize_t n = ::read(f.fd, out.data() + got, out.size() - got);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) throw InputError(name + ": cannot read: " + std::strerror(errno));
        if (n == 0) break;
        got += static_cast<std::size_t>(n);
    }
    if (got > max_bytes) throw InputError(name + ": more than the " + limit_text + " limit");
    out.resize(got);
    return out;
}

std::string quote_for_message(const std::string& text, std::size_t max_chars) {
    std::string out;
    std::size_t shown = 0;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const unsigned char c = static_cast<unsigned char>(text[i]);
        // a UTF-8 continuation byte belongs to the character already counted
        if ((c & 0xC0) != 0x80 && shown++ == max_chars) {
            std::size_t rest = 0; // the characters not shown, so the reader sees the size
            for (std::size_t j = i; j < text.size(); ++j)
                rest += (static_cast<unsigned char>(text[j]) & 0xC0) != 0x80 ? 1 : 0;
            out += "… (" + std::to_string(rest) + " more characters)";
            break;
        }
        if (c == '\n')
            out += "\\n";
        else if (c == '\t')
            out += "\\t";
        else if (c < 0x20 || c == 0x7F) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\x%02x", c);
            out += buf;
        } else
            out += static_cast<char>(c);
    }
    return out;
}

} // namespace dampsym
