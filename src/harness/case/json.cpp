// Reading case JSON strictly (duplicate keys, depth, number overflow, control characters; the
// key path of an offending value in the message), case files as bounded regular files, and
// --set KEY=VALUE overrides.
#include "harness/case/case.hpp"
#include "harness/case/util.hpp"
#include "harness/json_file.hpp"
#include "harness/run/limits.hpp"

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace dampsym {
namespace {

using json = nlohmann::json;
using namespace case_detail;

// SAX handler that builds nothing: checks nesting depth, duplicate keys, number overflow and
// control characters, and knows the key path of the value being read for the error message.
class JsonChecker : public json::json_sax_t {
public:
    explicit JsonChecker(std::string source) : source_(std::move(source)) {}
    const std::string& error() const { return error_; }

    bool null() override { return value(); }
    bool boolean(bool) override { return value(); }
    bool number_integer(number_integer_t) override { return value(); }
    bool number_unsigned(number_unsigned_t) override { return value(); }
    bool number_float(number_float_t x, const string_t&) override {
        if (!std::isfinite(x)) return failed("number overflows a double");
        return value();
    }
    bool string(string_t& s) override {
        if (!printable(s)) return failed("control character in a string (newline, tab, ...)");
        return value();
    }
    bool binary(binary_t&) override { return failed("binary values are not JSON text"); }
    bool start_object(std::size_t) override { return open(false); }
    bool key(string_t& k) override {
        Frame& f = frames_.back();
        f.key = k;
        if (!printable(k)) return failed("control character in a key");
        if (!f.keys.insert(k).second) return failed("duplicate key");
        return true;
    }
    bool end_object() override { return close(); }
    bool start_array(std::size_t) override { return open(true); }
    bool end_array() override { return close(); }
    bool parse_error(std::size_t position, const std::string& last_token,
                     const json::exception& e) override {
        if (!error_.empty()) return false;
        if (e.id == 406) // out_of_range: number overflow parsing '1e400'
            return failed("number " + brief(last_token) + " overflows a double");
        std::string what = e.what();
        if (what.size() > 200) what = what.substr(0, 200) + "...";
        error_ = source_ + ": malformed JSON at byte " + std::to_string(position) +
                 (frames_.empty() ? "" : " (in " + path() + ")") + ": " + what;
        // a comment is the commonest such error in a hand-written file
        if (!last_token.empty() && last_token.back() == '/')
            error_ += "; comments (// or /* */) are not JSON: remove them (a case file can say "
                      "what it means in \"notes\")";
        return false;
    }

private:
    struct Frame {
        bool array;
        std::set<std::string> keys;
        std::string key;
        std::size_t index = 0;
    };
    static bool printable(const std::string& s) {
        return std::none_of(s.begin(), s.end(), [](char ch) {
            const auto u = static_cast<unsigned char>(ch);
            return u < 0x20 || u == 0x7f;
        });
    }
    std::string path() const {
        std::string out;
        for (const Frame& f : frames_) {
            if (f.array)
                out += "[" + std::to_string(f.index) + "]";
            else
                out += (out.empty() ? "" : ".") + brief(f.key);
        }
        return out.empty() ? "(top level)" : out;
    }
    bool value() {
        if (!frames_.empty() && frames_.back().array) ++frames_.back().index;
        return true;
    }
    bool open(bool array) {
        if (static_cast<int>(frames_.size()) >= limits::max_depth)
            return failed("nesting deeper than " + std::to_string(limits::max_depth) + " levels");
        frames_.push_back({array, {}, {}, 0});
        return true;
    }
    bool close() {
        frames_.pop_back();
        return value();
    }
    bool failed(const std::string& what) {
        if (error_.empty()) error_ = source_ + ": " + path() + ": " + what;
        return false;
    }

    std::string source_;
    std::vector<Frame> frames_;
    std::string error_;
};

// The components of a --set KEY (dotted), each non-empty, at most limits::max_depth of them.
std::vector<std::string> key_parts(const std::string& dotted) {
    std::vector<std::string> parts;
    std::string::size_type start = 0;
    while (true) {
        const auto dot = dotted.find('.', start);
        parts.push_back(dotted.substr(start, dot - start));
        if (parts.back().empty())
            throw InputError("--set " + brief(dotted) + ": empty key component");
        if (static_cast<int>(parts.size()) > limits::max_depth)
            throw InputError("--set " + brief(dotted) + ": more than " +
                             std::to_string(limits::max_depth) + " key components");
        if (dot == std::string::npos) return parts;
        start = dot + 1;
    }
}

} // namespace

namespace case_detail {

void set_path(json& root, const std::string& dotted, const json& value) {
    json* node = &root;
    const auto parts = key_parts(dotted);
    for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
        if (!node->contains(parts[i])) (*node)[parts[i]] = json::object();
        node = &(*node)[parts[i]];
        if (!node->is_object())
            throw InputError("--set " + brief(dotted) + ": '" + brief(parts[i]) +
                             "' is not an object");
    }
    (*node)[parts.back()] = value;
}

} // namespace case_detail

