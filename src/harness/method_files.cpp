// Method files: parsing, validation and the run-time method registry (method_files.hpp,
// docs/method-files.md).
#include "harness/method_files.hpp"

#include "harness/case.hpp"
#include "methods/coefficient_expr.hpp"
#include "methods/exponential_conditions.hpp"
#include "methods/exponential_tableaux.hpp"
#include "methods/glm_coefficients.hpp"
#include "methods/runtime_methods.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <utility>

namespace dampsym {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

constexpr int max_stages = 16;               // stages (and GLM values) of a file method
constexpr int max_order = 12;                // declared order
constexpr std::size_t max_perk_methods = 64; // see perk_slot below

[[noreturn]] void bad(const std::string& file, const std::string& key, const std::string& what) {
    throw InputError(file + ": " + key + ": " + what);
}

std::string show(const json& v) {
    std::string s = v.dump();
    return s.size() > 60 ? s.substr(0, 60) + "..." : s;
}

// ---- exponential coefficient functions: Σ_k coef_k φ_k(arg_k x) ----

enum class Phi { none, exp, phi1, phi2, phi3 };

// φ_k(z) = Σ_{n≥0} z^n/(n+k)! for |z| < 1 (25 terms: the remainder is below 1/25! < 1e-25
// relative), else by the recurrence φ_{k+1}(z) = (φ_k(z) − 1/k!)/z from φ_1 = exprel.
double phi_k(int k, double z) {
    if (std::abs(z) < 1.0) {
        double fact = 1.0; // k!
        for (int i = 2; i <= k; ++i) fact *= i;
        double term = 1.0 / fact, sum = 0.0;
        for (int n = 0; n < 25; ++n) {
            sum += term;
            term *= z / static_cast<double>(n + k + 1);
        }
        return sum;
    }
    double v = exprel(z); // φ_1
    double inv_fact = 1.0;
    for (int j = 1; j < k; ++j) {
        v = (v - inv_fact) / z; // φ_{j+1} = (φ_j − 1/j!)/z
        inv_fact /= static_cast<double>(j + 1);
    }
    return v;
}

struct ExpTerm {
    double coef = 1.0;
    Phi phi = Phi::none;
    double arg = 1.0;
    double operator()(double x) const {
        switch (phi) {
        case Phi::none:
            return coef;
        case Phi::exp:
            return coef * std::exp(arg * x);
        case Phi::phi1:
            return coef * exprel(arg * x); // the same function as the built-in rows
        case Phi::phi2:
            return coef * phi_k(2, arg * x);
        case Phi::phi3:
            return coef * phi_k(3, arg * x);
        }
        return coef;
    }
};

struct ExpFn {
    std::vector<ExpTerm> terms;
    double operator()(double x) const {
        double s = terms.front()(x);
        for (std::size_t k = 1; k < terms.size(); ++k) s += terms[k](x);
        return s;
    }
    bool structurally_zero() const {
        return std::all_of(terms.begin(), terms.end(),
                           [](const ExpTerm& t) { return t.coef == 0.0; });
    }
};

struct ExpTableauFns {
    int s = 0;
    std::vector<ExpFn> A, b, phi; // A row-major s×s
    std::vector<double> c;
    ExpFn phi0;
    void eval(double x, ExponentialTableau& t) const {
        for (int i = 0; i < s; ++i) {
            const auto ui = static_cast<std::size_t>(i);
            t.c[i] = c[ui];
            t.phi[i] = phi[ui](x);
            t.b[i] = b[ui](x);
            for (int j = 0; j < s; ++j)
                t.A(i, j) = A[ui * static_cast<std::size_t>(s) + static_cast<std::size_t>(j)](x);
        }
        t.phi0 = phi0(x);
    }
    bool nonzero(int i, int j) const {
        return !A[static_cast<std::size_t>(i * s + j)].structurally_zero();
    }
};

struct LoadedErk {
    ExponentialRKData data;
    ExpTableauFns fns;
};
struct LoadedPerk {
    PartitionedExponentialRKData data;
    ExpTableauFns q, p;
};

// A method as parsed from a file, before it is registered.
struct Parsed {
    std::string id, citation, family;
    int order = 0;
    unsigned claims = 0;
    bool implicit = false;
    Form form = Form::plain;
    bool integrating_factor = false;
    std::optional<ButcherTableau> t1, t2; // rk: t1; partitioned-rk: t1 = q, t2 = p
    std::optional<ExpTableauFns> e1, e2;  // exponential-rk: e1; partitioned: e1 = q, e2 = p
    std::optional<GlmCoefficients> glm;
};

struct Registry {
    std::deque<std::string> strings;
    std::deque<ButcherTableau> tableaux;
    std::deque<LoadedErk> erks;
    std::deque<LoadedPerk> perks;
    std::deque<GlmCoefficients> glms;
    std::deque<MethodInfo> rows;
    std::map<std::string, std::string, std::less<>> file_of;      // id -> file
    std::map<std::string, std::vector<std::string>> loaded_files; // canonical path -> ids
};

Registry& registry() {
    static Registry r;
    return r;
}

std::string_view keep(std::string s) {
    return registry().strings.emplace_back(std::move(s));
}

// ERK coefficient function of a loaded row: the data is found by its address.
void loaded_erk_coefficients(const ExponentialRKData& self, double x, ExponentialTableau& out) {
    for (const LoadedErk& e : registry().erks)
        if (&e.data == &self) return e.fns.eval(x, out);
}

// PERK coefficient functions take no data argument (exponential_tableaux.hpp), so each loaded
// PERK row gets one of max_perk_methods fixed functions, slot K evaluating the K-th loaded row.
template <std::size_t K>
void perk_slot(double x_B, ExponentialTableau& q, ExponentialTableau& p) {
    const LoadedPerk& m = registry().perks[K];
    m.q.eval(x_B, q);
    m.p.eval(x_B, p);
}
using PerkFn = void (*)(double, ExponentialTableau&, ExponentialTableau&);
template <std::size_t... K>
constexpr std::array<PerkFn, sizeof...(K)> make_perk_slots(std::index_sequence<K...>) {
    return {&perk_slot<K>...};
}
constexpr auto perk_slots = make_perk_slots(std::make_index_sequence<max_perk_methods>{});

// ---- reading values ----

class Reader {
public:
    explicit Reader(std::string file) : file_(std::move(file)) {}
    const std::string& file() const { return file_; }

