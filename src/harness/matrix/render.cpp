// The method × property matrix, the rendering: the matrix JSON (judge_matrix) as a Markdown table
// with its legend and criteria (docs/matrix.md; the README's table is this output).
#include "harness/matrix/matrix.hpp"
#include "harness/report/markdown.hpp"

#include <cstdio>
#include <sstream>

namespace dampsym {
namespace matrix_detail {
namespace {

using json = nlohmann::json;

std::string fmt(double v, const char* f = "%.3g") {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

std::string cell_text(const std::string& prop, const json& c) {
    const std::string verdict = c["verdict"];
    const std::string role = c["role"];
    std::string v;
    if (prop == "coefficients" && c.contains("checks")) {
        const int n = c["checks"].get<int>(), agree = c["agree"].get<int>();
        v = std::to_string(agree) + "/" + std::to_string(n);
        if (agree < n) {
            std::string names;
            for (const auto& r : c["refuted"])
                names += (names.empty() ? "" : ", ") + r.get<std::string>();
            v += " (" + names + ")";
        }
    } else if (c["value"].is_number()) {
        const double x = c["value"].get<double>();
        v = prop == "order" ? fmt(x, "%.2f") : fmt(x, "%.2g");
    } else if (prop == "threshold" && (verdict != "n/a" || c.contains("swept"))) {
        v = "none"; // no failure on the grid
    } else if (c.contains("detail") && c["detail"].get<std::string>().rfind("run ", 0) == 0) {
        v = c["detail"].get<std::string>().substr(4); // the run's status, e.g. solve-failed
    } else if (prop == "order") {
        v = "no fit"; // fewer than three consistent points (docs/conventions.md §5 order)
    }
    if (prop == "threshold" && !v.empty()) v = "h " + v;
    std::string mark;
    if (verdict == "n/a")
        mark = v.empty() ? "n/a" : "(n/a)";
    else if (role == "claimed")
        mark = verdict == "holds" ? "✓" : "✗ **FAILS**";
    else // control
        mark = verdict == "holds"
                   ? (c.value("agrees", true) ? "✓ (unclaimed)" : "✓ **(control passes)**")
                   : "✗ (control)";
    return v.empty() ? mark : v + " " + mark;
}

} // namespace
} // namespace matrix_detail

namespace {
using json = nlohmann::json;
} // namespace

std::string render_matrix_markdown(const json& matrix) {
    std::ostringstream md;
    md << "| method | order | claims |";
    for (const auto& p : matrix["properties"])
        md << " " << md_cell(p["header"].get<std::string>()) << " |";
    md << "\n|---|---|---|";
    for (std::size_t i = 0; i < matrix["properties"].size(); ++i) md << "---|";
    md << "\n";
    for (const auto& m : matrix["methods"]) {
        std::string claims;
        for (const auto& w : m["claims"])
            claims += (claims.empty() ? "" : ", ") + w.get<std::string>();
        md << "| " << md_cell(m["id"].get<std::string>())
           << (m["built_in"].get<bool>() ? "" : " (loaded)") << " | " << m["order"].get<int>()
           << " | " << md_cell(claims.empty() ? "none" : claims) << " |";
        for (const auto& p : matrix["properties"]) {
            const std::string pid = p["id"];
            md << " " << md_cell(matrix_detail::cell_text(pid, m["cells"][pid])) << " |";
        }
        md << "\n";
    }
    md << "\n✓ claimed and holds; ✗ **FAILS** claimed and fails; ✗ (control) not claimed and "
          "fails (a negative control); ✓ (unclaimed) not claimed but holds (allowed where the "
          "controls need not fail); ✓ **(control passes)** a negative control that holds where "
          "it must fail; n/a the method does not run on the problem or has no closed form. "
          "Criteria:\n\n";
    for (const auto& p : matrix["properties"]) {
        md << "- **" << p["header"].get<std::string>() << "**: " << p["title"].get<std::string>()
           << "; holds iff " << p["criterion"].get<std::string>() << " ("
           << p["source"].get<std::string>() << ")"
           << (p["controls_must_fail"].get<bool>() ? "; negative controls must fail" : "") << ".\n";
    }
    const json& s = matrix["summary"];
    md << "\n"
       << s["methods"].get<int>() << " methods: " << s["claimed_holds"].get<int>()
       << " claimed properties hold, " << s["claimed_failures"].get<int>() << " fail; "
       << s["controls"].get<int>() << " negative-control cells, "
       << s["controls_passing"].get<int>() << " passing where they must fail.\n";
    return md.str();
}

} // namespace dampsym
