#include "harness/case.hpp"

#include "harness/case_job.hpp"
#include "harness/case_util.hpp"
#include "harness/limits.hpp"
#include "harness/method_files.hpp"
#include "harness/problem_info.hpp"
#include "methods/runtime_methods.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
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

// Whether the validation error at `key` concerns the value set by --set `set_key`: the same key,
// a key inside it (dt_ladder[2] inside dt_ladder), or the object that contains it (problem for
// problem.gamma, checked by the problem as a whole).
bool concerns(const std::string& key, const std::string& set_key) {
    auto inside = [](const std::string& a, const std::string& b) {
        return a.size() > b.size() && a.compare(0, b.size(), b) == 0 &&
               (a[b.size()] == '.' || a[b.size()] == '[');
    };
    return key == set_key || inside(key, set_key) || inside(set_key, key);
}

CaseSpec parse_case_unchecked(const json& input, const std::string& file,
                              const std::vector<std::string>& overrides, json& applied);

} // namespace

std::vector<double> Range3::values() const {
    std::vector<double> out;
    const auto n = static_cast<std::int64_t>(std::floor((to - from) / step + 1e-9));
    for (std::int64_t i = 0; i <= n; ++i) out.push_back(from + static_cast<double>(i) * step);
    return out;
}

bool CaseSpec::wants(const std::string& d) const {
    return std::find(diagnostics.begin(), diagnostics.end(), d) != diagnostics.end();
}

const std::vector<std::string>& known_diagnostics() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> out;
        for (const DiagnosticInfo& d : diagnostic_registry()) out.push_back(d.name);
        return out;
    }();
    return names;
}

bool diagnostic_applies(const std::string& d, const ProblemInfo& p) {
    return p.supports(d);
}

bool diagnostic_is_method_level(const std::string& d) {
    const DiagnosticInfo* info = find_diagnostic(d);
    return info && info->level == DiagnosticLevel::method;
}

std::string brief(const std::string& s) {
    if (s.size() <= limits::max_message_value) return s;
    return s.substr(0, limits::max_message_value) + "... (" + std::to_string(s.size()) +
           " characters)";
}

std::string brief(const json& v) {
    if (v.is_number_float() && !std::isfinite(v.get<double>()))
        return std::isnan(v.get<double>()) ? "NaN" : v.get<double>() > 0 ? "inf" : "-inf";
    return brief(v.dump(-1, ' ', false, json::error_handler_t::replace));
}

std::vector<std::string> diagnostic_metric_names(const std::string& diagnostic,
                                                 const std::vector<std::string>& invariant_names) {
    return diagnostic_metrics(diagnostic, invariant_names, true);
}

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
    // O_NONBLOCK: opening a FIFO must not wait for a writer; fstat then rejects it.
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0)
        throw InputError(brief(path) + ": cannot open case file (" + std::strerror(errno) + ")");
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    struct stat st {};
    if (::fstat(fd, &st) != 0)
        throw InputError(brief(path) + ": cannot stat case file (" + std::strerror(errno) + ")");
    if (!S_ISREG(st.st_mode)) {
        const char* kind = S_ISDIR(st.st_mode)    ? "a directory"
                           : S_ISFIFO(st.st_mode) ? "a FIFO"
                           : S_ISCHR(st.st_mode)  ? "a character device"
                           : S_ISBLK(st.st_mode)  ? "a block device"
                           : S_ISSOCK(st.st_mode) ? "a socket"
                                                  : "not a regular file";
        throw InputError(brief(path) + ": a case file must be a regular file; this is " + kind);
    }
    const auto too_big = [&] {
        return InputError(brief(path) + ": case file larger than " +
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
            throw InputError(brief(path) + ": cannot read case file (" + std::strerror(errno) +
                             ")");
        }
        if (got == 0) break;
        text.append(buf, static_cast<std::size_t>(got));
        if (text.size() > limits::max_file_bytes) throw too_big();
    }
    return parse_json_checked(text, brief(path));
}