    void only(const json& obj, const std::set<std::string>& allowed, const std::string& prefix) {
        for (auto it = obj.begin(); it != obj.end(); ++it)
            if (!allowed.count(it.key())) {
                std::string list;
                for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
                bad(file_, prefix + it.key(), "unknown key (allowed here: " + list + ")");
            }
    }
    const json& need(const json& obj, const std::string& k, const std::string& prefix) {
        if (!obj.contains(k)) bad(file_, prefix + k, "missing required key");
        return obj[k];
    }
    // A coefficient: a JSON number or an exact expression string (coefficient_expr.hpp).
    double coefficient(const json& v, const std::string& key) {
        double x = 0.0;
        if (v.is_number()) {
            x = v.get<double>();
        } else if (v.is_string()) {
            try {
                x = static_cast<double>(evaluate_coefficient_expr(v.get<std::string>()));
            } catch (const CoefficientExprError& e) {
                bad(file_, key, e.what());
            }
        } else {
            bad(file_, key, "must be a number or an expression string, got " + show(v));
        }
        if (!std::isfinite(x)) bad(file_, key, "is not a finite number (NaN or infinite)");
        return x;
    }
    std::vector<double> vector(const json& v, const std::string& key, int n) {
        if (!v.is_array()) bad(file_, key, "must be an array of coefficients, got " + show(v));
        if (n >= 0 && v.size() != static_cast<std::size_t>(n))
            bad(file_, key,
                "has " + std::to_string(v.size()) + " entries, expected " + std::to_string(n));
        std::vector<double> out;
        for (std::size_t i = 0; i < v.size(); ++i)
            out.push_back(coefficient(v[i], key + "[" + std::to_string(i) + "]"));
        return out;
    }
    // rows×cols matrix as an array of rows (rows < 0: any number of rows, at most max_stages).
    std::vector<std::vector<double>> matrix(const json& v, const std::string& key, int rows,
                                            int cols, const char* shape) {
        if (!v.is_array()) bad(file_, key, "must be an array of rows, got " + show(v));
        if (rows >= 0 && v.size() != static_cast<std::size_t>(rows))
            bad(file_, key,
                "has " + std::to_string(v.size()) + " rows, expected " + std::to_string(rows) +
                    " (" + shape + ")");
        std::vector<std::vector<double>> out;
        for (std::size_t i = 0; i < v.size(); ++i) {
            const std::string ki = key + "[" + std::to_string(i) + "]";
            if (!v[i].is_array()) bad(file_, ki, "must be an array (a row), got " + show(v[i]));
            if (v[i].size() != static_cast<std::size_t>(cols))
                bad(file_, ki,
                    "has " + std::to_string(v[i].size()) + " entries, expected " +
                        std::to_string(cols) + " (" + shape + ")");
            out.push_back(vector(v[i], ki, cols));
        }
        return out;
    }
    // Butcher tableau {"A": s×s, "b": s, "c": s}.
    ButcherTableau tableau(const json& v, const std::string& key) {
        if (!v.is_object()) bad(file_, key, "must be an object {\"A\", \"b\", \"c\"}");
        const std::string p = key + ".";
        only(v, {"A", "b", "c"}, p);
        const json& A = need(v, "A", p);
        if (!A.is_array() || A.empty()) bad(file_, p + "A", "must be a non-empty array of rows");
        const int s = static_cast<int>(A.size());
        if (s > max_stages)
            bad(file_, p + "A",
                std::to_string(s) + " stages (at most " + std::to_string(max_stages) + ")");
        const auto rows = matrix(A, p + "A", s, s, "A must be square, s×s");
        ButcherTableau t{
            s, {}, vector(need(v, "b", p), p + "b", s), vector(need(v, "c", p), p + "c", s)};
        for (const auto& r : rows) t.a.insert(t.a.end(), r.begin(), r.end());
        return t;
    }
    // One exponential coefficient: a constant, a term {"coef", "phi", "arg"} = coef·φ(arg·x), or a
    // non-empty array of them (their sum).
    ExpFn exp_fn(const json& v, const std::string& key) {
        ExpFn f;
        if (v.is_array()) {
            if (v.empty()) bad(file_, key, "an empty sum (give at least one term)");
            if (v.size() > 16) bad(file_, key, "more than 16 terms");
            for (std::size_t i = 0; i < v.size(); ++i)
                f.terms.push_back(exp_term(v[i], key + "[" + std::to_string(i) + "]"));
        } else {
            f.terms.push_back(exp_term(v, key));
        }
        return f;
    }
    ExpTerm exp_term(const json& v, const std::string& key) {
        ExpTerm t;
        if (!v.is_object()) {
            t.coef = coefficient(v, key);
            return t;
        }
        only(v, {"coef", "phi", "arg"}, key + ".");
        if (v.contains("coef")) t.coef = coefficient(v["coef"], key + ".coef");
        if (v.contains("arg")) t.arg = coefficient(v["arg"], key + ".arg");
        const json& ph = need(v, "phi", key + ".");
        static const std::pair<const char*, Phi> vocabulary[] = {{"exp", Phi::exp},
                                                                 {"phi0", Phi::exp},
                                                                 {"phi1", Phi::phi1},
                                                                 {"phi2", Phi::phi2},
                                                                 {"phi3", Phi::phi3}};
        if (ph.is_string())
            for (const auto& [name, phi] : vocabulary)
                if (ph.get<std::string>() == name) t.phi = phi;
        if (t.phi == Phi::none)
            bad(file_, key + ".phi",
                "unknown φ-function " + show(ph) +
                    " (known: \"exp\" = \"phi0\" e^z, \"phi1\" (e^z-1)/z, \"phi2\" "
                    "(e^z-1-z)/z^2, \"phi3\" (e^z-1-z-z^2/2)/z^3)");
        return t;
    }
    // Exponential tableau B(2.10) {"c", "A", "phi", "b", "phi0"}.
    ExpTableauFns exp_tableau(const json& v, const std::string& key) {
        if (!v.is_object())
            bad(file_, key, "must be an object {\"c\", \"A\", \"phi\", \"b\", \"phi0\"}");
        const std::string p = key + ".";
        only(v, {"A", "b", "c", "phi", "phi0"}, p);
        const json& A = need(v, "A", p);
        if (!A.is_array() || A.empty()) bad(file_, p + "A", "must be a non-empty array of rows");
        ExpTableauFns t;
        t.s = static_cast<int>(A.size());
        if (t.s > max_stages)
            bad(file_, p + "A",
                std::to_string(t.s) + " stages (at most " + std::to_string(max_stages) + ")");
        const auto n = static_cast<std::size_t>(t.s);
        for (std::size_t i = 0; i < n; ++i) {
            const std::string ki = p + "A[" + std::to_string(i) + "]";
            if (!A[i].is_array() || A[i].size() != n)
                bad(file_, ki,
                    "must be a row of " + std::to_string(n) + " entries (A must be square, s×s)");
            for (std::size_t j = 0; j < n; ++j)
                t.A.push_back(exp_fn(A[i][j], ki + "[" + std::to_string(j) + "]"));
        }
        auto list = [&](const char* k, std::vector<ExpFn>& out) {
            const json& a = need(v, k, p);
            if (!a.is_array() || a.size() != n)
                bad(file_, p + k,
                    "must be an array of " + std::to_string(n) + " entries (one per stage)");
            for (std::size_t i = 0; i < n; ++i)
                out.push_back(exp_fn(a[i], p + k + "[" + std::to_string(i) + "]"));
        };
        list("b", t.b);
        list("phi", t.phi);
        t.c = vector(need(v, "c", p), p + "c", t.s);
        t.phi0 = exp_fn(need(v, "phi0", p), p + "phi0");
        return t;
    }
    Mat mat(const json& v, const std::string& key, int rows, int cols, const char* shape) {
        const auto m = matrix(v, key, rows, cols, shape);
        Mat out(rows, cols);
        for (int i = 0; i < rows; ++i)
            for (int j = 0; j < cols; ++j)
                out(i, j) = m[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
        return out;
    }
    Vec vec(const json& v, const std::string& key, int n) {
        const auto x = vector(v, key, n);
        Vec out(n);
        for (int i = 0; i < n; ++i) out[i] = x[static_cast<std::size_t>(i)];
        return out;
    }

private:
    std::string file_;
};

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

Parsed parse_method(const json& j, Reader& r) {
    const std::string& file = r.file();
    if (!j.is_object()) bad(file, "(top level)", "a method file must be a JSON object");
    Parsed m;
    const json& fam = r.need(j, "family", "");
    static const std::map<std::string, std::set<std::string>> family_keys{
        {"rk", {"tableau", "integrating_factor"}},
        {"partitioned-rk", {"q", "p"}},
        {"exponential-rk", {"tableau"}},
        {"partitioned-exponential-rk", {"q", "p"}},
        {"general-linear", {"A", "U", "B", "V", "c", "G", "D", "starting"}}};
    if (!fam.is_string() || !family_keys.count(fam.get<std::string>()))
        bad(file, "family",
            "unknown family " + show(fam) +
                " (known: rk, partitioned-rk, exponential-rk, partitioned-exponential-rk, "
                "general-linear)");
    m.family = fam.get<std::string>();
    std::set<std::string> allowed = common_keys;
    allowed.insert(family_keys.at(m.family).begin(), family_keys.at(m.family).end());
    r.only(j, allowed, "");

    // id: valid, not a built-in, not loaded from another file.
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
    if (const auto it = registry().file_of.find(m.id); it != registry().file_of.end())
        bad(file, "id", "duplicate id: '" + m.id + "' is also defined in " + it->second);

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
    // Declared explicit: a tableau's A must be strictly lower triangular.
    auto check_explicit = [&](const std::string& key, int s,
                              const std::function<bool(int, int)>& nz) {
        if (declared_explicit == true) {
            const std::string e = first_upper_entry(s, nz);
            if (!e.empty())
                bad(file, key + "." + e,
                    "the method is declared \"explicit\": true but A is not strictly lower "
                    "triangular (this entry is on or above the diagonal)");
        }
    };

    if (m.family == "rk") {
        m.t1 = r.tableau(r.need(j, "tableau", ""), "tableau");
        if (j.contains("integrating_factor")) {
            if (!j["integrating_factor"].is_boolean())
                bad(file, "integrating_factor", "must be true or false");
            m.integrating_factor = j["integrating_factor"].get<bool>();
        }
        const ButcherTableau& t = *m.t1;
        check_explicit("tableau", t.stages, [&](int i, int k) { return t.A(i, k) != 0.0; });
        m.implicit = !strictly_lower(t);
        m.form = m.integrating_factor ? Form::conformal : Form::plain;
    } else if (m.family == "partitioned-rk") {
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
    } else if (m.family == "exponential-rk") {
        m.e1 = r.exp_tableau(r.need(j, "tableau", ""), "tableau");
        const ExpTableauFns& t = *m.e1;
        check_explicit("tableau", t.s, [&](int i, int k) { return t.nonzero(i, k); });
        m.implicit = !first_upper_entry(t.s, [&](int i, int k) { return t.nonzero(i, k); }).empty();
        m.form = Form::conformal;
    } else if (m.family == "partitioned-exponential-rk") {
        m.e1 = r.exp_tableau(r.need(j, "q", ""), "q");
        m.e2 = r.exp_tableau(r.need(j, "p", ""), "p");
        if (m.e2->s != m.e1->s)
            bad(file, "p.A",
                std::to_string(m.e2->s) + " stages, but the q tableau has " +
                    std::to_string(m.e1->s) + " (both tableaux have the same stages)");
        const ExpTableauFns &q = *m.e1, &p = *m.e2;
        m.implicit = !partitioned_explicit(
            q.s, [&](int i, int k) { return q.nonzero(i, k); },
            [&](int i, int k) { return p.nonzero(i, k); });
        if (declared_explicit == true && m.implicit)
            bad(file, "q.A",
                "the method is declared \"explicit\": true but its stages cannot be computed one "
                "after the other (the dependencies of q.A and p.A form a cycle)");
        if (registry().perks.size() >= max_perk_methods)
            bad(file, "family",
                "at most " + std::to_string(max_perk_methods) +
                    " partitioned exponential methods can be loaded in one run");
        m.form = Form::separable;
    } else { // general-linear
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
        // Starting method [A0 U0; B0 V0]: s0 stages, one input value.
        if (!j.contains("starting") && g.r > 1)
            bad(file, "starting",
                "missing required key: a method with r = " + std::to_string(g.r) +
                    " values needs a starting method {\"A\", \"U\", \"B\", \"V\", \"c\"}");
        if (j.contains("starting")) {
            const json& st = j["starting"];
            if (!st.is_object()) bad(file, "starting", "must be an object");
            r.only(st, {"A", "U", "B", "V", "c"}, "starting.");
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
                        bad(file, std::string("starting.") + k,
                            "given without starting.A (s0 = 0)");
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
        check_explicit("A", g.s, [&](int i, int k) { return g.A(i, k) != 0.0; });
        bool lower = true;
        for (int i = 0; i < g.s; ++i)
            for (int k = i; k < g.s; ++k)
                if (g.A(i, k) != 0.0) lower = false;
        m.implicit = !lower;
        m.form = Form::plain;
        m.glm = std::move(g);
    }
    return m;
}

// Registers a parsed method (storage first, then the row pointing into it).
void commit(Parsed& m, const std::string& file) {
    Registry& reg = registry();
    const std::string_view id = keep(m.id);
    const std::string_view citation = keep(m.citation);
    MethodData data = RungeKuttaTableau{nullptr};
    if (m.family == "rk") {
        const ButcherTableau* t = &reg.tableaux.emplace_back(std::move(*m.t1));
        if (m.integrating_factor)
            data = IntegratingFactorTableau{t};
        else
            data = RungeKuttaTableau{t};
    } else if (m.family == "partitioned-rk") {
        const ButcherTableau* q = &reg.tableaux.emplace_back(std::move(*m.t1));
        const ButcherTableau* p = &reg.tableaux.emplace_back(std::move(*m.t2));
        data = PartitionedTableau{q, p};
    } else if (m.family == "exponential-rk") {
        LoadedErk& e = reg.erks.emplace_back();
        e.fns = std::move(*m.e1);
        e.data = ExponentialRKData{id, citation, "file", e.fns.s, nullptr, loaded_erk_coefficients};
        data = ExponentialCoefficients{&e.data};
    } else if (m.family == "partitioned-exponential-rk") {
        const std::size_t slot = reg.perks.size();
        LoadedPerk& e = reg.perks.emplace_back();
        e.q = std::move(*m.e1);
        e.p = std::move(*m.e2);
        e.data = PartitionedExponentialRKData{id, citation, "file", e.q.s, perk_slots[slot]};
        data = PartitionedExponentialCoefficients{&e.data};
    } else {
        GlmCoefficients& g = reg.glms.emplace_back(std::move(*m.glm));
        g.name = id;
        g.citation = citation;
        data = GeneralLinearCoefficients{&g};
    }
    reg.rows.push_back(MethodInfo{id, m.order, m.implicit, m.form, m.claims, citation, data});
    reg.file_of.emplace(m.id, file);
}

} // namespace

const MethodInfo* find_loaded_method(std::string_view id) {
    for (const MethodInfo& m : registry().rows)
        if (m.id == id) return &m;
    return nullptr;
}

std::vector<const MethodInfo*> loaded_methods() {
    std::vector<const MethodInfo*> out;
    for (const MethodInfo& m : registry().rows) out.push_back(&m);
    return out;
}

std::vector<const MethodInfo*> load_method_file(const std::string& path) {
    std::error_code ec;
    const fs::path canonical = fs::weakly_canonical(path, ec);
    const std::string key = ec ? path : canonical.string();
    Registry& reg = registry();
    if (!reg.loaded_files.count(key)) {
        const json j = read_case_json(path); // regular file, bounded size, depth, duplicate keys
        Reader r(path);
        std::vector<Parsed> parsed;
        parsed.push_back(parse_method(j, r)); // every method validated before any is registered
        std::vector<std::string> ids;
        for (auto& m : parsed) {
            ids.push_back(m.id);
            commit(m, fs::path(path).lexically_normal().string());
        }
        reg.loaded_files[key] = std::move(ids);
    }
    std::vector<const MethodInfo*> out;
    for (const auto& id : reg.loaded_files[key]) out.push_back(find_loaded_method(id));
    return out;
}

std::string check_method_text(const std::string& text, const std::string& file) {
    const json j = parse_json_checked(text, file); // as read_case_json after reading the file
    Reader r(file);
    return parse_method(j, r).id;
}

void load_method_folder(const std::string& dir) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) return;
    std::vector<std::string> paths;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().extension() == ".json") paths.push_back(e.path().string());
    std::sort(paths.begin(), paths.end());
    for (const auto& p : paths) load_method_file(p);
}

