// Derivatives checked against what they differentiate (diagnostics/jacobian_check.hpp,
// problem_check.hpp; docs/conventions.md "Derivative checks"):
//  - the conformal-symplectic pass checks each kernel's step Jacobian Ψ against central
//    differences of its step: the real csv1, cimp, glifrk2, gauss2, rk4, stormer-verlet and
//    cse-etd pass on the pendulum and on Kepler, with the tolerance below 1e-9 relative (a 1e-7
//    relative defect of a coefficient is above it);
//  - negative control: csv1 with its first kick's (h/2)F' × (1 + 1e-7) in Ψ only (a test-local
//    kernel wrapping csv1; the step unchanged) keeps E_n at round-off, and the check reports
//    "jacobian-mismatch";
//  - the problems' Jacobians (rhs, N, and N'D + DN'ᵀ = 0 for the structure E_n uses) pass for the
//    pendulum, Kepler, N-body, Klein-Gordon (M = 512, 1024 unknowns, too) and Burgers (M = 1024
//    too); negative controls: the pendulum with force −sin q × (1 + 1e-7) and its Jacobian
//    unchanged, and a force that is not a gradient (N'D + DN'ᵀ ≠ 0), fail.
// Set DAMPSYM_TEST_VERBOSE=1 to print the measured disagreements, tolerances and margins.
#include "diagnostics/conformal_symplectic_diagnostic.hpp"
#include "diagnostics/problem_check_json.hpp"
#include "harness/problem_list.hpp"
#include "methods/csv1.hpp"

#include "support/helpers.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

using dampsym::Counters;
using dampsym::json;
using dampsym::Mat;
using dampsym::MethodInfo;
using dampsym::StepStatus;
using dampsym::Vec;
using dampsym::test::method;
using dampsym::test::verbose;

