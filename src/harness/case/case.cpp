// Cases: the public entry points of the case parser (load_case, parse_case with the --set
// attribution of errors), the diagnostic names, case ids and the predicted cost of a case.
#include "harness/case/case.hpp"

#include "harness/bounded_read.hpp"

#include "harness/case/util.hpp"
#include "harness/problem_info.hpp"
#include "harness/run/case_job.hpp"
#include "harness/run/limits.hpp"

#include <algorithm>
#include <map>

namespace dampsym {
namespace {

using json = nlohmann::json;
using namespace case_detail;

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

} // namespace

std::vector<double> Range3::values() const {
    std::vector<double> out;
    const auto n = static_cast<std::int64_t>(std::floor((to - from) / step + 1e-9));
    for (std::int64_t i = 0; i <= n; ++i) out.push_back(from + static_cast<double>(i) * step);
    return out;
}

bool CaseSpec::wants(std::string_view d) const {
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
    // control characters escaped: a newline in a value must not break the one-line message
    return quote_for_message(s, limits::max_message_value);
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

} // namespace dampsym
