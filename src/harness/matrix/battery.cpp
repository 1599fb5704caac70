// The method × property matrix, the battery: the property table (properties(), one function per
// property group), which methods claim which property, and the battery's cases built from it as
// JSON and validated by parse_case, so they are ordinary cases (docs/matrix.md "The battery").
#include "harness/matrix/battery.hpp"

#include "diagnostics/conformal_symplectic_diagnostic.hpp"
#include "diagnostics/dissipation_drift_diagnostic.hpp"
#include "diagnostics/error_diagnostic.hpp"
#include "diagnostics/invariants_diagnostic.hpp"
#include "diagnostics/momentum_diagnostic.hpp"
#include "diagnostics/order_diagnostic.hpp"
#include "diagnostics/stability_sweep_diagnostic.hpp"
#include "harness/matrix/matrix.hpp"
#include "harness/problem_info.hpp"
#include "harness/run/runner.hpp"
#include "methods/coefficient_checks.hpp"
#include "methods/runtime_methods.hpp"

#include <fnmatch.h>
#include <map>

namespace dampsym {
namespace matrix_detail {
namespace {

// The battery's cases name diagnostics and metrics by the names the diagnostics declare.
template <class D>
std::string name_of() {
    return std::string(D::name);
}
template <class D>
std::string metric_of(std::string_view rest) {
    return name_of<D>() + "." + std::string(rest);
}

CheckSpec criterion(CheckOp op, double value, double tol = 0.0, bool use_abs = false) {
    CheckSpec c;
    c.op = op;
    c.value = value;
    c.tol = tol;
    c.use_abs = use_abs;
    return c;
}

// The coefficient-level checks of the method's family (methods --check): order conditions to the
// declared order, the structure its claims imply; a method without coefficients (a hand-written
// scheme, a plugin) is n/a.
void coefficients_property(std::vector<Property>& p) {
    Property c;
    c.id = "coefficients";
    c.header = "coefficients";
    c.title = "coefficient-level checks of the method's family (order conditions through the "
              "declared order, symplecticity / conformal conditions / G-symplecticity it claims)";
    c.source = "dampsym methods --check; src/methods/coefficient_checks.hpp";
    c.from = Source::coefficients;
    c.criterion_text = "every check agrees with the declaration (a sufficient condition that "
                       "fails is inconclusive)";
    p.push_back(c);
}

// The fitted order on the pendulum ladders.
void order_property(std::vector<Property>& p) {
    Property o;
    o.id = "order";
    o.header = "order (pendulum)";
    o.title = "fitted convergence order on the damped pendulum";
    o.source = "verify/cases/families-orders-*.json; docs/conventions.md §5 order";
    o.from = Source::order;
    o.case_id = "matrix-order-";
    o.problem = "pendulum";
    o.case_json = {{"problem", {{"id", "pendulum"}, {"gamma", 0.1}, {"q0", 1.0}, {"p0", 0.0}}},
                   {"t_end", 10.0},
                   {"reference", {{"epsrel", 1e-14}, {"epsabs", 1e-15}}},
                   {"diagnostics", {name_of<ErrorDiagnostic>(), name_of<OrderDiagnostic>()}}};
    o.criterion = criterion(CheckOp::near, 0.0, 0.1); // value: the declared order
    o.criterion_text = "|slope − declared order| ≤ 0.1";
    p.push_back(o);
}

// E_n on the damped pendulum and on Hill's equation.
void en_properties(std::vector<Property>& p) {
    const json cs_diag = {name_of<ConformalSymplecticDiagnostic>()};
    Property e;
    e.id = "en-pendulum";
    e.header = "E_n pendulum";
    e.title = "conformal symplecticity: max_n E_n (relative) on the damped pendulum";
    e.source = "verify/cases/cs-pendulum.json; B(2.42), B(3.2)";
    e.case_id = "matrix-en-pendulum";
    e.problem = "pendulum";
    e.case_json = {{"problem", {{"id", "pendulum"}, {"gamma", 0.1}, {"q0", 2.0}, {"p0", 0.5}}},
                   {"t_end", 50.0},
                   {"dt", 0.5},
                   {"diagnostics", cs_diag}};
    e.metric = metric_of<ConformalSymplecticDiagnostic>("max_rel");
    e.criterion = criterion(CheckOp::le, 1e-13);
    e.claim = claim_conformal_symplectic;
    e.controls_must_fail = true;
    e.criterion_text = "max_n E_n ≤ 1e-13";
    p.push_back(e);
    e.id = "en-hill";
    e.header = "E_n Hill";
    e.title = "conformal symplecticity: max_n E_n (relative) on Hill's equation, "
              "γ(t) = 0.5 cos 2t";
    e.source = "verify/cases/cs-hill.json; B(2.42), B(3.2), B Fig 3.3";
    e.case_id = "matrix-en-hill";
    e.problem = "hill";
    e.case_json["problem"] = {
        {"id", "hill"}, {"epsilon", 1.0}, {"kappa", 1.0}, {"q0", 1.0}, {"p0", 0.0}};
    p.push_back(e);
}

// E_n on the undamped pendulum.
void en_undamped_property(std::vector<Property>& p) {
    const json cs_diag = {name_of<ConformalSymplecticDiagnostic>()};
    Property e;
    e.id = "en-pendulum-undamped";
    e.header = "E_n pendulum γ = 0";
    e.title = "symplecticity: max_n E_n (relative) on the undamped pendulum (γ = 0, "
              "where a conformal symplectic method is symplectic)";
    e.source = "verify/cases/cs-pendulum.json at gamma = 0; HLW VI, B(2.42)";
    e.case_id = "matrix-en-pendulum-undamped";
    e.problem = "pendulum";
    e.case_json = {{"problem", {{"id", "pendulum"}, {"gamma", 0.0}, {"q0", 2.0}, {"p0", 0.5}}},
                   {"t_end", 50.0},
                   {"dt", 0.5},
                   {"diagnostics", cs_diag}};
    e.metric = metric_of<ConformalSymplecticDiagnostic>("max_rel");
    e.criterion = criterion(CheckOp::le, 1e-13);
    e.claim = claim_conformal_symplectic | claim_symplectic_if_undamped;
    e.criterion_text = "max_n E_n ≤ 1e-13";
    p.push_back(e);
}

// The conformal law of H_γ on the oscillator.
void hgamma_property(std::vector<Property>& p) {
    Property h;
    h.id = "hgamma-oscillator";
    h.header = "H_γ law (oscillator)";
    h.title = "conformal law H_{n+1} = e^{-2γh} H_n of H_γ = ½(ω²q² + p²) + γqp on the "
              "oscillator, max per-step residual";
    h.source = "verify/cases/osc-orders.json; B Ex. 1.2, B Def. 2.3";
    h.case_id = "matrix-hgamma-oscillator";
    h.problem = "oscillator";
    h.case_json = {
        {"problem",
         {{"id", "oscillator"}, {"omega", 1.0}, {"gamma", 0.025}, {"q0", 1.0}, {"p0", 0.0}}},
        {"t_end", 10.0},
        {"dt", 0.1},
        {"diagnostics", {name_of<InvariantsDiagnostic>()}}};
    h.metric = metric_of<InvariantsDiagnostic>("H_gamma.max_step_res");
    h.criterion = criterion(CheckOp::le, 1e-13);
    h.claim = claim_conformal_quadratic;
    h.criterion_text = "max per-step residual ≤ 1e-13";
    p.push_back(h);
}

// The momentum laws of the damped 3-body problem.
void momentum_properties(std::vector<Property>& p) {
    Property n;
    n.id = "linear-momentum";
    n.header = "Σp law (N-body)";
    n.title = "linear momentum per step on the damped 3-body problem: e^{-2γh} (claim "
              "linear-momentum) or B Table 3.1's e^{-γh}(2-γh)/(2+γh) (claim "
              "linear-momentum-cayley)";
    n.source = "verify/cases/nbody-table31-momentum.json; B Table 3.1, B(3.9)";
    n.case_id = "matrix-nbody";
    n.problem = "nbody";
    n.case_json = {{"problem", {{"id", "nbody"}, {"gamma", 0.1}}},
                   {"t_end", 2.5},
                   {"dt", 0.05},
                   {"diagnostics", {name_of<MomentumDiagnostic>()}}};
    n.metric =
        metric_of<MomentumDiagnostic>("linear.max_law_res"); // max_table_res for the Cayley claim
    n.criterion = criterion(CheckOp::le, 1e-13);
    n.claim = claim_linear_momentum | claim_linear_momentum_cayley;
    n.criterion_text = "max per-step residual of the claimed factor ≤ 1e-13 (unclaimed: "
                       "of e^{-2γh})";
    p.push_back(n);
    n.id = "angular-momentum";
    n.header = "Σq×p law (N-body)";
    n.title = "angular momentum per step on the damped 3-body problem: e^{-2γh}";
    n.metric = metric_of<MomentumDiagnostic>("angular.max_law_res");
    n.criterion = criterion(CheckOp::le, 1e-12);
    n.claim = claim_angular_momentum;
    n.criterion_text = "max per-step residual ≤ 1e-12";
    p.push_back(n);
}

// The quadratic Casimir of the undamped rigid body.
void quadratic_property(std::vector<Property>& p) {
    Property r;
    r.id = "quadratic-undamped";
    r.header = "quadratic inv. γ = 0 (rigid body)";
    r.title = "drift of the quadratic Casimir |z|² on BS's undamped rigid body: "
              "least-squares slope of |F_n/F_0 − 1| per unit time";
    r.source = "verify/cases/rb-bs-glm4.json over 10^4 instead of 10^5 steps; BS, BD §3";
    r.case_id = "matrix-quadratic-rigid-body";
    r.problem = "rigid-body";
    r.case_json = {{"problem",
                    {{"id", "rigid-body"},
                     {"epsilon", 0.0},
                     {"I1", 4.0},
                     {"I2", 3.0},
                     {"I3", 2.0},
                     {"z1", 4.0},
                     {"z2", 3.0},
                     {"z3", 0.0}}},
                   {"t_end", 1000.0},
                   {"dt", 0.1},
                   {"diagnostics", {name_of<InvariantsDiagnostic>()}}};
    r.metric = metric_of<InvariantsDiagnostic>("casimir.ratio_dev_slope");
    r.criterion = criterion(CheckOp::le, 1e-11, 0.0, true);
    r.claim = claim_g_symplectic | claim_conformal_quadratic;
    r.criterion_text = "|slope| ≤ 1e-11 per unit time";
    p.push_back(r);
}

// The drift of d(t) on the oscillator.
void drift_property(std::vector<Property>& p) {
    Property d;
    d.id = "drift";
    d.header = "d(t) drift (oscillator)";
    d.title = "slope of d(t) = ln(max q) + γt over the maxima on the oscillator (F(4.4))";
    d.source = "verify/cases/osc-drift-fig47.json; F Figs 4.6, 4.7, F(4.4)";
    d.case_id = "matrix-drift-oscillator";
    d.problem = "oscillator";
    d.case_json = {{"problem", {{"id", "oscillator"}, {"omega", 1.0}, {"gamma", 0.005}}},
                   {"t_end", 1000.0},
                   {"dt", 0.5},
                   {"diagnostics", {name_of<DissipationDriftDiagnostic>()}}};
    d.metric = metric_of<DissipationDriftDiagnostic>("slope");
    d.criterion = criterion(CheckOp::le, 1e-4, 0.0, true);
    d.claim = claim_conformal_symplectic;
    d.criterion_text = "|slope| ≤ 1e-4";
    p.push_back(d);
}

// The stability threshold on the oscillator.
void threshold_property(std::vector<Property>& p) {
    Property s;
    s.id = "threshold";
    s.header = "threshold h* (oscillator)";
    s.title = "stability threshold on the oscillator ω = 3.51 over γ ∈ [0, 3.5], h ∈ "
              "[0.025, 1]: the kernel's one-step matrix against F's closed form (F's "
              "condition) or the tableau's stability function R(z) (power-boundedness); "
              "value: the first h of the γ = 0 row where it fails";
    s.source = "verify/cases/osc-stability-sweep.json; F(3.12), (3.17), (3.22), F Figs "
               "3.1-3.3";
    s.from = Source::threshold;
    s.case_id = "matrix-threshold-oscillator";
    s.problem = "oscillator";
    s.case_json = {{"problem", {{"id", "oscillator"}, {"omega", 3.51}, {"gamma", 1.0}}},
                   {"t_end", 1.0},
                   {"dt", 0.1},
                   {"diagnostics", {name_of<StabilitySweepDiagnostic>()}},
                   {"stability_sweep",
                    {{"omega", 3.51}, {"gamma", {0.0, 3.5, 0.25}}, {"h", {0.025, 1.0, 0.025}}}}};
    s.criterion = criterion(CheckOp::le, 1.0);
    s.criterion_text = "first failure per γ row within one h cell of the closed form's";
    p.push_back(s);
}

} // namespace

std::vector<double> order_ladder(int order) {
    if (order <= 1) return {0.02, 0.01, 0.005, 0.0025};
    if (order == 2) return {0.1, 0.05, 0.025, 0.0125};
    if (order <= 5) return {0.2, 0.1, 0.05, 0.025};
    return {1.0, 0.625, 0.5, 0.3125};
}
int ladder_group(int order) {
    return order <= 1 ? 1 : order == 2 ? 2 : order <= 5 ? 4 : 6;
}

const std::vector<Property>& properties() {
    static const std::vector<Property> props = [] {
        std::vector<Property> p;
        coefficients_property(p);
        order_property(p);
        en_properties(p);
        en_undamped_property(p);
        hgamma_property(p);
        momentum_properties(p);
        quadratic_property(p);
        drift_property(p);
        threshold_property(p);
        return p;
    }();
    return props;
}

bool claims_property(const Property& p, const MethodInfo& m) {
    if (p.from == Source::order) return true; // every method declares its order
    if (p.from == Source::threshold) return false;
    if (p.from == Source::coefficients) return true; // every declaration is checked
    // an RK method on the plain form that is symplectic for γ = 0 conserves every quadratic
    // invariant (B(1.18), HLW IV.2); a partitioned one only those of the form qᵀCp
    if (p.id == "quadratic-undamped" && (m.claims & claim_symplectic_if_undamped) != 0 &&
        m.form == Form::plain)
        return true;
    return (m.claims & p.claim) != 0;
}

namespace {

json base_case(const Property& p, const std::string& id, const std::vector<std::string>& methods) {
    json c = p.case_json;
    c["id"] = id;
    c["title"] = "matrix: " + p.title;
    c["source"] = p.source;
    c["suites"] = json::array({"matrix"});
    c["methods"] = methods;
    c["no_checks_because"] =
        "the method x property matrix judges the metrics against the "
        "methods' declared claims (src/harness/matrix/judge.cpp, docs/matrix.md)";
    return c;
}

} // namespace
} // namespace matrix_detail

namespace {
using json = nlohmann::json;
} // namespace

std::vector<const MethodInfo*> matrix_methods(const std::vector<std::string>& globs) {
    std::vector<const MethodInfo*> all;
    for (const auto& m : method_catalog()) all.push_back(&m);
    for (const MethodInfo* m : loaded_methods()) all.push_back(m); // method files, plugins
    std::vector<const MethodInfo*> out;
    for (const MethodInfo* m : all) {
        const std::string id(m->id);
        bool keep = globs.empty();
        for (const auto& g : globs)
            if (fnmatch(g.c_str(), id.c_str(), 0) == 0) keep = true;
        if (keep) out.push_back(m);
    }
    return out;
}

std::vector<CaseSpec> matrix_battery(const std::vector<const MethodInfo*>& methods) {
    std::vector<CaseSpec> cases;
    std::map<std::string, bool> made; // the N-body case serves two properties
    const std::string file = "dampsym matrix battery";
    for (const matrix_detail::Property& p : matrix_detail::properties()) {
        if (p.from == matrix_detail::Source::coefficients) continue; // no case to run
        if (p.from == matrix_detail::Source::order) {
            std::map<int, std::vector<std::string>> groups;
            for (const MethodInfo* m : methods)
                if (method_applies(m->id, p.problem))
                    groups[matrix_detail::ladder_group(m->order)].push_back(std::string(m->id));
            for (const auto& [g, ms] : groups) {
                json c = matrix_detail::base_case(p, p.case_id + std::to_string(g), ms);
                c["dt_ladder"] = matrix_detail::order_ladder(g);
                cases.push_back(parse_case(c, file, {}));
            }
            continue;
        }
        if (made[p.case_id]) continue;
        made[p.case_id] = true;
        std::vector<std::string> ms;
        for (const MethodInfo* m : methods)
            if (method_applies(m->id, p.problem)) ms.push_back(std::string(m->id));
        if (ms.empty()) continue;
        cases.push_back(parse_case(matrix_detail::base_case(p, p.case_id, ms), file, {}));
    }
    return cases;
}

} // namespace dampsym
