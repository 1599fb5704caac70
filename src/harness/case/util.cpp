#include "harness/case/util.hpp"
#include "harness/suggest.hpp"

#include <cmath>
#include <sstream>

namespace dampsym::case_detail {

std::string format_number(double x) {
    std::ostringstream os;
    os.precision(17);
    os << x;
    return os.str();
}

double number(const json& v, const std::string& file, const std::string& key) {
    if (!v.is_number()) fail(file, key, "must be a number, got " + brief(v));
    const double x = v.get<double>();
    if (std::isnan(x)) fail(file, key, "must be a number, got NaN");
    if (std::isinf(x))
        fail(file, key,
             "must be finite, got " + std::string(x > 0 ? "+" : "-") +
                 "infinity (or a number that overflows a double)");
    return x;
}

std::string string_of(const json& v, const std::string& file, const std::string& key) {
    if (!v.is_string()) fail(file, key, "must be a string, got " + brief(v));
    return v.get<std::string>();
}

bool boolean(const json& v, const std::string& file, const std::string& key) {
    if (!v.is_boolean()) fail(file, key, "must be true or false, got " + brief(v));
    return v.get<bool>();
}

std::string describe(const Range& r) {
    std::ostringstream os;
    os << (r.lo_open ? "(" : "[") << r.lo << ", " << r.hi << (r.hi_open ? ")" : "]");
    return os.str();
}

void only_keys(const json& obj, const std::set<std::string>& allowed, const std::string& file,
               const std::string& prefix) {
    for (auto it = obj.begin(); it != obj.end(); ++it) {
        if (!allowed.count(it.key())) {
            std::string list;
            for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
            const std::string hint =
                did_you_mean(it.key(), std::vector<std::string>(allowed.begin(), allowed.end()));
            fail(file, prefix + brief(it.key()),
                 "unknown key" + (hint.empty() ? "" : "; " + hint) + " (allowed: " + list + ")");
        }
    }
}

// Steps of size dt in [t0, t_end]; t_end − t0 must be an integer multiple of dt to 1e-9 relative.
std::int64_t step_count(double span, double dt, const std::string& file, const std::string& key,
                        double limit) {
    const double ratio = span / dt;
    if (!(ratio <= limit)) {
        std::ostringstream os;
        os.precision(3);
        os << "too many steps: (t_end - t0)/" << key << " = " << ratio << " (limit " << limit
           << ")";
        fail(file, key, os.str());
    }
    const auto n = static_cast<std::int64_t>(std::llround(ratio));
    if (n < 1 || std::abs(static_cast<double>(n) * dt - span) > 1e-9 * span) {
        std::ostringstream os;
        os.precision(17);
        os << "t_end - t0 = " << span << " is not an integer multiple of dt = " << dt;
        fail(file, key, os.str());
    }
    return n;
}

Range3 parse_range(const json& v, const std::string& file, const std::string& key) {
    if (!v.is_array() || v.size() != 3)
        fail(file, key, "must be [from, to, step], got " + brief(v));
    Range3 r{number(v[0], file, key + "[0]"), number(v[1], file, key + "[1]"),
             number(v[2], file, key + "[2]")};
    if (!(r.step > 0.0)) fail(file, key + "[2]", "step must be > 0");
    if (r.to < r.from) fail(file, key + "[1]", "must be >= from");
    if (!((r.to - r.from) / r.step <= 10000.0)) fail(file, key, "more than 10000 grid points");
    return r;
}

// Metric names each run-level or method-level diagnostic produces (for validating "expect"), from
// the diagnostic registry (src/diagnostics/diagnostic.hpp).
std::vector<std::string> metric_names(const std::string& diagnostic,
                                      const std::vector<std::string>& invariants) {
    return diagnostic_metrics(diagnostic, invariants);
}

} // namespace dampsym::case_detail