namespace {

constexpr double h = 0.1;
constexpr std::int64_t n_steps = 200;
constexpr double defect = 1e-7;

// csv1 whose step Jacobian has its first kick's (h/2)F'(q₀) multiplied by 1 + 1e-7; its step is
// csv1's. By csv1.hpp's chain rule the defect a = 1e-7 (h/2)F'(q₀) of ∂p½/∂q₀ moves ∂q₁/∂q₀ by
// h T'' a and ∂p₁/∂q₀ by d₂ (a + (h/2) F'(q₁) h T'' a); one degree of freedom, T'' = 1.
template <class P>
class Csv1KickDefect {
public:
    static constexpr std::string_view kernel_id = "csv1";
    static constexpr bool has_step_jacobian = true;
    Csv1KickDefect(const P& p, const MethodInfo& info, double step, Counters& c)
        : inner_(p, info, step, c), p_(p), h_(step) {}
    StepStatus step(double t, Vec& z) { return inner_.step(t, z); }
    StepStatus step_jacobian(double t, Vec& z, Mat& Psi) {
        const double q0 = z[0];
        const StepStatus s = inner_.step_jacobian(t, z, Psi);
        const double hh = 0.5 * h_, d2 = std::exp(-2.0 * p_.dGamma(t + hh, hh));
        Mat F(1, 1);
        Vec q(1);
        q[0] = q0;
        p_.force_jacobian(t, q, F);
        const double a = defect * hh * F(0, 0);
        q[0] = z[0]; // q₁
        p_.force_jacobian(t + h_, q, F);
        Psi(0, 0) += h_ * a;
        Psi(1, 0) += d2 * (a + hh * F(0, 0) * h_ * a);
        return s;
    }

private:
    dampsym::Csv1<P> inner_;
    const P& p_;
    double h_;
};

// The pendulum with force −sin q × (1 + 1e-7) and its Jacobian −cos q unchanged.
struct ForceDefectPendulum : dampsym::SeparableProblem<ForceDefectPendulum>,
                             dampsym::UnitMass,
                             dampsym::ConstantGamma<ForceDefectPendulum> {
    double gamma = 0.1;
    static constexpr bool is_linear = false;
    static constexpr int static_n = 1;
    int n() const { return 1; }
    template <class In, class Out>
    void force(double, const In& q, Out& out) const {
        out[0] = -std::sin(q[0]) * (1.0 + defect);
    }
    template <class In, class Out>
    void force_jacobian(double, const In& q, Out& out) const {
        out(0, 0) = -std::cos(q[0]);
    }
};

// Two coupled oscillators with the non-gradient force F = (−q₁ + c q₂, −q₂), its Jacobian exact:
// the derivative checks pass, N'J⁻¹ + J⁻¹N'ᵀ = 0 does not (F' is not symmetric).
struct CirculationOscillator : dampsym::SeparableProblem<CirculationOscillator>,
                               dampsym::UnitMass,
                               dampsym::ConstantGamma<CirculationOscillator> {
    double gamma = 0.1, c = 1e-7;
    static constexpr bool is_canonical = true;
    int n() const { return 2; }
    template <class In, class Out>
    void force(double, const In& q, Out& out) const {
        out[0] = -q[0] + c * q[1];
        out[1] = -q[1];
    }
    template <class In, class Out>
    void force_jacobian(double, const In&, Out& out) const {
        out(0, 0) = -1.0;
        out(0, 1) = c;
        out(1, 0) = 0.0;
        out(1, 1) = -1.0;
    }
};

template <class P>
P with_defaults(const dampsym::ParamMap& overrides = {}) {
    dampsym::ParamMap m;
    for (const dampsym::ParamSpec& s : P::param_specs()) {
        if (s.is_array)
            m.arrays[s.name] = s.default_array;
        else
            m.scalars[s.name] = s.default_value;
    }
    for (const auto& [k, v] : overrides.scalars) m.scalars[k] = v;
    return P::from_params(m);
}

// The conformal-symplectic metrics of method `id` (kernel K, or the kernel that steps it).
template <class P>
json metrics_of(const P& prob, const std::string& id) {
    json out;
    const MethodInfo& info = method(id);
    out = dampsym::conformal_symplectic_metrics(prob, info, 0.0, h, n_steps,
                                                dampsym::test::kernel<P>(info).stepper);
    return out;
}

void print_check(const char* what, const std::string& id, double rel, double tol) {
    if (verbose())
        std::printf("[jacobian-check] %-10s %-15s rel %.2e  tol %.2e  margin %.1f decades\n", what,
                    id.c_str(), rel, tol, std::log10(tol / rel));
}

template <class P>
void real_kernels_pass(const P& prob, const char* label) {
    for (const std::string id :
         {"csv1", "cimp", "glifrk2", "gauss2", "rk4", "stormer-verlet", "cse-etd"}) {
        const json m = metrics_of(prob, id);
        INFO(label << " / " << id << ": " << m.dump());
        CHECK(m["status"] == "ok");
        CHECK(m["jacobian_check"] == "central-differences");
        CHECK(m["jacobian_check_states"] == 3);
        CHECK(m["jacobian_check_ratio"].get<double>() <= 1.0);
        // a 1e-7 relative defect of a term is two decades above the tolerance
        CHECK(m["jacobian_check_tol"].get<double>() <= 1e-9);
        print_check(label, id, m["jacobian_check_rel"].get<double>(),
                    m["jacobian_check_tol"].get<double>());
    }
}

template <class P>
dampsym::ProblemCheck problem_check(const P& p, const std::vector<double>& times,
                                    const std::vector<Vec>& states) {
    dampsym::ProblemCheck pc;
    pc.parts = dampsym::problem_check_parts<P>();
    for (std::size_t i = 0; i < states.size(); ++i)
        dampsym::check_problem_at(p, times[i], states[i], i, pc);
    return pc;
}

// The problem check at the initial state and at two perturbed initial states (the runner checks
// the reference's states there).
template <class P>
dampsym::ProblemCheck problem_check(const P& p) {
    const Vec z0 = p.initial_state();
    Vec z1 = z0, z2 = z0;
    for (Eigen::Index i = 0; i < z0.size(); ++i) {
        z1[i] += 0.1 * std::sin(1.0 + static_cast<double>(i));
        z2[i] -= 0.05 * std::cos(2.0 + static_cast<double>(i));
    }
    return problem_check(p, {0.0, 0.5, 1.0}, {z0, z1, z2});
}

template <class P>
void problem_passes(const P& p, const char* label) {
    const dampsym::ProblemCheck pc = problem_check(p);
    const json j = dampsym::problem_check_json(pc, 3);
    INFO(label << ": " << j.dump());
    CHECK(pc.passed());
    CHECK(dampsym::problem_check_failure(j).is_null());
    CHECK(pc.derivative.states >= 3);
    CHECK(pc.derivative.tol <= 1e-9);
    print_check("problem", label, pc.derivative.rel, pc.derivative.tol);
}

} // namespace

