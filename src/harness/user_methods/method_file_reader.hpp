// Method files, internal: the values a method file is read into (the φ-function coefficient
// functions of the exponential families, the parsed method) and the Reader that reads and validates
// coefficients, vectors, matrices and tableaux, naming file and key in every error
// (docs/method-files.md). Shared by method_file_parse.cpp (the parser) and method_files.cpp (the
// run-time registry); not part of the public interface (method_files.hpp).
#pragma once

#include "harness/case/case.hpp"
#include "methods/coefficient_expr.hpp"
#include "methods/exponential_tableaux.hpp"
#include "methods/glm_coefficients.hpp"
#include "methods/runtime_methods.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace dampsym::method_file {

using json = nlohmann::json;

constexpr int max_stages = 16;               // stages (and GLM values) of a file method
constexpr int max_order = 12;                // declared order
constexpr std::size_t max_perk_methods = 64; // see perk_slot (method_files.cpp)

[[noreturn]] inline void bad(const std::string& file, const std::string& key,
                             const std::string& what) {
    throw InputError(file + ": " + key + ": " + what);
}

inline std::string show(const json& v) {
    std::string s = v.dump();
    return s.size() > 60 ? s.substr(0, 60) + "..." : s;
}

// ---- exponential coefficient functions: Σ_k coef_k φ_k(arg_k x) ----

enum class Phi { none, exp, phi1, phi2, phi3, sinhc };

// φ_k(z) = Σ_{n≥0} z^n/(n+k)! for |z| < 1 (25 terms: the remainder is below 1/25! < 1e-25
// relative), else by the recurrence φ_{k+1}(z) = (φ_k(z) − 1/k!)/z from φ_1 = exprel.
inline double phi_k(int k, double z) {
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
        case Phi::sinhc: // sinh(z)/z = 2 sinh_half_over(2z): B(2.13)'s a_11 = ½ sinhc(x/2)
            return coef * (2.0 * sinh_half_over(2.0 * (arg * x)));
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
        static const std::pair<const char*, Phi> vocabulary[] = {
            {"exp", Phi::exp},   {"phi0", Phi::exp},  {"phi1", Phi::phi1},
            {"phi2", Phi::phi2}, {"phi3", Phi::phi3}, {"sinhc", Phi::sinhc}};
        if (ph.is_string())
            for (const auto& [name, phi] : vocabulary)
                if (ph.get<std::string>() == name) t.phi = phi;
        if (t.phi == Phi::none)
            bad(file_, key + ".phi",
                "unknown φ-function " + show(ph) +
                    " (known: \"exp\" = \"phi0\" e^z, \"phi1\" (e^z-1)/z, \"phi2\" "
                    "(e^z-1-z)/z^2, \"phi3\" (e^z-1-z-z^2/2)/z^3, \"sinhc\" sinh(z)/z)");
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

// The method of a parsed file (method_file_parse.cpp); throws InputError naming file and key.
Parsed parse_method(const json& j, Reader& r);
// The values a method file's "family" may take (each a Family<D>::file_family).
std::vector<std::string> known_families();

// Of the run-time registry (method_files.cpp): the number of loaded partitioned exponential
// methods, and the file a loaded id came from ("" if none).
std::size_t loaded_perk_count();
std::string file_defining(std::string_view id);

} // namespace dampsym::method_file
