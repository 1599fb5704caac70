// Damped driven pendulum q'' + 2γq' + λ² sin q = f sin t (B(3.5), B §3.2.2). Not Hamiltonian for
// f ≠ 0 but conformal symplectic; V(q, t) = −λ² cos q − f q sin t. Numerical reference.
#pragma once

#include "core/param_table.hpp"
#include "core/problem.hpp"

#include <array>
#include <cmath>
#include <string_view>

namespace dampsym {

struct DrivenPendulum : SeparableProblem<DrivenPendulum>,
                        UnitMass,
                        ConstantGamma<DrivenPendulum>,
                        ParamTable<DrivenPendulum> {
    static constexpr std::string_view id = "driven-pendulum";
    static constexpr std::string_view title = "damped driven pendulum q''+2γq'+λ² sin q=f sin t";
    static constexpr bool is_linear = false;
    static constexpr bool has_exact = false;
    static constexpr bool has_energy = false;
    static constexpr std::array<std::string_view, 0> invariant_names{};
    static constexpr std::array<std::string_view, 0> invariant_scale_defs{};

    double gamma = 0.1, lambda = 1.0, f = 1.0, q0 = 0.0, p0 = 0.0;

    // Ranges: γ, λ ≤ 1e3 keep the certified reference non-stiff enough to finish.
    static std::vector<Param<DrivenPendulum>> param_table() {
        return {
            {{"gamma", 0.1, Range::closed(0.0, 1e3), "damping γ"}, &DrivenPendulum::gamma},
            {{"lambda", 1.0, Range::closed(1e-6, 1e3), "λ, λ² = g/(lΩ²)"}, &DrivenPendulum::lambda},
            {{"f", 1.0, Range::symmetric(1e6), "driving amplitude f of f sin t"},
             &DrivenPendulum::f},
            {{"q0", 0.0, Range::symmetric(1e6), "initial angle"}, &DrivenPendulum::q0},
            {{"p0", 0.0, Range::symmetric(1e6), "initial angular velocity"}, &DrivenPendulum::p0}};
    }

    static constexpr int static_n = 1; // degrees of freedom (core/problem.hpp)
    int n() const { return static_n; }
    Vec initial_state() const { return Vec{{q0, p0}}; }

    template <class In, class Out>
    void force(double t, const In& q, Out& out) const {
        out[0] = -lambda * lambda * std::sin(q[0]) + f * std::sin(t);
    }
    template <class In, class Out>
    void force_jacobian(double, const In& q, Out& out) const {
        out(0, 0) = -lambda * lambda * std::cos(q[0]);
    }

    void invariants(double, const Vec&, double*) const {}
    void invariant_scales(double, const Vec&, double*) const {}
    // Period of the forcing f sin t: Poincaré sections at t = 2πk (B Fig 3.5).
    double forcing_period() const { return 2.0 * M_PI; }
};

} // namespace dampsym
