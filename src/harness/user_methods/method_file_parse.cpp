// Method files, the parser: a method file's JSON to a Parsed method — the keys common to every
// family (id, order, citation, claims, explicit), then each family's coefficients, and whether the
// method is explicit (docs/method-files.md). Every error is an InputError naming file and key.
#include "harness/user_methods/method_file_reader.hpp"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <utility>

namespace dampsym::method_file {
namespace {

namespace fs = std::filesystem;

bool strictly_lower(const ButcherTableau& t) {
    return is_explicit_tableau(t);
}

// Whether the 2s stages Q_1..Q_s, P_1..P_s of a partitioned pair can be computed one after the
// other: Q_i needs P_j where q_nz(i, j), P_i needs Q_j where p_nz(i, j); explicit iff this
// dependency graph has no cycle.
template <class Qnz, class Pnz>
bool partitioned_explicit(int s, Qnz q_nz, Pnz p_nz) {
    const int n = 2 * s;
    std::vector<int> state(static_cast<std::size_t>(n), 0); // 0 new, 1 on stack, 2 done
    std::function<bool(int)> acyclic = [&](int v) {
        auto& st = state[static_cast<std::size_t>(v)];
        if (st == 1) return false;
        if (st == 2) return true;
        st = 1;
        for (int j = 0; j < s; ++j) {
            const bool edge = v < s ? q_nz(v, j) : p_nz(v - s, j);
            if (edge && !acyclic(v < s ? s + j : j)) return false;
        }
        st = 2;
        return true;
    };
    for (int v = 0; v < n; ++v)
        if (!acyclic(v)) return false;
    return true;
}

std::string first_upper_entry(int s, const std::function<bool(int, int)>& nz) {
    for (int i = 0; i < s; ++i)
        for (int j = i; j < s; ++j)
            if (nz(i, j)) return "A[" + std::to_string(i) + "][" + std::to_string(j) + "]";
    return "";
}

unsigned parse_claims(const json& v, Reader& r) {
    if (!v.is_array()) bad(r.file(), "claims", "must be an array of claim names");
    static const std::pair<const char*, unsigned> names[] = {
        {"conformal-symplectic", claim_conformal_symplectic},
        {"conformal-quadratic", claim_conformal_quadratic},
        {"angular-momentum", claim_angular_momentum},
        {"linear-momentum", claim_linear_momentum},
        {"symplectic-if-undamped", claim_symplectic_if_undamped},
        {"linear-momentum-cayley", claim_linear_momentum_cayley},
        {"g-symplectic", claim_g_symplectic}};
    unsigned claims = 0;
    for (std::size_t i = 0; i < v.size(); ++i) {
        const std::string key = "claims[" + std::to_string(i) + "]";
        unsigned bit = 0;
        if (v[i].is_string())
            for (const auto& [name, b] : names)
                if (v[i].get<std::string>() == name) bit = b;
        if (bit == 0) {
            std::string list;
            for (const auto& [name, b] : names)
                list += (list.empty() ? "" : ", ") + std::string(name);
            bad(r.file(), key, "unknown claim " + show(v[i]) + " (known: " + list + ")");
        }
        claims |= bit;
    }
    return claims;
}

const std::set<std::string> common_keys{"id",     "family",   "order", "citation",
                                        "claims", "explicit", "notes"};

// The reader of one "family" of method files: its coefficient keys and its parser.
struct FileFamily {
    std::set<std::string> keys;
    void (*parse)(const json&, Reader&, Parsed&, std::optional<bool>);
};
using FileFamilies = std::vector<std::pair<std::string, FileFamily>>;
const FileFamilies& file_families(); // below, after the parsers

const FileFamily* file_family(const std::string& name) {
    for (const auto& [n, f] : file_families())
        if (n == name) return &f;
    return nullptr;
}

// "family", and no key outside the common keys and the family's.
void parse_family(const json& j, Reader& r, Parsed& m) {
    const std::string& file = r.file();
    const json& fam = r.need(j, "family", "");
    if (!fam.is_string() || !file_family(fam.get<std::string>())) {
        std::string known;
        for (const auto& [name, f] : file_families()) known += (known.empty() ? "" : ", ") + name;
        bad(file, "family", "unknown family " + show(fam) + " (known: " + known + ")");
    }
    m.family = fam.get<std::string>();
    std::set<std::string> allowed = common_keys;
    const std::set<std::string>& keys = file_family(m.family)->keys;
    allowed.insert(keys.begin(), keys.end());
    r.only(j, allowed, "");
}

// id: valid, not a built-in, not loaded from another file.
void parse_id(const json& j, Reader& r, Parsed& m) {
    const std::string& file = r.file();
    const json& id = r.need(j, "id", "");
    if (!id.is_string() || !valid_case_id(id.get<std::string>()))
        bad(file, "id",
            show(id) + " is not a valid method id (1 to 100 characters of A-Z a-z 0-9 . _ -, "
                       "starting with a letter or digit)");
    m.id = id.get<std::string>();
    for (const auto& b : method_catalog())
        if (b.id == m.id)
            bad(file, "id",
                "'" + m.id +
                    "' is a built-in method; a method file cannot shadow it (choose "
                    "another id)");
    if (const std::string other = file_defining(m.id); !other.empty())
        bad(file, "id", "duplicate id: '" + m.id + "' is also defined in " + other);
}

// order, citation, notes, claims; returns "explicit" (unset if not declared).
std::optional<bool> parse_declarations(const json& j, Reader& r, Parsed& m) {
    const std::string& file = r.file();
    const json& ord = r.need(j, "order", "");
    if (!ord.is_number_integer() || ord.get<std::int64_t>() < 1 ||
        ord.get<std::int64_t>() > max_order)
        bad(file, "order",
            "must be a whole number from 1 to " + std::to_string(max_order) + ", got " + show(ord));
    m.order = ord.get<int>();
    if (j.contains("citation")) {
        if (!j["citation"].is_string()) bad(file, "citation", "must be a string");
        m.citation = j["citation"].get<std::string>();
    }
    if (j.contains("notes") && !j["notes"].is_string()) bad(file, "notes", "must be a string");
    m.citation = "method file " + fs::path(file).filename().string() +
                 (m.citation.empty() ? "" : ": " + m.citation);
    if (j.contains("claims")) m.claims = parse_claims(j["claims"], r);
    std::optional<bool> declared_explicit;
    if (j.contains("explicit")) {
        if (!j["explicit"].is_boolean()) bad(file, "explicit", "must be true or false");
        declared_explicit = j["explicit"].get<bool>();
    }
    return declared_explicit;
}

// Declared explicit: a tableau's A must be strictly lower triangular.
void check_explicit(const std::string& file, std::optional<bool> declared_explicit,
                    const std::string& key, int s, const std::function<bool(int, int)>& nz) {
    if (declared_explicit == true) {
        const std::string e = first_upper_entry(s, nz);
        if (!e.empty())
            bad(file, key + "." + e,
                "the method is declared \"explicit\": true but A is not strictly lower "
                "triangular (this entry is on or above the diagonal)");
    }
}

// family "rk": tableau, integrating_factor.
void parse_rk(const json& j, Reader& r, Parsed& m, std::optional<bool> declared_explicit) {
    const std::string& file = r.file();
    m.t1 = r.tableau(r.need(j, "tableau", ""), "tableau");
    if (j.contains("integrating_factor")) {
        if (!j["integrating_factor"].is_boolean())
            bad(file, "integrating_factor", "must be true or false");
        m.integrating_factor = j["integrating_factor"].get<bool>();
    }
    const ButcherTableau& t = *m.t1;
    check_explicit(file, declared_explicit, "tableau", t.stages,
                   [&](int i, int k) { return t.A(i, k) != 0.0; });
    m.implicit = !strictly_lower(t);
    m.form = m.integrating_factor ? Form::conformal : Form::plain;
}

// family "partitioned-rk": q, p.
void parse_partitioned_rk(const json& j, Reader& r, Parsed& m,
                          std::optional<bool> declared_explicit) {
    const std::string& file = r.file();
    m.t1 = r.tableau(r.need(j, "q", ""), "q");
    m.t2 = r.tableau(r.need(j, "p", ""), "p");
    if (m.t2->stages != m.t1->stages)
        bad(file, "p.A",
            std::to_string(m.t2->stages) + " stages, but the q tableau has " +
                std::to_string(m.t1->stages) + " (both tableaux have the same stages)");
    const ButcherTableau &q = *m.t1, &p = *m.t2;
    m.implicit = !partitioned_explicit(
        q.stages, [&](int i, int k) { return q.A(i, k) != 0.0; },
        [&](int i, int k) { return p.A(i, k) != 0.0; });
    if (declared_explicit == true && m.implicit)
        bad(file, "q.A",
            "the method is declared \"explicit\": true but its stages cannot be computed one "
            "after the other (Q_i needs P_j where q.A[i][j] != 0, P_i needs Q_j where "
            "p.A[i][j] != 0, and these dependencies form a cycle)");
    m.form = Form::separable;
}

// family "exponential-rk": tableau.
void parse_exponential_rk(const json& j, Reader& r, Parsed& m,
                          std::optional<bool> declared_explicit) {
    const std::string& file = r.file();
    m.e1 = r.exp_tableau(r.need(j, "tableau", ""), "tableau");
    const ExpTableauFns& t = *m.e1;
    check_explicit(file, declared_explicit, "tableau", t.s,
                   [&](int i, int k) { return t.nonzero(i, k); });
    m.implicit = !first_upper_entry(t.s, [&](int i, int k) { return t.nonzero(i, k); }).empty();
    m.form = Form::conformal;
}

// family "partitioned-exponential-rk": q, p.
void parse_partitioned_exponential_rk(const json& j, Reader& r, Parsed& m,
                                      std::optional<bool> declared_explicit) {
    const std::string& file = r.file();
    m.e1 = r.exp_tableau(r.need(j, "q", ""), "q");
    m.e2 = r.exp_tableau(r.need(j, "p", ""), "p");
    if (m.e2->s != m.e1->s)
        bad(file, "p.A",
            std::to_string(m.e2->s) + " stages, but the q tableau has " + std::to_string(m.e1->s) +
                " (both tableaux have the same stages)");
    const ExpTableauFns &q = *m.e1, &p = *m.e2;
    m.implicit = !partitioned_explicit(
        q.s, [&](int i, int k) { return q.nonzero(i, k); },
        [&](int i, int k) { return p.nonzero(i, k); });
    if (declared_explicit == true && m.implicit)
        bad(file, "q.A",
            "the method is declared \"explicit\": true but its stages cannot be computed one "
            "after the other (the dependencies of q.A and p.A form a cycle)");
    if (loaded_perk_count() >= max_perk_methods)
        bad(file, "family",
            "at most " + std::to_string(max_perk_methods) +
                " partitioned exponential methods can be loaded in one run");
    m.form = Form::separable;
}

// general-linear: the tableau [A U; B V], c and the certificate G, D (without the starting method).
GlmCoefficients parse_glm_tableau(const json& j, Reader& r) {
    const std::string& file = r.file();
    GlmCoefficients g;
    const json& A = r.need(j, "A", "");
    if (!A.is_array() || A.empty()) bad(file, "A", "must be a non-empty array of rows");
    g.s = static_cast<int>(A.size());
    const json& V = r.need(j, "V", "");
    if (!V.is_array() || V.empty()) bad(file, "V", "must be a non-empty array of rows");
    g.r = static_cast<int>(V.size());
    if (g.s > max_stages || g.r > max_stages)
        bad(file, g.s > max_stages ? "A" : "V",
            "more than " + std::to_string(max_stages) + " stages or values");
    g.A = r.mat(A, "A", g.s, g.s, "A is s×s");
    g.U = r.mat(r.need(j, "U", ""), "U", g.s, g.r, "U is s×r");
    g.B = r.mat(r.need(j, "B", ""), "B", g.r, g.s, "B is r×s");
    g.V = r.mat(V, "V", g.r, g.r, "V is r×r");
    g.c = r.vec(r.need(j, "c", ""), "c", g.s);
    if (j.contains("G") != j.contains("D"))
        bad(file, j.contains("G") ? "D" : "G",
            "missing: the G-symplecticity certificate is the pair G (r×r) and D (s×s)");
    if (j.contains("G")) {
        g.G = r.mat(j["G"], "G", g.r, g.r, "G is r×r");
        g.D = r.mat(j["D"], "D", g.s, g.s, "D is s×s");
    }
    return g;
}

// general-linear: the starting method [A0 U0; B0 V0]: s0 stages, one input value.
void parse_glm_starting(const json& j, Reader& r, GlmCoefficients& g) {
    const std::string& file = r.file();
    if (!j.contains("starting") && g.r > 1)
        bad(file, "starting",
            "missing required key: a method with r = " + std::to_string(g.r) +
                " values needs a starting method {\"A\", \"U\", \"B\", \"V\", \"c\"}");
    if (j.contains("starting")) {
        const json& st = j["starting"];
        if (!st.is_object()) bad(file, "starting", "must be an object");
        r.only(st, {"A", "U", "B", "V", "c"}, "starting.");
        if (st.contains("A") && !st["A"].is_array()) // (was read as s0 = 0 and ignored)
            bad(file, "starting.A", "must be an array of rows (A0 is s0×s0; [] for s0 = 0)");
        g.s0 = st.contains("A") ? static_cast<int>(st["A"].is_array() ? st["A"].size() : 0) : 0;
        if (g.s0 > max_stages) bad(file, "starting.A", "too many stages");
        if (g.s0 > 0) {
            g.A0 = r.mat(st["A"], "starting.A", g.s0, g.s0, "A0 is s0×s0");
            g.U0 = r.vec(r.need(st, "U", "starting."), "starting.U", g.s0);
            g.B0 = r.mat(r.need(st, "B", "starting."), "starting.B", g.r, g.s0, "B0 is r×s0");
            g.c0 = r.vec(r.need(st, "c", "starting."), "starting.c", g.s0);
        } else {
            for (const char* k : {"U", "B", "c"})
                if (st.contains(k))
                    bad(file, std::string("starting.") + k, "given without starting.A (s0 = 0)");
            g.A0 = Mat(0, 0);
            g.U0 = Vec(0);
            g.B0 = Mat(g.r, 0);
            g.c0 = Vec(0);
        }
        g.V0 = r.vec(r.need(st, "V", "starting."), "starting.V", g.r);
    } else {
        g.s0 = 0;
        g.A0 = Mat(0, 0);
        g.U0 = Vec(0);
        g.B0 = Mat(1, 0);
        g.V0 = Vec::Ones(1);
        g.c0 = Vec(0);
    }
}

// family "general-linear": A, U, B, V, c, G, D, starting.
void parse_general_linear(const json& j, Reader& r, Parsed& m,
                          std::optional<bool> declared_explicit) {
    const std::string& file = r.file();
    GlmCoefficients g = parse_glm_tableau(j, r);
    parse_glm_starting(j, r, g);
    check_explicit(file, declared_explicit, "A", g.s,
                   [&](int i, int k) { return g.A(i, k) != 0.0; });
    bool lower = true;
    for (int i = 0; i < g.s; ++i)
        for (int k = i; k < g.s; ++k)
            if (g.A(i, k) != 0.0) lower = false;
    m.implicit = !lower;
    m.form = Form::plain;
    m.glm = std::move(g);
}

// Every family a method file can name (Family<D>::file_family, methods/families.hpp; ctest
// "method files: the reader knows exactly the families whose traits name a file family").
const FileFamilies& file_families() {
    static const FileFamilies table{
        {"rk", {{"tableau", "integrating_factor"}, parse_rk}},
        {"partitioned-rk", {{"q", "p"}, parse_partitioned_rk}},
        {"exponential-rk", {{"tableau"}, parse_exponential_rk}},
        {"partitioned-exponential-rk", {{"q", "p"}, parse_partitioned_exponential_rk}},
        {"general-linear",
         {{"A", "U", "B", "V", "c", "G", "D", "starting"}, parse_general_linear}}};
    return table;
}

} // namespace

Parsed parse_method(const json& j, Reader& r) {
    if (!j.is_object()) bad(r.file(), "(top level)", "a method file must be a JSON object");
    Parsed m;
    parse_family(j, r, m);
    parse_id(j, r, m);
    const std::optional<bool> declared_explicit = parse_declarations(j, r, m);
    file_family(m.family)->parse(j, r, m, declared_explicit);
    return m;
}

std::vector<std::string> known_families() {
    std::vector<std::string> out;
    for (const auto& [name, f] : file_families()) out.push_back(name);
    return out;
}

} // namespace dampsym::method_file
