// "Did you mean": the known names closest to a mistyped one (a subcommand, a case id, a method id,
// a key), by optimal-string-alignment distance (an edit, an insertion, a deletion or a swap of two
// neighbours each count 1), offered when at most a third of the word (at least 1, at most 3) is
// off.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

namespace dampsym {

inline std::size_t edit_distance(const std::string& a, const std::string& b) {
    const std::size_t n = a.size(), m = b.size();
    std::vector<std::vector<std::size_t>> d(n + 1, std::vector<std::size_t>(m + 1));
    for (std::size_t i = 0; i <= n; ++i) d[i][0] = i;
    for (std::size_t j = 0; j <= m; ++j) d[0][j] = j;
    for (std::size_t i = 1; i <= n; ++i)
        for (std::size_t j = 1; j <= m; ++j) {
            const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
                d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
        }
    return d[n][m];
}

// "did you mean 'run'?" (or "'csv1' or 'csv2'"), or "" when no known name is close.
inline std::string did_you_mean(const std::string& word, const std::vector<std::string>& known) {
    if (word.size() > 200) return ""; // a hostile argument is not compared
    const std::size_t limit = std::clamp<std::size_t>(word.size() / 3, 1, 3);
    std::size_t best = limit + 1;
    std::vector<std::string> names;
    for (const auto& k : known) {
        if (k == word || k.size() > 200) continue;
        const std::size_t dist = edit_distance(word, k);
        if (dist < best) {
            best = dist;
            names.clear();
        }
        if (dist == best && names.size() < 3 &&
            std::find(names.begin(), names.end(), k) == names.end())
            names.push_back(k);
    }
    if (names.empty()) return "";
    std::string out = "did you mean ";
    for (std::size_t i = 0; i < names.size(); ++i)
        out += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + ("'" + names[i] + "'");
    return out + "?";
}

} // namespace dampsym
