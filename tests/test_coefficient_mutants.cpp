// Negative controls of the coefficient-level checks (src/methods/coefficient_checks.hpp,
// exponential_checks.cpp): every built-in method defined by coefficients, with each nonzero
// coefficient in turn multiplied by (1 + 1e-6), is refuted by some check of its family — the same
// checks `dampsym methods --check`, the matrix's coefficient cell and `dampsym run` apply. The
// coefficients no check reads are equivalent mutants, skipped with the reason: the p tableau's
// nodes of a partitioned pair (time is integrated with the q tableau's c, partitioned_rk.hpp) and
// of a PERK pair (c̃ is B's printed column, exponential_tableaux.hpp).
#include "methods/coefficient_checks.hpp"
#include "methods/exponential_tableaux.hpp"
#include "methods/glm_coefficients.hpp"

#include <catch2/catch.hpp>

#include <functional>
#include <string>
#include <type_traits>
#include <vector>

namespace coefficient_mutants { // named: the test files are compiled in unity batches

using dampsym::ButcherTableau;
using dampsym::ExponentialTableau;
using dampsym::MethodInfo;

constexpr double kFactor = 1.0 + 1e-6;

bool refuted(const MethodInfo& m) {
    for (const auto& c : dampsym::method_checks(m))
        if (!c.agrees()) return true;
    return false;
}

// Each nonzero entry of `values`, multiplied in turn: `survives(label)` is called for a mutant no
// check refutes (`mutant` runs the checks on the current copy).
void mutate_each(std::vector<double*> values, const std::string& what,
                 const std::function<bool()>& mutant, std::vector<std::string>& survivors,
                 int& mutants) {
    for (std::size_t k = 0; k < values.size(); ++k) {
        if (*values[k] == 0.0) continue; // unchanged by the factor
        const double saved = *values[k];
        *values[k] *= kFactor;
        ++mutants;
        if (!mutant()) survivors.push_back(what + "[" + std::to_string(k) + "]");
        *values[k] = saved;
    }
}

std::vector<double*> entries(ButcherTableau& t, bool with_c = true) {
    std::vector<double*> out;
    for (auto& v : t.a) out.push_back(&v);
    for (auto& v : t.b) out.push_back(&v);
    if (with_c)
        for (auto& v : t.c) out.push_back(&v);
    return out;
}

std::vector<double*> entries(dampsym::Mat& m) {
    std::vector<double*> out;
    for (Eigen::Index i = 0; i < m.size(); ++i) out.push_back(m.data() + i);
    return out;
}

std::vector<double*> entries(dampsym::Vec& v) {
    std::vector<double*> out;
    for (Eigen::Index i = 0; i < v.size(); ++i) out.push_back(v.data() + i);
    return out;
}

// The exponential families' coefficients are functions of γh: the mutant multiplies the k-th
// scalar of the evaluated tableau (A, b, c, φ, φ_0 of each tableau, in that order) at every γh.
struct ExpMutant {
    const dampsym::ExponentialRKData* erk = nullptr;
    const dampsym::PartitionedExponentialRKData* perk = nullptr;
    int index = -1;
};
ExpMutant g_mutant; // the function-pointer data cannot capture; one mutant at a time

std::vector<double*> scalars(ExponentialTableau& t, bool with_c = true) {
    std::vector<double*> out = entries(t.A);
    for (auto* v : entries(t.b)) out.push_back(v);
    if (with_c)
        for (auto* v : entries(t.c)) out.push_back(v);
    for (auto* v : entries(t.phi)) out.push_back(v);
    out.push_back(&t.phi0);
    return out;
}

void mutated_erk(const dampsym::ExponentialRKData&, double x, ExponentialTableau& out) {
    g_mutant.erk->coefficients(*g_mutant.erk, x, out);
    *scalars(out)[static_cast<std::size_t>(g_mutant.index)] *= kFactor;
}

void mutated_perk(double x_B, ExponentialTableau& q, ExponentialTableau& p) {
    g_mutant.perk->coefficients_B(x_B, q, p);
    std::vector<double*> all = scalars(q);
    for (auto* v : scalars(p, false)) all.push_back(v); // c̃ is not read (see above)
    *all[static_cast<std::size_t>(g_mutant.index)] *= kFactor;
}

} // namespace coefficient_mutants

