// The outer solar system, HLW I.2: the Sun and the five outer planets (Jupiter, Saturn, Uranus,
// Neptune, Pluto) as a 3-D gravitational N-body problem with Hamiltonian HLW(2.10)
//   H = ½ Σ_{i=0}^{5} |p_i|²/m_i − G Σ_{i=1}^{5} Σ_{j=0}^{i−1} m_i m_j / |q_i − q_j|,
// damped as in conventions §1 (p_i' = −∇_{q_i}V − 2γ p_i; default γ = 0, HLW's conservative
// problem). HLW's units: masses relative to the Sun, distances in astronomical units, times in
// earth days, so γ is per day. G = 2.95912208286e−4, m0 = 1.00000597682 (the Sun with the inner
// planets). Data of HLW Table 2.2 (5 September 1994, 0h00): positions q_i(0) and velocities q̇_i(0);
// the momenta are p_i = m_i q̇_i(0). The Sun starts at rest at the origin. HLW integrate with h = 10
// days over 200 000 days (Fig. 2.3). Built on NBodySystem (src/problems/nbody.hpp): gravity, d = 3,
// N = 6, body 0 = Sun, 1 = Jupiter, ..., 5 = Pluto; state z = [q_0..q_5; p_0..p_5].
#pragma once

#include "problems/nbody.hpp"

#include <array>
#include <cstddef>
#include <string_view>
#include <vector>

namespace dampsym {

struct OuterSolarSystem : NBodyProblem<OuterSolarSystem> {
    static constexpr std::string_view id = "outer-solar-system";
    static constexpr OrbitFigure figure_orbit =
        OrbitFigure::by_default; // its figures draw the orbit
    static constexpr std::string_view title =
        "outer solar system, Sun + 5 planets, HLW(2.10), HLW Table 2.2";
    static constexpr bool has_exact = false;

    static constexpr double G_hlw = 2.95912208286e-4; // AU³ / (solar mass · day²)
    static constexpr double sun_mass = 1.00000597682; // m0
    // HLW Table 2.2, bodies 1..5 (Jupiter, Saturn, Uranus, Neptune, Pluto).
    static constexpr std::array<double, 5> planet_mass{
        0.000954786104043, 0.000285583733151, 0.0000437273164546, 0.0000517759138449, 1.0 / 1.3e8};
    static constexpr std::array<std::array<double, 3>, 5> planet_position{
        {{-3.5023653, -3.8169847, -1.5507963},     // Jupiter
         {9.0755314, -3.0458353, -1.6483708},      // Saturn
         {8.3101420, -16.2901086, -7.2521278},     // Uranus
         {11.4707666, -25.7294829, -10.8169456},   // Neptune
         {-15.5387357, -25.2225594, -3.1902382}}}; // Pluto
    static constexpr std::array<std::array<double, 3>, 5> planet_velocity{
        {{0.00565429, -0.00412490, -0.00190589},   // Jupiter
         {0.00168318, 0.00483525, 0.00192462},     // Saturn
         {0.00354178, 0.00137102, 0.00055029},     // Uranus
         {0.00288930, 0.00114527, 0.00039677},     // Neptune
         {0.00276725, -0.00170702, -0.00136504}}}; // Pluto

    static std::vector<ParamSpec> param_specs() {
        return {{"gamma", 0.0, Range::closed(0.0, 1e3), "damping γ per day"}};
    }
    static OuterSolarSystem from_params(const ParamMap& m) {
        OuterSolarSystem o;
        o.gamma = m.at("gamma");
        return o;
    }

    OuterSolarSystem() {
        sys.d = 3;
        sys.kind = PairPotential::gravity;
        sys.G = G_hlw;
        sys.m = {sun_mass};
        q0.assign(3, 0.0); // the Sun: q0(0) = 0, q̇0(0) = 0
        p0.assign(3, 0.0);
        for (std::size_t i = 0; i < planet_mass.size(); ++i) {
            sys.m.push_back(planet_mass[i]);
            for (std::size_t k = 0; k < 3; ++k) {
                q0.push_back(planet_position[i][k]);
                p0.push_back(planet_mass[i] * planet_velocity[i][k]);
            }
        }
    }
};

} // namespace dampsym
