// The problem contract as C++20 concepts (the prose version is in core/problem.hpp). Every
// registered problem is checked with static_assert at registration (harness/registry.hpp); the
// diagnostics state what they need of a problem with these and diagnostics/capabilities.hpp.
#pragma once

#include "core/problem.hpp"
#include "core/types.hpp"

#include <concepts>
#include <string_view>
#include <vector>

namespace dampsym {

// Every problem: identity, parameters, state, damping, invariants and the plain vector field.
template <class P>
concept Problem = requires(const P& p, const ParamMap& m, const Vec& z, Vec& out, double t) {
    { P::id } -> std::convertible_to<std::string_view>;
    { P::title } -> std::convertible_to<std::string_view>;
    { P::param_specs() } -> std::same_as<std::vector<ParamSpec>>;
    { P::from_params(m) } -> std::same_as<P>;
    { p.dim() } -> std::convertible_to<int>;
    { p.initial_state() } -> std::convertible_to<Vec>;
    { p.Gamma(t) } -> std::convertible_to<double>;
    { p.dGamma(t, t) } -> std::convertible_to<double>;
    p.rhs(t, z, out);
    { P::is_linear } -> std::convertible_to<bool>;
    { P::has_exact } -> std::convertible_to<bool>;
    { P::has_energy } -> std::convertible_to<bool>;
    { P::constant_gamma } -> std::convertible_to<bool>;
    P::invariant_names.size();
    P::invariant_scale_defs.size();
}
&&P::invariant_names.size() == P::invariant_scale_defs.size() && exact_solution_contract<P>();

// A problem in the separable Rayleigh form q' = ∇T(p), p' = F(q,t) − 2γ(t)p (core/problem.hpp's
// SeparableProblem base provides N and f from it).
template <class P>
concept Separable = Problem<P> && P::has_separable && requires(const P& p, double t) {
    { p.n() } -> std::convertible_to<int>;
    { p.gamma_at(t) } -> std::convertible_to<double>;
};

// A problem with an exact solution from (t0, z0) (core/problem.hpp ExactSolution).
template <class P>
concept HasExactSolution = P::has_exact && ExactSolution<P>;

// A problem with an energy H(z) and the scale of its changes (docs/conventions.md).
template <class P>
concept HasEnergy = P::has_energy && requires(const P& p, const Vec& z) {
    { p.energy(z) } -> std::convertible_to<double>;
    { p.energy_scale(z) } -> std::convertible_to<double>;
};

// The damped linear oscillator q'' + 2γq' + ω²q = 0 with constant ω and γ (F ch. 3): a constant
// one-step matrix M(h) whose closed forms the stability diagnostics compare with. `with(ω, γ)` is
// the same problem at other coefficients (the stability sweep's grid).
template <class P>
concept LinearOscillator = Separable<P> && P::is_linear && P::constant_gamma &&
    requires(const P& p, double w) {
    { p.omega } -> std::convertible_to<double>;
    { p.gamma } -> std::convertible_to<double>;
    { p.with(w, w) } -> std::same_as<P>;
};

} // namespace dampsym
