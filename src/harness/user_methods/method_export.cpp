// Export of a built-in method as a method file (method_export.hpp, docs/method-files.md).
#include "harness/user_methods/method_export.hpp"

#include "core/method.hpp"
#include "harness/case/case.hpp"
#include "methods/coefficient_checks.hpp"
#include "methods/exponential_tableaux.hpp"
#include "methods/glm_coefficients.hpp"

#include <cstddef>

namespace dampsym {
namespace {

using json = nlohmann::json;

json vec(const std::vector<double>& v) {
    return json(v); // nlohmann writes the shortest decimal that reads back to the same double
}

json rows(const std::vector<double>& a, int n_rows, int n_cols) {
    json out = json::array();
    for (int i = 0; i < n_rows; ++i) {
        const auto first = a.begin() + static_cast<std::ptrdiff_t>(i * n_cols);
        out.push_back(vec(std::vector<double>(first, first + n_cols)));
    }
    return out;
}

json tableau(const ButcherTableau& t) {
    return {{"A", rows(t.a, t.stages, t.stages)}, {"b", vec(t.b)}, {"c", vec(t.c)}};
}

json mat(const Mat& m) {
    json out = json::array();
    for (int i = 0; i < m.rows(); ++i) {
        json row = json::array();
        for (int j = 0; j < m.cols(); ++j) row.push_back(m(i, j));
        out.push_back(row);
    }
    return out;
}

json vec(const Vec& v) {
    json out = json::array();
    for (int i = 0; i < v.size(); ++i) out.push_back(v[i]);
    return out;
}

json glm(const GlmCoefficients& g) {
    json j = {{"A", mat(g.A)}, {"U", mat(g.U)}, {"B", mat(g.B)}, {"V", mat(g.V)}, {"c", vec(g.c)}};
    if (g.G.size() > 0) {
        j["G"] = mat(g.G);
        j["D"] = mat(g.D);
    }
    json st = {{"V", vec(g.V0)}};
    if (g.s0 > 0) {
        st["A"] = mat(g.A0);
        st["U"] = vec(g.U0);
        st["B"] = mat(g.B0);
        st["c"] = vec(g.c0);
    }
    j["starting"] = st;
    return j;
}

// The exponential rows as the φ-vocabulary writes them, each term with the built-in's own
// operations (exponential_tableaux.cpp): coef·exp(arg·x), coef·exprel(arg·x) ("phi1"), and
// etdrk2's a_11 = sinh(x/2)/x = ½ sinhc(x/2) ("sinhc", B(2.13)), where ½·(2·s) and 2·(½x) are
// exact, so every coefficient is the same double as the built-in's. PERK rows in B's x_B (as B
// prints them).
const char* const etdrk2_json = R"({"tableau": {
  "c": [0.5], "A": [[{"coef": 0.5, "phi": "sinhc", "arg": 0.5}]],
  "phi": [{"phi": "exp", "arg": -0.5}], "b": [{"phi": "phi1", "arg": -1}],
  "phi0": {"phi": "exp", "arg": -1}}})";
const char* const se_hat = R"({"c": [0], "A": [[0]], "phi": [1], "b": [1], "phi0": 1})";
const char* const lobatto_hat =
    R"({"c": [0, 1], "A": [[0, 0], [0.5, 0.5]], "phi": [1, 1], "b": [0.5, 0.5], "phi0": 1})";
const char* const cse_if_p = R"({"c": [1], "A": [[1]], "phi": [{"phi": "exp", "arg": -1}],
  "b": [1], "phi0": {"phi": "exp", "arg": -1}})";
const char* const cse_etd_p = R"({"c": [1], "A": [[{"phi": "phi1", "arg": -1}]],
  "phi": [{"phi": "exp", "arg": -1}], "b": [{"phi": "phi1", "arg": -1}],
  "phi0": {"phi": "exp", "arg": -1}})";
