#include "harness/case.hpp"

#include "harness/case_job.hpp"
#include "harness/limits.hpp"
#include "harness/registry.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fcntl.h>
#include <map>
#include <set>
#include <sstream>
#include <sys/stat.h>
#include <unistd.h>

namespace dampsym {
namespace {

using json = nlohmann::json;

// A validation error with its key kept apart, so that parse_case can say when the value came
// from --set rather than from the file.
struct KeyedError : InputError {
    KeyedError(const std::string& file, const std::string& key, const std::string& what)
        : InputError(file + ": " + key + ": " + what), file_(file), key_(key), what_(what) {}
    std::string file_, key_, what_;
};

[[noreturn]] void fail(const std::string& file, const std::string& key, const std::string& what) {
    throw KeyedError(file, key, what);
}

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

void only_keys(const json& obj, const std::set<std::string>& allowed, const std::string& file,
               const std::string& prefix) {
    for (auto it = obj.begin(); it != obj.end(); ++it) {
        if (!allowed.count(it.key())) {
            std::string list;
            for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
            fail(file, prefix + brief(it.key()), "unknown key (allowed: " + list + ")");
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

// Metric names each run-level or method-level diagnostic produces (for validating "expect").
std::vector<std::string> metric_names(const std::string& diagnostic,
                                      const std::vector<std::string>& invariants) {
    if (diagnostic == "error")
        return {"final_abs", "final_rel", "max_abs",
                "max_rel",   "mean_abs",  "reference_error_estimate"};
    if (diagnostic == "order" || diagnostic == "local-order") return {"slope", "r2", "points"};
    if (diagnostic == "local-error") return {"abs", "rel"};
    if (diagnostic == "invariants") {
        std::vector<std::string> out;
        for (const auto& inv : invariants)
            for (const char* stat :
                 {"max_step_res", "last_step_res", "max_step_abs", "scale_initial",
                  "scale_at_max_step_res", "max_global_res", "global_res_slope",
                  "max_global_ratio_dev", "ratio_dev_slope", "undefined_points"})
                out.push_back(inv + "." + stat);
        return out;
    }
    if (diagnostic == "energy")
        return {"max_abs_error",  "final_abs_error", "drift_slope",    "error_res_slope",
                "max_abs_change", "change_slope",    "max_change_res", "change_res_slope",
                "growth_ratio",   "scale_initial"};
    if (diagnostic == "dissipation-drift")
        return {"slope",
                "range",
                "maxima",
                "maxima_nonpositive",
                "slope_minus_reference",
                "max_abs_diff_reference",
                "maxima_count_diff",
                "reference.slope"};
    if (diagnostic == "momentum") {
        std::vector<std::string> out;
        for (const char* part : {"linear", "angular"})
            for (const char* stat :
                 {"max_law_res", "last_law_res", "max_law_abs", "scale_initial",
                  "scale_at_max_law_res", "first_factor", "max_factor_dev", "max_table_res",
                  "initial_norm", "undefined_points", "factor_undefined_points"})
                out.push_back(std::string(part) + "." + stat);
        return out;
    }
    if (diagnostic == "conformal-symplectic")
        return {"max_rel",  "last_rel",       "max_abs",
                "last_abs", "steps_measured", "rel_undefined_steps"};
    if (diagnostic == "energy-balance")
        return {"max", "last", "mean", "max_rel", "max_rate", "points"};
    if (diagnostic == "poincare")
        return {"sections", "pointwise_max", "pointwise_final", "set_mean", "set_hausdorff"};
    if (diagnostic == "temperature")
        return {"initial", "mean", "min", "max", "max_abs_dev_initial", "max_abs_error"};
    if (diagnostic == "stability")
        return {"det",
                "det_rel_err",
                "det_abs_err",
                "half_trace",
                "half_trace_formula_rel_err",
                "half_trace_formula_abs_err",
                "half_trace_exact_err",
                "spectral_radius",
                "F_condition",
                "power_bounded"};
    if (diagnostic == "stability-sweep")
        return {"max_boundary_mismatch_cells", "mismatch_points",
                "violations_omega_gt_gamma",   "F_violations",
                "power_bounded_violations",    "max_power_boundary_mismatch_cells",
                "power_mismatch_points",       "first_row.gamma",
                "first_row.h_F_empirical",     "first_row.h_power_unbounded"};
    // Not a diagnostic: the run record's own fields, checkable in every case and for any status.
    if (diagnostic == "run")
        return {"steps",     "steps_planned", "rhs_evals",
                "jac_evals", "newton_iters",  "final_time",
                "ok",        "diverged",      "failed_at_step"};
    if (diagnostic == "trace-taylor")
        return {"h4_coeff", "h4_coeff_expected", "h4_coeff_rel_err", "h4_coeff_abs_err"};
    if (diagnostic == "cost")
        return {"rhs_evals_per_step", "jac_evals_per_step", "newton_iters_per_step",
                "max_newton_iters", "wall_seconds"};
    return {};
}

// "methods" (each method), "ratio" ([A, B]: metric(A) / metric(B)) or "spread" ("all" or
// [A, B, ...]: max / min over the methods), and "across_dt" (docs/case-keys.md).
void parse_check_methods(const json& cj, const CaseSpec& c, const std::string& diag,
                         const std::string& file, const std::string& base, CheckSpec& cs) {
    int forms = 0;
    for (const char* k : {"methods", "ratio", "spread"}) forms += cj.contains(k) ? 1 : 0;
    if (forms != 1) fail(file, base + ".methods", "give exactly one of methods, ratio, spread");
    const char* key = cj.contains("methods") ? "methods"
                      : cj.contains("ratio") ? "ratio"
                                             : "spread";
    cs.form = cj.contains("methods") ? CheckForm::per_method
              : cj.contains("ratio") ? CheckForm::ratio
                                     : CheckForm::spread;
    const json& mj = cj[key];
    const std::string mkey = base + "." + key;
    if (mj.is_string() && mj.get<std::string>() == "all" && cs.form != CheckForm::ratio) {
        cs.methods = c.methods;
    } else {
        if (!mj.is_array() || mj.empty())
            fail(file, mkey,
                 cs.form == CheckForm::ratio ? "must be an array [A, B] of two methods"
                                             : "must be \"all\" or a non-empty array");
        for (std::size_t i = 0; i < mj.size(); ++i) {
            const std::string ki = mkey + "[" + std::to_string(i) + "]";
            const std::string m = string_of(mj[i], file, ki);
            if (std::find(c.methods.begin(), c.methods.end(), m) == c.methods.end())
                fail(file, ki, "method '" + brief(m) + "' is not among the case's methods");
            if (std::find(cs.methods.begin(), cs.methods.end(), m) != cs.methods.end())
                fail(file, ki, "method '" + brief(m) + "' listed twice");
            cs.methods.push_back(m);
        }
    }
    if (cs.form == CheckForm::ratio && cs.methods.size() != 2)
        fail(file, mkey, "must name exactly two methods [A, B] (value A / B)");
    if (cs.form == CheckForm::spread && cs.methods.size() < 2)
        fail(file, mkey, "needs at least two methods");
    if (cj.contains("across_dt")) {
        const std::string a = string_of(cj["across_dt"], file, base + ".across_dt");
        if (a != "loglog-slope") fail(file, base + ".across_dt", "must be \"loglog-slope\"");
        if (c.dts.size() < 2)
            fail(file, base + ".across_dt", "needs a dt_ladder of at least two step sizes");
        cs.across_dt_slope = true;
    }
    if ((cs.form != CheckForm::per_method || cs.across_dt_slope) &&
        (diagnostic_is_method_level(diag) || diag == "run"))
        fail(file, base + ".metric",
             "ratio, spread and across_dt compare per-run metrics; '" + diag + "' is not one");
}

// "measures": { "<name>": { "quantity", "component", "norm", "over", "from" } }
// (docs/case-keys.md).
void parse_measures(const json& mj, const ProblemInfo& prob, const std::string& file, CaseSpec& c) {
    if (!mj.is_object() || mj.empty())
        fail(file, "measures", "must be an object of named measures");
    if (!c.wants("error"))
        fail(file, "measures", "measures are computed by the \"error\" diagnostic; request it");
    int dim = 0, dof = -1; // dof: degrees of freedom of a canonical z = [q; p], else -1
    with_problem_type(c.problem_id, [&]<class P>() {
        const P p = P::from_params(c.params);
        dim = p.dim();
        if constexpr (requires { p.n(); }) dof = p.n();
    });
    const std::int64_t points = detail::output_points(c);
    for (auto it = mj.begin(); it != mj.end(); ++it) {
        const std::string base = "measures." + it.key();
        const json& e = it.value();
        MeasureSpec m;
        m.name = it.key();
        if (m.name.empty() ||
            m.name.find_first_not_of("abcdefghijklmnopqrstuvwxyz"
                                     "ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-") != std::string::npos)
            fail(file, base, "a measure name uses letters, digits, '_' and '-' only");
        if (!e.is_object()) fail(file, base, "must be an object");
        only_keys(e, {"quantity", "component", "norm", "over", "from"}, file, base + ".");
        if (e.contains("quantity")) {
            const std::string q = string_of(e["quantity"], file, base + ".quantity");
            if (q == "energy-error")
                m.quantity = MeasureQuantity::energy_error;
            else if (q != "error")
                fail(file, base + ".quantity", "must be \"error\" or \"energy-error\"");
        }
        if (m.quantity == MeasureQuantity::energy_error) {
            if (!prob.has_energy)
                fail(file, base + ".quantity", "problem '" + c.problem_id + "' declares no energy");
            if (e.contains("component"))
                fail(file, base + ".component", "the energy error has no component");
            m.component = "energy";
        } else {
            m.count = dim;
            if (e.contains("component")) {
                m.component = string_of(e["component"], file, base + ".component");
                const std::string& s = m.component;
                if (s.empty()) fail(file, base + ".component", "must not be empty");
                const bool qp = s[0] == 'q' || s[0] == 'p';
                if ((qp || s.rfind("z[", 0) == 0) && s != "state") {
                    if (qp && dof < 0)
                        fail(file, base + ".component",
                             "problem '" + c.problem_id +
                                 "' has no canonical q/p split; use \"z[i]\" or \"state\"");
                    const int block = s[0] == 'z' ? dim : dof;
                    const int offset = s[0] == 'p' ? dof : 0;
                    if (s.size() == 1) {
                        m.first = offset;
                        m.count = dof;
                    } else {
                        std::size_t used = 0;
                        int idx = -1;
                        if (s.size() > 3 && s[1] == '[' && s.back() == ']') {
                            try {
                                idx = std::stoi(s.substr(2, s.size() - 3), &used);
                            } catch (const std::exception&) {
                                idx = -1;
                            }
                        }
                        if (idx < 0 || used != s.size() - 3)
                            fail(file, base + ".component",
                                 "must be \"state\", \"q\", \"p\", \"q[i]\", \"p[i]\" or "
                                 "\"z[i]\", got \"" +
                                     s + "\"");
                        if (idx >= block)
                            fail(file, base + ".component",
                                 "index " + std::to_string(idx) + " out of range (" +
                                     std::to_string(block) + " components)");
                        m.first = offset + idx;
                        m.count = 1;
                    }
                } else if (s != "state") {
                    fail(file, base + ".component",
                         "must be \"state\", \"q\", \"p\", \"q[i]\", \"p[i]\" or \"z[i]\", "
                         "got \"" +
                             s + "\"");
                }
            }
        }
        if (e.contains("norm")) {
            const std::string n = string_of(e["norm"], file, base + ".norm");
            if (n == "rel")
                m.relative = true;
            else if (n != "abs")
                fail(file, base + ".norm", "must be \"abs\" or \"rel\" (relative to |u(t_n)|)");
        }
        if (!e.contains("over")) fail(file, base + ".over", "missing required key");
        const std::string over = string_of(e["over"], file, base + ".over");
        const std::pair<const char*, MeasureStat> stats[] = {{"final", MeasureStat::final_value},
                                                             {"max", MeasureStat::max},
                                                             {"mean", MeasureStat::mean},
                                                             {"rms", MeasureStat::rms},
                                                             {"growth", MeasureStat::growth}};
        bool found = false;
        for (const auto& [name, st] : stats)
            if (over == name) {
                m.over = st;
                found = true;
            }
        if (!found) fail(file, base + ".over", "must be one of final, max, mean, rms, growth");
        if (m.over != MeasureStat::final_value && points < 2)
            fail(file, base + ".over",
                 "'" + over +
                     "' needs an output grid: give \"output_dt\" (or a ladder whose "
                     "step sizes divide each other)");
        const double span = c.t_end - c.t0;
        m.growth_from = c.t0 + 0.1 * span;
        if (e.contains("from")) {
            if (m.over != MeasureStat::growth)
                fail(file, base + ".from", "only \"over\": \"growth\" takes a fit start");
            m.growth_from = number(e["from"], file, base + ".from");
            if (!(m.growth_from > c.t0) || !(m.growth_from < c.t_end))
                fail(file, base + ".from", "must lie in (t0, t_end)");
        }
        if (m.over == MeasureStat::growth) {
            const double spacing = span / static_cast<double>(points);
            if ((c.t_end - m.growth_from) / spacing < 2.0)
                fail(file, base + ".from", "the growth fit needs >= 3 output points after it");
        }
        c.measures.push_back(m);
    }
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
    static const std::vector<std::string> names{"error",
                                                "order",
                                                "invariants",
                                                "energy",
                                                "dissipation-drift",
                                                "stability",
                                                "stability-sweep",
                                                "trace-taylor",
                                                "cost",
                                                "momentum",
                                                "energy-balance",
                                                "poincare",
                                                "temperature",
                                                "conformal-symplectic",
                                                "local-error",
                                                "local-order"};
    return names;
}

bool diagnostic_applies(const std::string& d, const ProblemInfo& p) {
    if (d == "energy") return p.has_energy;
    if (d == "momentum") return p.has_momentum;
    if (d == "energy-balance") return p.has_energy_balance;
    if (d == "temperature") return p.has_temperature;
    if (d == "poincare") return p.has_forcing_period;
    if (d == "dissipation-drift") return p.has_maxima;
    if (d == "local-error" || d == "local-order") return p.has_exact;
    if (d == "stability" || d == "stability-sweep" || d == "trace-taylor")
        return p.id == "oscillator";
    return true;
}

bool diagnostic_is_method_level(const std::string& d) {
    return d == "order" || d == "local-order" || d == "stability-sweep" || d == "trace-taylor";
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
    return metric_names(diagnostic, invariant_names.empty() && diagnostic == "invariants"
                                        ? std::vector<std::string>{"<invariant>"}
                                        : invariant_names);
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
              {"id", "title", "source", "suites", "problem", "methods", "t0", "t_end", "dt",
               "dt_ladder", "diagnostics", "output_dt", "expect", "stability_sweep", "reference",
               "notes", "measures", "no_checks_because", "timeout_seconds"},
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

    // problem
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
    std::optional<double> forcing_period;
    with_problem_type(c.problem_id, [&]<class P>() {
        try {
            const P p = P::from_params(c.params);
            c.dim = p.dim();
            if constexpr (HasForcingPeriod<P>) forcing_period = p.forcing_period();
        } catch (const std::invalid_argument& e) {
            fail(file, "problem", e.what());
        }
    });

    // methods
    if (!j["methods"].is_array() || j["methods"].empty())
        fail(file, "methods", "must be a non-empty array of method ids");
    for (std::size_t i = 0; i < j["methods"].size(); ++i) {
        const std::string key = "methods[" + std::to_string(i) + "]";
        const std::string m = string_of(j["methods"][i], file, key);
        if (!find_method(m)) {
            std::string list;
            for (const auto& mi : method_catalog())
                list += (list.empty() ? "" : ", ") + std::string(mi.id);
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

    // time grid
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

    // diagnostics
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
    if (c.wants("order")) {
        if (c.dts.size() < 3) fail(file, "dt_ladder", "the order diagnostic needs >= 3 step sizes");
        if (!c.wants("error")) c.diagnostics.push_back("error");
    }
    if (c.wants("local-order")) {
        if (c.dts.size() < 3)
            fail(file, "dt_ladder", "the local-order diagnostic needs >= 3 step sizes");
        if (!c.wants("local-error")) c.diagnostics.push_back("local-error");
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
    if (c.wants("energy") && !prob->has_energy)
        fail(file, "diagnostics", "problem '" + c.problem_id + "' declares no energy");
    const std::pair<const char*, bool> needs[] = {
        {"momentum", prob->has_momentum},        {"energy-balance", prob->has_energy_balance},
        {"temperature", prob->has_temperature},  {"poincare", prob->has_forcing_period},
        {"dissipation-drift", prob->has_maxima}, {"local-error", prob->has_exact}};
    for (const auto& [d, supported] : needs)
        if (c.wants(d) && !supported)
            fail(file, "diagnostics",
                 std::string(d) + " is not defined for problem '" + c.problem_id + "'");
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
    for (const char* d : {"stability", "stability-sweep", "trace-taylor"})
        if (c.wants(d) && c.problem_id != "oscillator")
            fail(file, "diagnostics", std::string(d) + " is defined on the oscillator only");
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
        // The oscillator's ranges (its exact solution and F's closed forms).
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

    if (j.contains("measures")) parse_measures(j["measures"], *prob, file, c);

    // expectations
    if (j.contains("expect")) {
        const json& ej = j["expect"];
        if (!ej.is_object()) fail(file, "expect", "must be an object of named checks");
        for (auto it = ej.begin(); it != ej.end(); ++it) {
            const std::string base = "expect." + brief(it.key());
            const json& cj = it.value();
            if (!cj.is_object()) fail(file, base, "must be an object");
            only_keys(cj,
                      {"metric", "methods", "ratio", "spread", "across_dt", "refutes", "near", "le",
                       "ge", "lt", "gt", "tol", "abs", "negative_control", "dt", "note"},
                      file, base + ".");
            CheckSpec cs;
            cs.name = it.key();
            if (!cj.contains("metric")) fail(file, base + ".metric", "missing required key");
            cs.metric = string_of(cj["metric"], file, base + ".metric");
            const auto dot = cs.metric.find('.');
            const std::string diag = cs.metric.substr(0, dot);
            const bool is_measure = diag == "measure" && !c.measures.empty();
            if (dot == std::string::npos || (!c.wants(diag) && diag != "run" && !is_measure))
                fail(file, base + ".metric",
                     "'" + brief(cs.metric) + "' is not a metric of a requested diagnostic" +
                         (diag == "measure" ? " (no \"measures\" defined)" : ""));
            std::vector<std::string> names = metric_names(diag, prob->invariants);
            if (diag == "invariants" && names.empty())
                fail(file, base + ".metric",
                     "problem '" + c.problem_id + "' declares no conformal invariants");
            if (is_measure)
                for (const auto& m : c.measures) names.push_back(m.name);
            if (std::find(names.begin(), names.end(), cs.metric.substr(dot + 1)) == names.end()) {
                std::string list;
                for (const auto& n : names) list += (list.empty() ? "" : ", ") + diag + "." + n;
                fail(file, base + ".metric",
                     "unknown metric '" + brief(cs.metric) + "' (known: " + list + ")");
            }
            parse_check_methods(cj, c, diag, file, base, cs);
            int ops = 0;
            const std::pair<const char*, CheckOp> op_names[] = {{"near", CheckOp::near},
                                                                {"le", CheckOp::le},
                                                                {"ge", CheckOp::ge},
                                                                {"lt", CheckOp::lt},
                                                                {"gt", CheckOp::gt}};
            for (const auto& [name, op] : op_names) {
                if (!cj.contains(name)) continue;
                ++ops;
                cs.op = op;
                const json& v = cj[name];
                cs.value = v.is_boolean() ? (v.get<bool>() ? 1.0 : 0.0)
                                          : number(v, file, base + "." + name);
            }
            if (ops != 1) fail(file, base, "give exactly one of near, le, ge, lt, gt");
            if (cs.op == CheckOp::near) {
                if (!cj.contains("tol")) fail(file, base + ".tol", "\"near\" needs a tolerance");
                cs.tol = number(cj["tol"], file, base + ".tol");
                if (!(cs.tol >= 0.0)) fail(file, base + ".tol", "must be >= 0");
            } else if (cj.contains("tol")) {
                fail(file, base + ".tol", "only \"near\" takes a tolerance");
            }
            if (cj.contains("abs")) cs.use_abs = boolean(cj["abs"], file, base + ".abs");
            if (cj.contains("negative_control"))
                cs.negative_control =
                    boolean(cj["negative_control"], file, base + ".negative_control");
            if (cj.contains("note")) cs.note = string_of(cj["note"], file, base + ".note");
            if (cj.contains("refutes"))
                cs.refutes = boolean(cj["refutes"], file, base + ".refutes");
            if (cj.contains("dt")) {
                if (cs.across_dt_slope)
                    fail(file, base + ".dt", "\"across_dt\" uses every step size; no dt");
                const double dt = number(cj["dt"], file, base + ".dt");
                if (std::find(c.dts.begin(), c.dts.end(), dt) == c.dts.end())
                    fail(file, base + ".dt", "not one of the case's step sizes");
                if (diagnostic_is_method_level(diag))
                    fail(file, base + ".dt", "'" + diag + "' is a per-method metric; no dt");
                cs.dt = dt;
            }
            c.checks.push_back(cs);
        }
    }

    // No silent cases: a case without a check says why.
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
    return c;
}

} // namespace

} // namespace dampsym
