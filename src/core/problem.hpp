// What a problem is. A problem is a small struct (one header in src/problems/) with:
//   static constexpr std::string_view id, title;
//   static std::vector<ParamSpec> param_specs();       parameters with defaults and ranges
//   static P from_params(const ParamMap&);              build from validated parameters
//   int dim() const;  Vec initial_state() const;        full state z = [q; p]
//   double Gamma(double t) const;                       Γ(t) = ∫₀ᵗ γ(s) ds
//   double dGamma(double t, double h) const;            Γ(t+h) − Γ(t), without cancellation
//   forms: separable Rayleigh form (grad_T, force, hess_T, force_jacobian), from which
//          SeparableProblem derives the conformal form N(z,t) and the plain form f(t,z);
//   invariants: names, values, decaying as e^{-2Γ(t)} (B Def. 1.1), and next to them the
//               scale of each law residual (invariant_scale_defs, invariant_scales: a magnitude
//               that does not vanish with the invariant, docs/conventions.md "Law residuals and
//               their scales"); optionally invariant_rate_factors (one per invariant, default 1):
//               invariant k then decays as e^{-2 f_k Γ(t)} (a linear Casimir of a first-order
//               system z' = N − γz decays as e^{-Γ}: f = ½; see invariant_rate_factor below);
//   optionally: energy(z) with energy_scale(z); exact(t0, z0, t, out) and autonomous (when
//               has_exact, see ExactSolution below);
//   optionally: static constexpr OrbitFigure figure_orbit (below): its figures can draw the
//               orbit, by default or when a case asks for it;
//   optionally: static constexpr int static_n, the degrees of freedom when fixed at compile time
//               (n() returns it); kernels that use static_dof<P>() then keep stage vectors of
//               fixed size, which the compiler reduces to scalar code.
#pragma once

#include "core/types.hpp"

#include <concepts>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace dampsym {

// Whether a problem's figures (`dampsym run --figures`, docs/reports.md) draw its orbit, the
// trajectory sampled over the run: by_default for the problems whose papers draw orbits (every case
// keeps the orbit), on_request for those whose cases draw one only when their "figures" key lists
// "orbit" (a phase portrait). A run keeps orbit samples only for a case that draws them.
enum class OrbitFigure { none, on_request, by_default };

// The interval of values a parameter may take: the range within which the problem's formulas
// (forms, invariants, exact solution, energy) are valid in double precision. Every bound is
// finite; lo_open/hi_open exclude the end point. Case files outside it are rejected (exit 2).
struct Range {
    double lo, hi;
    bool lo_open = false, hi_open = false;

    static constexpr Range closed(double lo, double hi) { return {lo, hi, false, false}; }
    static constexpr Range above(double lo, double hi) { return {lo, hi, true, false}; } // (lo, hi]
    static constexpr Range below(double lo, double hi) { return {lo, hi, false, true}; } // [lo, hi)
    static constexpr Range symmetric(double bound) { return {-bound, bound, false, false}; }

    bool contains(double x) const {
        return (lo_open ? x > lo : x >= lo) && (hi_open ? x < hi : x <= hi);
    }
};

// A parameter: a scalar (default_value), or, when is_array, a list of numbers (default_array;
// size_multiple > 1 requires the length to be a multiple of it, e.g. 3 for 3-D positions; at most
// max_size entries). Every number (each entry of an array) must lie in `range`. A parameter with
// `choices` is enum-like: the case gives one of the names, the problem receives its index.
// An `integer` parameter takes whole numbers only.
struct ParamSpec {
    std::string name;
    double default_value;
    Range range;
    std::string doc;
    bool is_array = false;
    std::vector<double> default_array{};
    int size_multiple = 1;
    int max_size = 0;
    std::vector<std::string> choices{};
    bool integer = false;
};

// Array-valued parameter spec: at most max_size entries, each in `range`.
inline ParamSpec array_param(std::string name, std::vector<double> defaults, Range range,
                             std::string doc, int max_size, int size_multiple = 1) {
    return {.name = std::move(name),
            .default_value = 0.0,
            .range = range,
            .doc = std::move(doc),
            .is_array = true,
            .default_array = std::move(defaults),
            .size_multiple = size_multiple,
            .max_size = max_size};
}