json parse_json_checked(const std::string& text, const std::string& source) {
    JsonChecker checker(source);
    const bool ok = json::sax_parse(text, &checker, json::input_format_t::json, true);
    if (!ok || !checker.error().empty())
        throw InputError(checker.error().empty() ? source + ": malformed JSON" : checker.error());
    // Depth, keys and numbers are checked: building the value cannot overflow the stack now.
    try {
        return json::parse(text);
    } catch (const json::exception& e) {
        throw InputError(source + ": malformed JSON: " + brief(std::string(e.what())));
    }
}

json read_case_json(const std::string& path) {
    return read_json_file(path, "case file");
}

json read_json_file(const std::string& path, const std::string& kind) {
    // O_NONBLOCK: opening a FIFO must not wait for a writer; fstat then rejects it.
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0)
        throw InputError(brief(path) + ": cannot open " + kind + " (" + std::strerror(errno) + ")");
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    struct stat st {};
    if (::fstat(fd, &st) != 0)
        throw InputError(brief(path) + ": cannot stat " + kind + " (" + std::strerror(errno) + ")");
    if (!S_ISREG(st.st_mode)) {
        const char* kind = S_ISDIR(st.st_mode)    ? "a directory"
                           : S_ISFIFO(st.st_mode) ? "a FIFO"
                           : S_ISCHR(st.st_mode)  ? "a character device"
                           : S_ISBLK(st.st_mode)  ? "a block device"
                           : S_ISSOCK(st.st_mode) ? "a socket"
                                                  : "not a regular file";
        throw InputError(brief(path) + ": a " + kind + " must be a regular file; this is " + kind);
    }
    const auto too_big = [&] {
        return InputError(brief(path) + ": " + kind + " larger than " +
                          std::to_string(limits::max_file_bytes >> 20) + " MiB");
    };
    if (static_cast<std::uintmax_t>(st.st_size) > limits::max_file_bytes) throw too_big();
    // Read at most the limit (plus one byte to notice a file that grew meanwhile).
    std::string text;
    char buf[65536];
    while (true) {
        const ssize_t got = ::read(fd, buf, sizeof buf);
        if (got < 0) {
            if (errno == EINTR) continue;
            throw InputError(brief(path) + ": cannot read " + kind + " (" + std::strerror(errno) +
                             ")");
        }
        if (got == 0) break;
        text.append(buf, static_cast<std::size_t>(got));
        if (text.size() > limits::max_file_bytes) throw too_big();
    }
    return parse_json_checked(text, brief(path));
}

std::pair<std::string, json> parse_override(const std::string& text) {
    const auto eq = text.find('=');
    if (eq == std::string::npos || eq == 0)
        throw InputError("--set " + brief(text) + ": expected KEY=VALUE");
    const std::string key = text.substr(0, eq);
    const std::string value = text.substr(eq + 1);
    (void)key_parts(key);
    const std::string source = "--set " + brief(key);
    // An array or object must be valid JSON, checked like a file (depth, duplicate keys, overflow).
    if (!value.empty() && (value[0] == '[' || value[0] == '{'))
        return {key, parse_json_checked(value, source)};
    if (!json::parse(value, nullptr, false).is_discarded())
        return {key, parse_json_checked(value, source)}; // a number, string, true, false, null
    char* end = nullptr;
    const double x = std::strtod(value.c_str(), &end);
    // NaN and ±inf (also from an overflowing literal such as 1e400) are kept, so that the
    // validation names the file and the key.
    if (!value.empty() && end == value.c_str() + value.size()) return {key, x};
    return {key, value};
}

} // namespace dampsym
