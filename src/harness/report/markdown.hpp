// Text in a cell of a GitHub-flavoured Markdown table (report.md, the compare, matrix and
// step-summary tables). GFM splits a table row at every `|` that is not escaped, before any inline
// parsing (GFM spec §4.10, "Tables": even inside a code span), and a line break ends the row; so a
// `|` in a cell (a check's `|H - H0|`, the energy column `max |H_exact−H|`) becomes `\|` and a line
// break a space. A backslash right before a `|` is doubled, so that the `|` stays escaped and the
// backslash is still shown.
#pragma once

#include <string>

namespace dampsym {

inline std::string md_cell(const std::string& text) {
    std::string out;
    out.reserve(text.size() + 8);
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char ch = text[i];
        if (ch == '|') {
            out += "\\|";
        } else if (ch == '\n' || ch == '\r') {
            out += ' ';
        } else if (ch == '\\' && i + 1 < text.size() && text[i + 1] == '|') {
            out += "\\\\";
        } else {
            out += ch;
        }
    }
    return out;
}

} // namespace dampsym