// Enum-like parameter: one of `choices` by name (the default is choices[default_index]); the
// problem's from_params receives the index as a number.
inline ParamSpec choice_param(std::string name, int default_index, std::vector<std::string> choices,
                              std::string doc) {
    const double last = static_cast<double>(choices.size()) - 1.0;
    return {.name = std::move(name),
            .default_value = static_cast<double>(default_index),
            .range = Range::closed(0.0, last),
            .doc = std::move(doc),
            .choices = std::move(choices),
            .integer = true};
}

// Whole-number parameter in [lo, hi].
inline ParamSpec integer_param(std::string name, int default_value, int lo, int hi,
                               std::string doc) {
    return {.name = std::move(name),
            .default_value = static_cast<double>(default_value),
            .range = Range::closed(lo, hi),
            .doc = std::move(doc),
            .integer = true};
}

// Validated parameter values: scalars by name (at, operator[]) and arrays by name (array).
struct ParamMap {
    std::map<std::string, double> scalars;
    std::map<std::string, std::vector<double>> arrays;

    double at(const std::string& name) const { return scalars.at(name); }
    double& operator[](const std::string& name) { return scalars[name]; }
    const std::vector<double>& array(const std::string& name) const { return arrays.at(name); }
};

// Degrees of freedom of problem type Q at compile time: Q::static_n, or Eigen::Dynamic.
template <class Q>
constexpr int static_dof() {
    if constexpr (requires { Q::static_n; })
        return Q::static_n;
    else
        return Eigen::Dynamic;
}

// Separable Rayleigh form q' = ∇T(p), p' = F(q,t) − 2γ(t)p with F = −∇_q V(q,t) (+ forcing).
// Derived provides: n() (degrees of freedom), gamma_at(t), grad_T(p, out), hess_T(p, out),
// force(t, q, out), force_jacobian(t, q, out). This base derives the other two forms of conventions
// §1:
//   conformal form: z' = N(z,t) − γ(t)z, N = J⁻¹∇H_γ = [∇T(p) + γq; F(q,t) − γp]
//   plain form:     z' = f(t,z) = [∇T(p); F(q,t) − 2γp]
template <class Derived>
struct SeparableProblem {
    static constexpr bool has_separable = true;
    static constexpr bool has_conformal = true;

    const Derived& self() const { return static_cast<const Derived&>(*this); }
    int dim() const { return 2 * self().n(); }

    void N(double t, const Vec& z, Vec& out) const {
        const int n = self().n();
        const double g = self().gamma_at(t);
        auto qo = out.head(n);
        auto po = out.tail(n);
        self().grad_T(z.tail(n), qo);
        self().force(t, z.head(n), po);
        qo += g * z.head(n);
        po -= g * z.tail(n);
    }
    void N_jacobian(double t, const Vec& z, Mat& J) const {
        const int n = self().n();
        const double g = self().gamma_at(t);
        J.setZero();
        auto Jqp = J.block(0, n, n, n);
        auto Jpq = J.block(n, 0, n, n);
        self().hess_T(z.tail(n), Jqp);
        self().force_jacobian(t, z.head(n), Jpq);
        J.block(0, 0, n, n).diagonal().setConstant(g);
        J.block(n, n, n, n).diagonal().setConstant(-g);
    }
    // z and out: Vec, or fixed-size vectors of 2·static_n (the blocks are then fixed-size too).
    template <class Z, class Out>
    void rhs(double t, const Z& z, Out& out) const {
        constexpr int N = static_dof<Derived>();
        const int n = self().n();
        auto qo = out.template head<N>(n);
        auto po = out.template segment<N>(n, n);
        self().grad_T(z.template segment<N>(n, n), qo);
        self().force(t, z.template head<N>(n), po);
        po -= 2.0 * self().gamma_at(t) * z.template segment<N>(n, n);
    }
    template <class Z>
    void rhs_jacobian(double t, const Z& z, Mat& J) const {
        const int n = self().n();
        J.setZero();
        auto Jqp = J.block(0, n, n, n);
        auto Jpq = J.block(n, 0, n, n);
        self().hess_T(z.tail(n), Jqp);
        self().force_jacobian(t, z.head(n), Jpq);
        J.block(n, n, n, n).diagonal().setConstant(-2.0 * self().gamma_at(t));
    }
};