const char* const csv1_perk_p = R"({"c": [0.5, 0.5], "A": [[0.5, 0], [0.5, 0]],
  "phi": [{"phi": "exp", "arg": -0.5}, {"phi": "exp", "arg": -0.5}],
  "b": [{"coef": 0.5, "phi": "exp", "arg": -0.5}, {"coef": 0.5, "phi": "exp", "arg": -0.5}],
  "phi0": {"phi": "exp", "arg": -1}})";
const char* const etdprk2_p = R"({"c": [0.5, 0.5],
  "A": [[{"coef": 0.5, "phi": "phi1", "arg": -0.5}, 0], [{"coef": 0.5, "phi": "phi1", "arg": -0.5}, 0]],
  "phi": [{"phi": "exp", "arg": -0.5}, {"phi": "exp", "arg": -0.5}],
  "b": [{"coef": 0.5, "phi": "exp", "arg": -0.5}, {"coef": 0.5, "phi": "exp", "arg": -0.5}],
  "phi0": {"phi": "exp", "arg": -1}})";

json perk(const char* q, const char* p) {
    return {{"q", json::parse(q)}, {"p", json::parse(p)}};
}

// The family and coefficient keys of a built-in row; null if it has no exportable coefficients.
json coefficients(const MethodInfo& m) {
    if (const ButcherTableau* t = plain_tableau(m))
        return {{"family", "rk"}, {"tableau", tableau(*t)}};
    if (const auto* f = method_data<IntegratingFactorTableau>(m))
        return {{"family", "rk"}, {"integrating_factor", true}, {"tableau", tableau(*f->tableau)}};
    if (const auto* p = method_data<PartitionedTableau>(m))
        return {{"family", "partitioned-rk"}, {"q", tableau(*p->q)}, {"p", tableau(*p->p)}};
    if (const auto* g = method_data<GeneralLinearCoefficients>(m)) {
        json j = glm(*g->glm);
        j["family"] = "general-linear";
        return j;
    }
    if (const auto* e = method_data<ExponentialCoefficients>(m); e && e->data == &etdrk2_data()) {
        json j = json::parse(etdrk2_json);
        j["family"] = "exponential-rk";
        return j;
    }
    const auto* pe = method_data<PartitionedExponentialCoefficients>(m);
    json j;
    if (pe && pe->data == &cse_if_data()) j = perk(se_hat, cse_if_p);
    if (pe && pe->data == &cse_etd_data()) j = perk(se_hat, cse_etd_p);
    if (pe && pe->data == &csv1_perk_data()) j = perk(lobatto_hat, csv1_perk_p);
    if (pe && pe->data == &etdprk2_data()) j = perk(lobatto_hat, etdprk2_p);
    if (!j.is_null()) j["family"] = "partitioned-exponential-rk";
    return j;
}

const MethodInfo* builtin(std::string_view id) {
    for (const auto& m : method_catalog())
        if (m.id == id) return &m;
    return nullptr;
}

} // namespace

json export_method_file(std::string_view id, const std::string& new_id) {
    const MethodInfo* m = builtin(id);
    if (m == nullptr)
        throw InputError("--export: '" + std::string(id) +
                         "' is not a built-in method (dampsym methods lists them)");
    json coef = coefficients(*m);
    if (coef.is_null())
        throw InputError("--export: '" + std::string(id) +
                         "' has no coefficients a method file can hold bit for bit (a "
                         "hand-written scheme, a family without method files, or csv2-perk's "
                         "Cayley factors of B(2.21))");
    if (!valid_case_id(new_id))
        throw InputError("--as: '" + new_id +
                         "' is not a valid method id (1 to 100 characters of A-Z a-z 0-9 . _ -, "
                         "starting with a letter or digit)");
    if (builtin(new_id) != nullptr)
        throw InputError("--as: '" + new_id +
                         "' is a built-in method; a method file needs its own id");
    json j = {{"id", new_id},
              {"order", m->order},
              {"claims", claim_words(m->claims)},
              {"citation",
               "export of the built-in " + std::string(id) + ": " + std::string(m->citation)}};
    if (!m->implicit) j["explicit"] = true;
    j.update(coef);
    return j;
}

} // namespace dampsym
