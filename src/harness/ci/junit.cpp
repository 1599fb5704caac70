#include "harness/ci/junit.hpp"

#include "harness/report/report.hpp"

#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace dampsym {
namespace {

using json = nlohmann::json;

// XML attribute/text escaping; characters XML 1.0 forbids are dropped.
std::string xml(const std::string& s) {
    std::string out;
    out.reserve(s.size());
    for (const char ch : s) {
        const auto c = static_cast<unsigned char>(ch);
        switch (ch) {
        case '&':
            out += "&amp;";
            break;
        case '<':
            out += "&lt;";
            break;
        case '>':
            out += "&gt;";
            break;
        case '"':
            out += "&quot;";
            break;
        case '\'':
            out += "&apos;";
            break;
        case '\n':
            out += "&#10;";
            break;
        case '\t':
            out += "&#9;";
            break;
        default:
            if (c >= 0x20) out += ch; // other control characters are not XML 1.0
        }
    }
    return out;
}

// The shortest of %.15g, %.16g, %.17g that reads back as the same double (0.1, not
// 0.10000000000000001).
std::string junit_num(const json& v) {
    if (v.is_null()) return "null";
    if (!v.is_number_float()) return v.dump();
    const double x = v.get<double>();
    char buf[64];
    for (int digits = 15; digits <= 17; ++digits) {
        std::snprintf(buf, sizeof buf, "%.*g", digits, x);
        if (std::strtod(buf, nullptr) == x) break;
    }
    return buf;
}

// Seconds as JUnit readers accept them (no exponent).
std::string seconds(double s) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.6f", s < 0.0 ? 0.0 : s);
    return buf;
}

std::string expected_text(const json& ck) {
    const std::string op = ck["op"].get<std::string>();
    std::string e = op == "near" ? junit_num(ck["expected"]) + " +- " + junit_num(ck["tolerance"])
                    : op == "le" ? "<= " + junit_num(ck["expected"])
                    : op == "ge" ? ">= " + junit_num(ck["expected"])
                    : op == "lt" ? "< " + junit_num(ck["expected"])
                                 : "> " + junit_num(ck["expected"]);
    if (ck.value("abs", false)) e = "|x| " + e;
    return e;
}

// A check whose value is missing because its run (or its reference) failed, not because the
// value was out of tolerance.
bool is_error(const json& ck) {
    if (ck["passed"].get<bool>() || !ck.contains("message")) return false;
    const std::string m = ck["message"].get<std::string>();
    return m.rfind("run ", 0) == 0 || m.rfind("reference failed", 0) == 0;
}

// The <failure> (a check out of tolerance) or <error> (its run or reference failed) of a check.
std::string failure_xml(const json& c, const json& ck) {
    const std::string what = "metric " + ck["metric"].get<std::string>() + ": value " +
                             junit_num(ck["value"]) + ", expected " + expected_text(ck);
    std::ostringstream detail;
    detail << "check: " << ck["name"].get<std::string>()
           << (ck.value("negative_control", false) ? " (negative control)" : "")
           << "\nmethod: " << ck["method"].get<std::string>();
    if (ck.contains("dt")) detail << "\ndt: " << junit_num(ck["dt"]);
    detail << "\nmetric: " << ck["metric"].get<std::string>()
           << "\nvalue: " << junit_num(ck["value"]) << "\nexpected: " << expected_text(ck);
    if (ck.contains("tolerance")) detail << "\ntolerance: " << junit_num(ck["tolerance"]);
    if (ck.contains("message")) detail << "\nmessage: " << ck["message"].get<std::string>();
    if (ck.contains("note")) detail << "\nnote: " << ck["note"].get<std::string>();
    if (!c.value("source", std::string()).empty())
        detail << "\nsource: " << c["source"].get<std::string>();
    if (is_error(ck))
        return "      <error type=\"run-failed\" message=\"" +
               xml(ck["message"].get<std::string>()) + "\">" + xml(detail.str()) + "</error>\n";
    return "      <failure type=\"check-failed\" message=\"" + xml(what) + "\">" +
           xml(detail.str()) + "</failure>\n";
}

// The wall time of the runs a check reads: the run of its method and dt, or (a check across the
// step sizes, or of the method as a whole) every run of its method; 0 when none is timed.
double check_seconds(const json& report, std::size_t ci, const json& ck) {
    const json& runs = report["cases"][ci]["runs"];
    double sum = 0.0;
    for (std::size_t ri = 0; ri < runs.size(); ++ri) {
        if (runs[ri]["method"] != ck["method"]) continue;
        if (ck.contains("dt") && runs[ri]["dt"] != ck["dt"]) continue;
        if (const json* rt = run_timing(report, ci, ri); rt && rt->contains("wall_seconds"))
            sum += (*rt)["wall_seconds"].get<double>();
    }
    return sum;
}