TEST_CASE("every coefficient of every built-in tableau, perturbed by 1e-6, is refuted by its "
          "family's checks",
          "[coefficients][mutants]") {
    using namespace coefficient_mutants;
    int mutants = 0;
    std::vector<std::string> survivors;
    for (const MethodInfo& m : dampsym::method_catalog()) {
        const std::string id(m.id);
        MethodInfo copy = m;
        auto check = [&] { return refuted(copy); };
        if (const auto* rk = dampsym::method_data<dampsym::RungeKuttaTableau>(m)) {
            ButcherTableau t = *rk->tableau;
            copy.data = dampsym::RungeKuttaTableau{&t};
            mutate_each(entries(t), id, check, survivors, mutants);
        } else if (const auto* ifrk = dampsym::method_data<dampsym::IntegratingFactorTableau>(m)) {
            ButcherTableau t = *ifrk->tableau;
            copy.data = dampsym::IntegratingFactorTableau{&t};
            mutate_each(entries(t), id, check, survivors, mutants);
        } else if (const auto* prk = dampsym::method_data<dampsym::PartitionedTableau>(m)) {
            ButcherTableau q = *prk->q, p = *prk->p;
            copy.data = dampsym::PartitionedTableau{&q, &p};
            mutate_each(entries(q), id + " q", check, survivors, mutants);
            mutate_each(entries(p, false), id + " p", check, survivors, mutants);
        } else if (const auto* glm = dampsym::method_data<dampsym::GeneralLinearCoefficients>(m)) {
            dampsym::GlmCoefficients g = *glm->glm;
            copy.data = dampsym::GeneralLinearCoefficients{&g};
            for (auto [name, mat] : {std::pair{"A", &g.A},
                                     {"U", &g.U},
                                     {"B", &g.B},
                                     {"V", &g.V},
                                     {"A0", &g.A0},
                                     {"B0", &g.B0},
                                     {"G", &g.G},
                                     {"D", &g.D}})
                mutate_each(entries(*mat), id + " " + name, check, survivors, mutants);
            for (auto [name, vec] :
                 {std::pair{"c", &g.c}, {"U0", &g.U0}, {"V0", &g.V0}, {"c0", &g.c0}})
                mutate_each(entries(*vec), id + " " + name, check, survivors, mutants);
        }
    }
    INFO("survivors: " << [&] {
        std::string s;
        for (const auto& x : survivors) s += x + " ";
        return s;
    }());
    CHECK(mutants >= 120); // 126 nonzero coefficients in the catalog today
    CHECK(survivors.empty());
}

TEST_CASE("every coefficient function of every built-in exponential method, perturbed by 1e-6, "
          "is refuted by its family's checks",
          "[coefficients][mutants]") {
    using namespace coefficient_mutants;
    int mutants = 0;
    std::vector<std::string> survivors;
    for (const MethodInfo& m : dampsym::method_catalog()) {
        const std::string id(m.id);
        MethodInfo copy = m;
        if (const auto* e = dampsym::method_data<dampsym::ExponentialCoefficients>(m)) {
            dampsym::ExponentialRKData data = *e->data;
            data.coefficients = mutated_erk;
            copy.data = dampsym::ExponentialCoefficients{&data};
            ExponentialTableau probe;
            dampsym::erk_coefficients(*e->data, 0.3, probe);
            const std::size_t n = scalars(probe).size();
            for (std::size_t k = 0; k < n; ++k) {
                if (*scalars(probe)[k] == 0.0) continue;
                g_mutant = {e->data, nullptr, static_cast<int>(k)};
                ++mutants;
                if (!refuted(copy)) survivors.push_back(id + "[" + std::to_string(k) + "]");
            }
        } else if (const auto* p =
                       dampsym::method_data<dampsym::PartitionedExponentialCoefficients>(m)) {
            dampsym::PartitionedExponentialRKData data = *p->data;
            data.coefficients_B = mutated_perk;
            copy.data = dampsym::PartitionedExponentialCoefficients{&data};
            ExponentialTableau q, pt;
            dampsym::perk_coefficients(*p->data, 0.3, q, pt);
            std::vector<double*> all = scalars(q);
            for (auto* v : scalars(pt, false)) all.push_back(v);
            for (std::size_t k = 0; k < all.size(); ++k) {
                if (*all[k] == 0.0) continue;
                g_mutant = {nullptr, p->data, static_cast<int>(k)};
                ++mutants;
                if (!refuted(copy)) survivors.push_back(id + "[" + std::to_string(k) + "]");
            }
        }
    }
    g_mutant = {};
    INFO("survivors: " << [&] {
        std::string s;
        for (const auto& x : survivors) s += x + " ";
        return s;
    }());
    CHECK(mutants > 40);
    CHECK(survivors.empty());
}

TEST_CASE("every family's coefficients are mutated by the tests above (no family skipped)",
          "[coefficients][mutants]") {
    // The two tests above perturb the coefficient types listed here; the hand-written schemes and
    // C plugins have none (their code is the method). A new family in MethodFamilies fails here
    // until its coefficients are perturbed above too.
    using Covered =
        dampsym::TypeList<dampsym::RungeKuttaTableau, dampsym::IntegratingFactorTableau,
                          dampsym::PartitionedTableau, dampsym::GeneralLinearCoefficients,
                          dampsym::ExponentialCoefficients,
                          dampsym::PartitionedExponentialCoefficients, dampsym::HandWrittenScheme,
                          dampsym::PluginStep>;
    int families = 0;
    dampsym::for_each_type(dampsym::MethodFamilies{}, [&]<class D>() {
        bool covered = false;
        dampsym::for_each_type(Covered{},
                               [&]<class C>() { covered = covered || std::is_same_v<C, D>; });
        INFO("family " << families << " of MethodFamilies");
        CHECK(covered);
        ++families;
    });
    CHECK(families > 0);
}