bool valid_case_id(const std::string& id) {
    if (id.empty() || id.size() > limits::max_id_length) return false;
    auto alnum = [](char ch) {
        return (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9');
    };
    if (!alnum(id[0])) return false;
    return std::all_of(id.begin(), id.end(),
                       [&](char ch) { return alnum(ch) || ch == '.' || ch == '_' || ch == '-'; });
}

void check_unique_ids(const std::vector<CaseSpec>& cases) {
    std::map<std::string, const CaseSpec*> seen;
    for (const auto& c : cases) {
        const auto [it, inserted] = seen.emplace(c.id, &c);
        if (inserted) continue;
        const CaseSpec& first = *it->second;
        if (first.file == c.file)
            throw InputError(c.file + ": id: case '" + c.id +
                             "' is named twice (each case runs once; give it once)");
        throw InputError(c.file + ": id: '" + c.id + "' is also the id of " + first.file +
                         (c.overrides.contains("id") || first.overrides.contains("id")
                              ? " (after --set id=...)"
                              : "") +
                         "; case ids must be unique in a run");
    }
}

double case_total_steps(const CaseSpec& c) {
    double per_method = 0.0;
    for (auto n : c.steps) per_method += static_cast<double>(n);
    return per_method * static_cast<double>(c.methods.size());
}

double case_predicted_seconds(const CaseSpec& c) {
    double ns = 0.0;
    for (const auto& m : c.methods) {
        const MethodInfo* info = find_method(m);
        const double per_component = info && info->implicit ? 300.0 : 30.0;
        for (auto n : c.steps) ns += static_cast<double>(n) * per_component * c.dim;
    }
    return ns * 1e-9;
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

CaseSpec load_case(const std::string& path, const std::vector<std::string>& overrides) {
    return parse_case(read_case_json(path), path, overrides);
}

CaseSpec parse_case(const json& input, const std::string& file,
                    const std::vector<std::string>& overrides) {
    json applied = json::object();
    try {
        return parse_case_unchecked(input, file, overrides, applied);
    } catch (const KeyedError& e) {
        for (auto it = applied.begin(); it != applied.end(); ++it)
            if (concerns(e.key_, it.key()))
                throw InputError(
                    e.file_ + ": " + e.key_ +
                    (e.key_.size() < it.key().size() ? " (with --set " : " (set by --set ") +
                    brief(it.key()) + "=" + brief(it.value().get<std::string>()) + "): " + e.what_);
        throw;
    }
}

namespace {

// "problem": the id and the parameters, each in its range; then the problem checks the whole.
const ProblemInfo* parse_problem(const json& j, const std::string& file, CaseSpec& c,
                                 std::optional<double>& forcing_period) {
    const json& pj = j["problem"];
    if (!pj.is_object()) fail(file, "problem", "must be an object with an \"id\"");
    if (!pj.contains("id")) fail(file, "problem.id", "missing required key");
    c.problem_id = string_of(pj["id"], file, "problem.id");
    const ProblemInfo* prob = find_problem(c.problem_id);
    if (!prob) {
        std::string list;
        for (const auto& p : problem_catalog()) list += (list.empty() ? "" : ", ") + p.id;
        fail(file, "problem.id",
             "unknown problem '" + brief(c.problem_id) + "' (known: " + list + ")");
    }
    std::set<std::string> allowed{"id"};
    for (const auto& ps : prob->params) {
        allowed.insert(ps.name);
        if (ps.is_array)
            c.params.arrays[ps.name] = ps.default_array;
        else
            c.params.scalars[ps.name] = ps.default_value;
    }
    only_keys(pj, allowed, file, "problem.");
    auto in_range = [&](const ParamSpec& ps, double x, const std::string& key) {
        if (!ps.range.contains(x))
            fail(file, key,
                 "must be in " + describe(ps.range) + " (the range where " + c.problem_id +
                     "'s formulas are valid), got " + format_number(x));
        if (ps.integer && x != std::floor(x))
            fail(file, key, "must be a whole number, got " + format_number(x));
    };
    for (const auto& ps : prob->params) {
        if (!pj.contains(ps.name)) continue;
        const std::string key = "problem." + ps.name;
        if (!ps.choices.empty()) {
            std::string list;
            for (const auto& ch : ps.choices) list += (list.empty() ? "\"" : ", \"") + ch + "\"";
            const json& v = pj[ps.name];
            if (!v.is_string()) fail(file, key, "must be one of " + list + ", got " + brief(v));
            const auto it = std::find(ps.choices.begin(), ps.choices.end(), v.get<std::string>());
            if (it == ps.choices.end())
                fail(file, key, "must be one of " + list + ", got " + brief(v));
            c.params.scalars[ps.name] = static_cast<double>(it - ps.choices.begin());
        } else if (ps.is_array) {
            const json& a = pj[ps.name];
            if (!a.is_array() || a.empty())
                fail(file, key, "must be a non-empty array of numbers, got " + brief(a));
            if (ps.max_size > 0 && a.size() > static_cast<std::size_t>(ps.max_size))
                fail(file, key,
                     "has " + std::to_string(a.size()) + " entries (at most " +
                         std::to_string(ps.max_size) + ")");
            if (a.size() % static_cast<std::size_t>(ps.size_multiple) != 0)
                fail(file, key,
                     "length " + std::to_string(a.size()) + " is not a multiple of " +
                         std::to_string(ps.size_multiple));
            std::vector<double> v;
            for (std::size_t i = 0; i < a.size(); ++i) {
                const std::string ki = key + "[" + std::to_string(i) + "]";
                v.push_back(number(a[i], file, ki));
                in_range(ps, v.back(), ki);
            }
            c.params.arrays[ps.name] = std::move(v);
        } else {
            const double x = number(pj[ps.name], file, key);
            in_range(ps, x, key);
            c.params.scalars[ps.name] = x;
        }
    }

    // Problem-level consistency (array lengths, ...) is checked by the problem itself.
    try {
        const ProblemFacts facts = prob->facts(c.params);
        c.dim = facts.dim;
        forcing_period = facts.forcing_period;
    } catch (const std::invalid_argument& e) {
        fail(file, "problem", e.what());
    }
    return prob;
}

// "method_files": method files (paths relative to the case file) loaded before "methods" is read.
void parse_method_files(const json& j, const std::string& file) {
    if (!j.contains("method_files")) return;
    const json& a = j["method_files"];
    if (!a.is_array()) fail(file, "method_files", "must be an array of method file paths");
    for (std::size_t i = 0; i < a.size(); ++i) {
        const std::string key = "method_files[" + std::to_string(i) + "]";
        const std::string rel = string_of(a[i], file, key);
        const std::filesystem::path p = std::filesystem::path(rel).is_absolute()
                                            ? std::filesystem::path(rel)
                                            : std::filesystem::path(file).parent_path() / rel;
        std::error_code ec;
        if (!std::filesystem::is_regular_file(p, ec))
            fail(file, key,
                 "method file " + p.string() + " not found (paths are relative to the case file)");
        load_method_file(p.string());
    }
}

// "methods": known, listed once, applicable to the problem.
void parse_methods(const json& j, const std::string& file, CaseSpec& c) {
    if (!j["methods"].is_array() || j["methods"].empty())
        fail(file, "methods", "must be a non-empty array of method ids");
    for (std::size_t i = 0; i < j["methods"].size(); ++i) {
        const std::string key = "methods[" + std::to_string(i) + "]";
        const std::string m = string_of(j["methods"][i], file, key);
        if (!find_method(m)) {
            std::string list;
            for (const auto& mi : method_catalog())
                list += (list.empty() ? "" : ", ") + std::string(mi.id);
            for (const MethodInfo* mi : loaded_methods()) // method files (issue 18)
                list += ", " + std::string(mi->id);
            fail(file, key, "unknown method '" + brief(m) + "' (known: " + list + ")");
        }
        if (std::find(c.methods.begin(), c.methods.end(), m) != c.methods.end())
            fail(file, key, "method '" + m + "' listed twice");
        if (!method_applies(m, c.problem_id)) {
            std::string list;
            for (const auto& mi : method_catalog())
                if (method_applies(mi.id, c.problem_id))
                    list += (list.empty() ? "" : ", ") + std::string(mi.id);
            fail(file, key,
                 "method '" + m + "' (" + std::string(form_name(find_method(m)->form)) +
                     " form) does not apply to problem '" + c.problem_id +
                     "' (applicable: " + list + ")");
        }
        c.methods.push_back(m);
    }
}

// "t0", "t_end", "dt" or "dt_ladder", "output_dt".
void parse_time_grid(const json& j, const std::string& file, CaseSpec& c) {
    if (j.contains("t0")) c.t0 = number(j["t0"], file, "t0");
    c.t_end = number(j["t_end"], file, "t_end");
    for (const auto& [k, t] : {std::pair<const char*, double>{"t0", c.t0}, {"t_end", c.t_end}})
        if (!(std::abs(t) <= limits::max_abs_time))
            fail(file, k, "|" + std::string(k) + "| must be <= 1e9, got " + format_number(t));
    if (!(c.t_end > c.t0)) fail(file, "t_end", "must be > t0");
    if (j.contains("dt") == j.contains("dt_ladder"))
        fail(file, "dt", "give exactly one of \"dt\" and \"dt_ladder\"");
    if (j.contains("dt")) {
        c.dts.push_back(number(j["dt"], file, "dt"));
        if (!(c.dts[0] > 0.0)) fail(file, "dt", "must be > 0");
        c.steps.push_back(
            step_count(c.t_end - c.t0, c.dts[0], file, "dt", limits::max_steps_per_run));
    } else {
        c.ladder = true;
        const json& lj = j["dt_ladder"];
        if (!lj.is_array() || lj.empty()) fail(file, "dt_ladder", "must be a non-empty array");
        if (lj.size() > limits::max_ladder)
            fail(file, "dt_ladder",
                 "has " + std::to_string(lj.size()) + " step sizes (at most " +
                     std::to_string(limits::max_ladder) + ")");
        for (std::size_t i = 0; i < lj.size(); ++i) {
            const std::string key = "dt_ladder[" + std::to_string(i) + "]";
            const double dt = number(lj[i], file, key);
            if (!(dt > 0.0)) fail(file, key, "must be > 0");
            if (std::find(c.dts.begin(), c.dts.end(), dt) != c.dts.end())
                fail(file, key, "step size listed twice");
            c.dts.push_back(dt);
            c.steps.push_back(step_count(c.t_end - c.t0, dt, file, key, limits::max_steps_per_run));
        }
    }
    if (j.contains("output_dt")) {
        const double odt = number(j["output_dt"], file, "output_dt");
        if (!(odt > 0.0)) fail(file, "output_dt", "must be > 0");
        step_count(c.t_end - c.t0, odt, file, "output_dt", limits::max_output_points);
        for (double dt : c.dts) {
            const double r = odt / dt;
            if (std::abs(r - std::round(r)) > 1e-9 * r || std::round(r) < 1.0)
                fail(file, "output_dt", "must be an integer multiple of every dt");
        }
        c.output_dt = odt;
    }
}

// "diagnostics" and "reference": each known and supported by the problem (diagnostic registry).
void parse_diagnostics(const json& j, const std::string& file, CaseSpec& c,
                       const ProblemInfo& problem, std::optional<double> forcing_period) {
    const ProblemInfo* prob = &problem;
    if (j.contains("diagnostics")) {
        if (!j["diagnostics"].is_array()) fail(file, "diagnostics", "must be an array");
        for (std::size_t i = 0; i < j["diagnostics"].size(); ++i) {
            const std::string key = "diagnostics[" + std::to_string(i) + "]";
            const std::string d = string_of(j["diagnostics"][i], file, key);
            const auto& known = known_diagnostics();
            if (std::find(known.begin(), known.end(), d) == known.end()) {
                std::string list;
                for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
                fail(file, key, "unknown diagnostic '" + brief(d) + "' (known: " + list + ")");
            }
            if (c.wants(d)) fail(file, key, "diagnostic '" + d + "' listed twice");
            c.diagnostics.push_back(d);
        }
    } else {
        c.diagnostics.push_back("error");
    }
    // What each requested diagnostic needs of the ladder and which diagnostics it adds (registry).
    for (std::size_t i = 0; i < c.diagnostics.size(); ++i) {
        const DiagnosticInfo& d = *find_diagnostic(c.diagnostics[i]);
        if (c.dts.size() < d.needs.min_dts)
            fail(file, "dt_ladder",
                 "the " + d.name + " diagnostic needs >= " + std::to_string(d.needs.min_dts) +
                     " step sizes");
        for (const std::string& implied : d.implies)
            if (!c.wants(implied)) c.diagnostics.push_back(implied);
    }
    if (j.contains("reference")) {
        const json& rj = j["reference"];
        if (!rj.is_object()) fail(file, "reference", "must be an object");
        only_keys(rj, {"stepper", "epsrel", "epsabs"}, file, "reference.");
        if (rj.contains("stepper")) {
            c.reference.stepper = string_of(rj["stepper"], file, "reference.stepper");
            if (c.reference.stepper != "rkf45" && c.reference.stepper != "rk8pd")
                fail(file, "reference.stepper", "must be \"rkf45\" or \"rk8pd\"");
        }
        for (const char* k : {"epsrel", "epsabs"}) {
            if (!rj.contains(k)) continue;
            const double x = number(rj[k], file, std::string("reference.") + k);
            if (!(x >= limits::min_reference_tol && x <= limits::max_reference_tol))
                fail(file, std::string("reference.") + k,
                     "must be in [1e-15, 1e-2], got " + format_number(x));
            (std::string(k) == "epsrel" ? c.reference.epsrel : c.reference.epsabs) = x;
        }
    }
    // What each requested diagnostic needs of the problem: its `supports<P>` concept (registry).
    for (const std::string& name : c.diagnostics)
        if (!prob->supports(name))
            fail(file, "diagnostics",
                 name + " is not defined for problem '" + c.problem_id + "' (it needs " +
                     find_diagnostic(name)->requirement + ")");
    if (c.wants("poincare")) {
        // Sections at t0 + kT: the output grid must be the forcing period (typed_case.hpp).
        const double T = forcing_period.value_or(0.0);
        if (!c.output_dt || std::abs(*c.output_dt - T) > 1e-9 * T)
            fail(file, "output_dt",
                 "the poincare diagnostic needs output_dt equal to the forcing period " +
                     format_number(T) +
                     (c.output_dt ? ", got " + format_number(*c.output_dt)
                                  : std::string(", which is not given")));
    }
}

// "stability_sweep": exactly with the stability-sweep diagnostic.
void parse_sweep(const json& j, const std::string& file, CaseSpec& c) {
    if (c.wants("stability-sweep") != j.contains("stability_sweep"))
        fail(file, "stability_sweep",
             "give \"stability_sweep\" exactly when the stability-sweep diagnostic is requested");
    if (j.contains("stability_sweep")) {
        const json& sj = j["stability_sweep"];
        if (!sj.is_object()) fail(file, "stability_sweep", "must be an object");
        only_keys(sj, {"omega", "gamma", "h"}, file, "stability_sweep.");
        SweepSpec s;
        if (sj.contains("omega")) s.omega = number(sj["omega"], file, "stability_sweep.omega");
        if (!(s.omega > 0.0)) fail(file, "stability_sweep.omega", "must be > 0");
        if (!sj.contains("gamma") || !sj.contains("h"))
            fail(file, "stability_sweep", "needs \"gamma\" and \"h\" ranges");
        s.gamma = parse_range(sj["gamma"], file, "stability_sweep.gamma");
        s.h = parse_range(sj["h"], file, "stability_sweep.h");
        if (s.gamma.from < 0.0) fail(file, "stability_sweep.gamma[0]", "must be >= 0");
        if (!(s.h.from > 0.0)) fail(file, "stability_sweep.h[0]", "must be > 0");
        // The linear oscillator's ranges (its exact solution and F's closed forms).
        if (!(s.omega >= 1e-6 && s.omega <= 1e6))
            fail(file, "stability_sweep.omega", "must be in [1e-06, 1e+06]");
        if (!(s.gamma.to <= 1e6)) fail(file, "stability_sweep.gamma[1]", "must be <= 1e+06");
        if (!(s.h.to <= 1e6)) fail(file, "stability_sweep.h[1]", "must be <= 1e+06");
        const double cells = ((s.gamma.to - s.gamma.from) / s.gamma.step + 1.0) *
                             ((s.h.to - s.h.from) / s.h.step + 1.0);
        if (!(cells <= limits::max_sweep_cells))
            fail(file, "stability_sweep",
                 "gamma x h grid of " + format_number(std::round(cells)) + " points (at most 1e6)");
        c.sweep = s;
    }
}

// No silent cases: a case without a check says why.
void parse_no_checks(const json& j, const std::string& file, CaseSpec& c) {
    if (j.contains("no_checks_because")) {
        c.no_checks_because = string_of(j["no_checks_because"], file, "no_checks_because");
        if (c.no_checks_because.empty())
            fail(file, "no_checks_because", "must say why the case has no check");
        if (!c.checks.empty())
            fail(file, "no_checks_because",
                 "the case has " + std::to_string(c.checks.size()) +
                     " checks; give a reason only for a case without checks");
    } else if (c.checks.empty()) {
        fail(file, "expect",
             "the case has no check: add one, or say why with \"no_checks_because\": \"...\"");
    }
}

CaseSpec parse_case_unchecked(const json& input, const std::string& file,
                              const std::vector<std::string>& overrides, json& applied) {
    if (!input.is_object()) fail(file, "(top level)", "a case must be a JSON object");
    CaseSpec c;
    c.file = file;
    json j = input;
    for (const auto& o : overrides) {
        auto [key, value] = parse_override(o);
        set_path(j, key, value);
        c.overrides[key] = value;
        applied[key] = o.substr(o.find('=') + 1); // as typed (1e400, not inf)
    }
    c.raw = j;

    only_keys(j,
              {"id",
               "title",
               "source",
               "suites",
               "problem",
               "methods",
               "t0",
               "t_end",
               "dt",
               "dt_ladder",
               "diagnostics",
               "output_dt",
               "expect",
               "stability_sweep",
               "reference",
               "notes",
               "measures",
               "no_checks_because",
               "timeout_seconds",
               "method_files"},
              file, "");
    validate_limit_keys(j, file); // issue 17: timeout_seconds (src/harness/limits.hpp)
    for (const char* k : {"id", "problem", "methods", "t_end"})
        if (!j.contains(k)) fail(file, k, "missing required key");

    c.id = string_of(j["id"], file, "id");
    if (c.id.empty()) fail(file, "id", "must not be empty");
    if (!valid_case_id(c.id))
        fail(file, "id",
             "'" + brief(c.id) + "' is not a valid case id (at most " +
                 std::to_string(limits::max_id_length) +
                 " characters of A-Z a-z 0-9 . _ -, starting with a letter or digit)");
    if (j.contains("title")) c.title = string_of(j["title"], file, "title");
    if (j.contains("source")) c.source = string_of(j["source"], file, "source");
    if (j.contains("notes")) string_of(j["notes"], file, "notes");
    if (j.contains("suites")) {
        if (!j["suites"].is_array()) fail(file, "suites", "must be an array of suite names");
        for (std::size_t i = 0; i < j["suites"].size(); ++i) {
            const std::string key = "suites[" + std::to_string(i) + "]";
            const std::string suite = string_of(j["suites"][i], file, key);
            if (!valid_case_id(suite))
                fail(file, key,
                     "'" + brief(suite) +
                         "' is not a valid suite name (characters of A-Z a-z "
                         "0-9 . _ -, starting with a letter or digit)");
            if (std::find(c.suites.begin(), c.suites.end(), suite) != c.suites.end())
                fail(file, key, "suite '" + suite + "' listed twice");
            c.suites.push_back(suite);
        }
    }

    std::optional<double> forcing_period;
    const ProblemInfo* prob = parse_problem(j, file, c, forcing_period);
    parse_method_files(j, file); // issue 18 (harness/method_files.hpp), before "methods"
    parse_methods(j, file, c);
    parse_time_grid(j, file, c);
    parse_diagnostics(j, file, c, *prob, forcing_period);
    parse_sweep(j, file, c);
    if (j.contains("measures")) parse_measures(j["measures"], *prob, file, c);
    if (j.contains("expect")) parse_expect(j["expect"], *prob, file, c);
    parse_no_checks(j, file, c);
    return c;
}

} // namespace

} // namespace dampsym