TEST_CASE("jacobian check: real kernels' step Jacobians match their steps", "[jacobian-check]") {
    real_kernels_pass(dampsym::test::pendulum(0.1), "pendulum");
    real_kernels_pass(with_defaults<dampsym::Kepler>(), "kepler");
}

TEST_CASE("jacobian check: csv1 with its first kick's (h/2)F' x (1 + 1e-7) in the Jacobian only",
          "[jacobian-check]") {
    const auto prob = dampsym::test::pendulum(0.1);
    const MethodInfo& info = method("csv1");
    const json bad = dampsym::conformal_symplectic_metrics(
        prob, info, 0.0, h, n_steps,
        dampsym::stepper_maker<Csv1KickDefect<dampsym::Pendulum>, dampsym::Pendulum>());
    INFO(bad.dump());
    // E_n cannot see it: the defective kick is still symplectic
    CHECK(bad["max_rel"].get<double>() <= 1e-13);
    CHECK(bad["status"] == "jacobian-mismatch");
    CHECK(bad["jacobian_check_ratio"].get<double>() > 1.0);
    CHECK(bad["message"].get<std::string>().find("not the step's derivative") != std::string::npos);
    print_check("csv1-kick", "defect", bad["jacobian_check_rel"].get<double>(),
                bad["jacobian_check_tol"].get<double>());
}

TEST_CASE("jacobian check: problems' Jacobians match their functions", "[jacobian-check]") {
    problem_passes(dampsym::test::pendulum(0.1), "pendulum");
    problem_passes(with_defaults<dampsym::Kepler>(), "kepler");
    problem_passes(with_defaults<dampsym::NBody>(), "nbody");
    problem_passes(with_defaults<dampsym::KleinGordon>(), "klein-gordon");
    problem_passes(with_defaults<dampsym::Burgers>(), "burgers");
    // M = 1024 unknowns (Klein-Gordon: M = 512, q and p): 2 random directions, dense Jacobians
    // (2.2 s under the sanitizers at -O1)
    dampsym::ParamMap big;
    const int m = 1024;
    big["M"] = m;
    problem_passes(with_defaults<dampsym::Burgers>(big), "burgers-large");
    big["M"] = m / 2;
    problem_passes(with_defaults<dampsym::KleinGordon>(big), "kg-large");
    const auto pc = problem_check(with_defaults<dampsym::Burgers>());
    CHECK(pc.parts == std::vector<std::string>{"rhs", "N", "structure:structure-matrix"});
    CHECK(pc.structure_vectors == 6);
}

TEST_CASE("jacobian check: the pendulum with force -sin q x (1 + 1e-7), Jacobian unchanged",
          "[jacobian-check]") {
    ForceDefectPendulum bad;
    const Vec z0{{1.0, 0.0}};
    const dampsym::ProblemCheck pc = problem_check(bad, {0.0}, {z0});
    const json j = dampsym::problem_check_json(pc, 1);
    INFO(j.dump());
    CHECK(!pc.passed());
    CHECK(pc.derivative.ratio > 1.0);
    const json failure = dampsym::problem_check_failure(j);
    REQUIRE(failure.is_object());
    CHECK(failure["name"] == "problem Jacobian matches its force");
    CHECK(failure["passed"] == false);
    print_check("pendulum", "force-defect", pc.derivative.rel, pc.derivative.tol);
}

TEST_CASE("jacobian check: a force that is not a gradient fails N'D + DN'^T = 0",
          "[jacobian-check]") {
    const Vec z0{{1.0, -0.5, 0.25, 0.5}};
    CirculationOscillator bad;
    const dampsym::ProblemCheck pc = problem_check(bad, {0.0}, {z0});
    CHECK(!pc.derivative.mismatch()); // its Jacobian is F's derivative
    CHECK(pc.structure_ratio > 1.0);
    CHECK(!pc.passed());
    bad.c = 0.0; // a gradient: passes
    CHECK(problem_check(bad, {0.0}, {z0}).passed());
}