// Conformal form given, z' = N(z,t) − γ(t)z (conventions §1): Derived provides N(t, z, out),
// N_jacobian(t, z, J) and gamma_at(t); this base derives the plain form from them,
//   f(t,z) = N(z,t) − γ(t)z,   ∂f/∂z = ∂N/∂z − γ(t)I.
template <class Derived>
struct ConformalForm {
    void rhs(double t, const Vec& z, Vec& out) const {
        const Derived& p = static_cast<const Derived&>(*this);
        p.N(t, z, out);
        out -= p.gamma_at(t) * z;
    }
    void rhs_jacobian(double t, const Vec& z, Mat& J) const {
        const Derived& p = static_cast<const Derived&>(*this);
        p.N_jacobian(t, z, J);
        J.diagonal().array() -= p.gamma_at(t);
    }
};

// Unit mass, T(p) = |p|²/2: ∇T(p) = p, ∇²T = I.
struct UnitMass {
    template <class In, class Out>
    void grad_T(const In& p, Out& out) const {
        out = p;
    }
    template <class In, class Out>
    void hess_T(const In&, Out& out) const {
        out.setIdentity();
    }
};

// Constant damping: Derived has a member `gamma`; Γ(t) = γt.
template <class Derived>
struct ConstantGamma {
    static constexpr bool constant_gamma = true;
    double gamma_at(double) const { return static_cast<const Derived&>(*this).gamma; }
    double Gamma(double t) const { return static_cast<const Derived&>(*this).gamma * t; }
    double dGamma(double, double h) const { return static_cast<const Derived&>(*this).gamma * h; }
};

// Start time. A case's initial state is the state at its start time t0, for every problem (the
// runner applies initial_state() at t0 and steps t0 + n h). An exact solution (has_exact = true)
// therefore takes the start explicitly,
//   void exact(double t0, const Vec& z0, double t, Vec& out) const;   z(t) with z(t0) = z0,
// the solution of the problem's own ODE from (t0, z0): for an autonomous problem a shift of the
// solution from (0, z0) by t0; for a time-dependent one (γ(t), forcing) not a shift. z(t0) must be
// z0 exactly. The problem also declares `static constexpr bool autonomous` (f(t, z) independent
// of t), which the tests use to check the shift property. There is deliberately no exact(t, out)
// form (a solution written for a start at 0 and evaluated at absolute time): ExactSolution
// rejects it, and src/harness/registry.hpp asserts the concept for every registered problem with
// has_exact; tests/test_exact_solutions.cpp checks every such problem against its ODE, the
// certified GSL reference and z(t0) = z0, from random t0 and states.
template <class P>
concept ExactSolution = requires(const P& p, const Vec& z0, Vec& out) {
    { p.exact(0.0, z0, 0.0, out) } -> std::same_as<void>;
    { P::autonomous } -> std::convertible_to<bool>;
}
&&!requires(const P& p, Vec& out) {
    p.exact(0.0, out);
};

// Whether problem type Q satisfies the exact-solution contract (trivially when it has none).
template <class Q>
constexpr bool exact_solution_contract() {
    if constexpr (Q::has_exact)
        return ExactSolution<Q>;
    else
        return true;
}

// Rate factor f_k of invariant k: its law is I(t) = e^{−2 f_k (Γ(t) − Γ(t0))} I(t0). 1 unless the
// problem declares `static constexpr std::array<double, K> invariant_rate_factors` (B's modified
// Burgers: the Casimir Σu of u' = N(u) − γu, γ = 2γ_B, decays as e^{−Γ}, f = ½; docs/pde.md).
template <class Q>
constexpr double invariant_rate_factor(std::size_t k) {
    if constexpr (requires { Q::invariant_rate_factors; }) {
        static_assert(Q::invariant_rate_factors.size() == Q::invariant_names.size(),
                      "one rate factor per invariant");
        return Q::invariant_rate_factors[k];
    } else {
        (void)k;
        return 1.0;
    }
}

namespace detail {
// Whether problem type Q declares constant damping (false when it does not say): kernels then
// evaluate their damping factors once instead of every step.
template <class Q>
constexpr bool declares_constant_gamma() {
    if constexpr (requires { Q::constant_gamma; })
        return Q::constant_gamma;
    else
        return false;
}
} // namespace detail

} // namespace dampsym