std::string method_file_of(std::string_view id) {
    const auto it = registry().file_of.find(id);
    return it == registry().file_of.end() ? std::string() : it->second;
}

std::string method_folder_beside(const std::string& cases_dir) {
    fs::path p(cases_dir);
    if (!p.has_filename()) p = p.parent_path(); // "verify/cases/"
    return (p.parent_path() / "methods").string();
}

std::vector<CoefficientCheck> method_file_checks(const MethodInfo& info) {
    std::vector<CoefficientCheck> out = method_checks(info);
    const bool claimed = (info.claims & claim_conformal_symplectic) != 0;
    const double tol = coefficient_tolerance;
    // Damping arguments γh (our γ) at which the exponential conditions are evaluated.
    const double args[] = {0.01, 0.1, 0.5};
    if (const auto* e = method_data<ExponentialCoefficients>(info)) {
        double cond = 0.0, phi0 = 0.0;
        for (const double x : args) {
            cond = std::max(cond, erk_condition_residual(*e->data, x));
            phi0 = std::max(phi0, erk_phi0_residual(*e->data, x));
        }
        out.push_back({"conformal-condition",
                       "b_i a_ij φ0/φ_i + b_j a_ji φ0/φ_j − b_i b_j = 0 at γh = 0.01, 0.1, 0.5 "
                       "(B(2.30), B Thm 2.11; sufficient, not necessary)",
                       claimed, cond <= tol, cond, tol});
        if (claimed) // necessary for the claim; silent about a method that does not claim it
            out.push_back(
                {"conformal-factor", "φ0 = e^{−γh} (B(2.31))", true, phi0 <= tol, phi0, tol});
    } else if (const auto* p = method_data<PartitionedExponentialCoefficients>(info)) {
        double cond = 0.0, phi0 = 0.0;
        for (const double x : args) {
            cond = std::max(cond, perk_condition_residual(*p->data, x));
            phi0 = std::max(phi0, perk_phi0_residual(*p->data, x));
        }
        out.push_back({"conformal-condition",
                       "B(2.23) at γh = 0.01, 0.1, 0.5 (B Thm 2.4, 2.10; sufficient, not "
                       "necessary: cse-etd and csv2 violate it and are conformal symplectic)",
                       claimed, cond <= tol, cond, tol});
        if (claimed) // necessary for the claim; silent about a method that does not claim it
            out.push_back({"conformal-factor", "φ̂0 φ̃0 = e^{−2γh} (B Thm 2.10)", true, phi0 <= tol,
                           phi0, tol});
    }
    return out;
}

} // namespace dampsym