// The suite's timestamp (JUnit: ISO 8601 without a zone; the run's start, UTC) and host name,
// from the report's provenance (a merged report: its first shard's).
std::string suite_attributes(const json& report) {
    const json none = json::object();
    const json& p = report.contains("provenance") ? report["provenance"] : none;
    const json& src = p.contains("host") || !p.contains("merged_from") ||
                              !p["merged_from"].is_array() || p["merged_from"].empty() ||
                              !p["merged_from"][0].is_object()
                          ? p
                          : p["merged_from"][0];
    std::string stamp = src.value("start_utc", p.value("start_utc", std::string()));
    if (!stamp.empty() && stamp.back() == 'Z') stamp.pop_back();
    std::string host = "unknown";
    if (src.contains("host") && src["host"].is_object() && src["host"].contains("hostname") &&
        src["host"]["hostname"].is_string())
        host = src["host"]["hostname"].get<std::string>();
    std::string out = " hostname=\"" + xml(host) + "\"";
    if (!stamp.empty()) out += " timestamp=\"" + xml(stamp) + "\"";
    return out;
}

} // namespace

std::string junit_test_name(const json& ck) {
    std::string name = ck["name"].get<std::string>() + " [" + ck["method"].get<std::string>();
    if (ck.contains("dt")) name += ", dt=" + junit_num(ck["dt"]);
    return name + "]";
}

// The case's checks that the selection left without a method (report "checks_not_run"), as
// skipped testcases with the reason.
void skipped_testcases(std::ostringstream& body, const json& c, const std::string& id) {
    if (!c.contains("checks_not_run")) return;
    for (const auto& ck : c["checks_not_run"])
        body << "    <testcase classname=\"" << xml(id) << "\" name=\"" << xml(junit_test_name(ck))
             << "\" time=\"0.000000\">\n      <skipped message=\""
             << xml(ck.value("reason", std::string())) << "\"/>\n    </testcase>\n";
}

std::string render_junit(const json& report) {
    // skipped (not-run) checks are counted per <testsuite>: the JUnit schema has no skipped
    // attribute on <testsuites>
    std::int64_t tests = 0, failures = 0, errors = 0;
    std::ostringstream body;
    double total_time = 0.0;
    const bool timed = report.contains("timings") && report["timings"].contains("wall_seconds");
    if (timed) total_time = report["timings"]["wall_seconds"].get<double>();
    const std::string attributes = suite_attributes(report);
    for (std::size_t ci = 0; ci < report["cases"].size(); ++ci) {
        const json& c = report["cases"][ci];
        std::int64_t t = 0, f = 0, e = 0;
        for (const auto& ck : c["checks"]) {
            ++t;
            if (is_error(ck))
                ++e;
            else if (!ck["passed"].get<bool>())
                ++f;
        }
        const std::int64_t s = c.contains("checks_not_run")
                                   ? static_cast<std::int64_t>(c["checks_not_run"].size())
                                   : 0;
        t += s;
        tests += t;
        failures += f;
        errors += e;
        double case_time = 0.0;
        for (std::size_t ri = 0; ri < c["runs"].size(); ++ri)
            if (const json* rt = run_timing(report, ci, ri); rt && rt->contains("wall_seconds"))
                case_time += (*rt)["wall_seconds"].get<double>();
        const std::string id = c["id"].get<std::string>();
        body << "  <testsuite name=\"" << xml(id) << "\" tests=\"" << t << "\" failures=\"" << f
             << "\" errors=\"" << e << "\" skipped=\"" << s << "\" time=\"" << seconds(case_time)
             << "\"" << attributes << ">\n    <properties>\n";
        auto property = [&](const char* name, const std::string& value) {
            body << "      <property name=\"" << name << "\" value=\"" << xml(value) << "\"/>\n";
        };
        property("title", c.value("title", std::string()));
        property("source", c.value("source", std::string()));
        property("problem", c["problem"]["id"].get<std::string>());
        property("file", c.value("file", std::string()));
        body << "    </properties>\n";
        for (const auto& ck : c["checks"]) {
            body << "    <testcase classname=\"" << xml(id) << "\" name=\""
                 << xml(junit_test_name(ck)) << "\" time=\""
                 << seconds(check_seconds(report, ci, ck)) << "\"";
            if (ck["passed"].get<bool>()) {
                body << "/>\n";
                continue;
            }
            body << ">\n" << failure_xml(c, ck) << "    </testcase>\n";
        }
        skipped_testcases(body, c, id);
        body << "  </testsuite>\n";
    }
    std::ostringstream os;
    os << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"dampsym\" tests=\""
       << tests << "\" failures=\"" << failures << "\" errors=\"" << errors << "\"";
    if (timed) os << " time=\"" << seconds(total_time) << "\"";
    os << ">\n" << body.str() << "</testsuites>\n";
    return os.str();
}

} // namespace dampsym
