// Which optional diagnostics a problem type supports, detected from what its header declares. The
// runner and the case validator ask these; a problem gains a diagnostic by declaring the hook.
#pragma once

#include "core/types.hpp"

#include <array>

namespace dampsym {

// Total linear momentum Σp_i and angular momentum Σq_i×p_i (B Ex. 1.3, B Table 3.1).
template <class P>
concept HasMomentum = requires(const P& p, const Vec& z, Vec& out) {
    { p.space_dim() } -> std::convertible_to<int>;
    p.linear_momentum(z, out);
    p.angular_momentum(z, out);
};

// Energy balance d/dt H = −2γ(t) p·∇T(p) (B(3.4) for the pendulum): needs the separable form,
// an energy and a potential that does not depend on t (no forcing).
template <class P>
concept HasEnergyBalance = P::has_separable && P::has_energy && requires {
    P::autonomous_potential;
} && P::autonomous_potential;

// Temperature, HLW(3.8).
template <class P>
concept HasTemperature = requires(const P& p, const Vec& z) {
    { p.temperature(z) } -> std::convertible_to<double>;
};

// Period of a time-periodic forcing, for Poincaré sections at t = t0 + kT (B §3.2.2).
template <class P>
concept HasForcingPeriod = requires(const P& p) {
    { p.forcing_period() } -> std::convertible_to<double>;
};

// One degree of freedom whose q' does not depend on t explicitly: oscillation maxima of q for
// d(t) = ln(max q) + Γ(t) (F(4.4)) are located with the vector field's q' and q''.
template <class P>
concept HasOneDofMaxima = requires(const P& p) {
    p.n();
}
&&P::has_separable;

} // namespace dampsym
