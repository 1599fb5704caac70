// Frozen argon crystal, HLW I.3: seven argon atoms in a plane, six arranged around a centre atom,
// the N-body Hamiltonian HLW(3.1) with the Lennard-Jones pair potential HLW(3.2)
//   V_ij(r) = 4ε[(σ/r)^12 − (σ/r)^6],   ε = 119.8 k_B [J],  σ = 0.341 [nm],
// m_i = m = 66.34·10^−27 [kg], k_B = 1.380658·10^−23 [J/K], initial values of HLW Table 3.1
// (positions in nm, velocities in nm/ns; p_i = m q̇_i(0)), damped as in conventions §1
// (p_i' = −∇_{q_i}V − 2γp_i; default γ = 0, HLW's conservative problem).
// Units exactly as HLW: masses in kg, distances in nm, times in ns; energies then come out in
// kg·nm²/ns² = J, velocities in nm/ns = m/s, and γ is per ns. HLW integrate over 0.2 ns with steps
// of a few fs (1 fs = 10^−6 ns) and report H(p0, q0) ≈ −1260.2 k_B [J] and T0 ≈ 22.72 K.
// Temperature HLW(3.8): T = (1/(2N k_B)) Σ m_i |q̇_i|² = (1/(2N k_B)) Σ |p_i|²/m_i [K].
// Scale warning: in these units the momenta are O(10^−24) and energies O(10^−21) while positions
// are O(0.1), so absolute error tolerances (e.g. a GSL epsabs of 1e−13) do not control p at all;
// compare p relative to its own scale (or energies divided by k_B, as HLW Fig. 3.1 does).
// Built on NBodySystem (src/problems/nbody.hpp): Lennard-Jones, d = 2, N = 7.
#pragma once

#include "problems/nbody.hpp"

#include <array>
#include <cstddef>
#include <string_view>
#include <vector>

namespace dampsym {

struct Argon : NBodyProblem<Argon> {
    static constexpr std::string_view id = "argon";
    static constexpr std::string_view title =
        "frozen argon crystal, 7 atoms, Lennard-Jones HLW(3.2), HLW Table 3.1 (kg, nm, ns)";
    static constexpr bool has_exact = false;
    static constexpr bool has_temperature = true;

    static constexpr int atoms = 7;
    static constexpr double k_B = 1.380658e-23;    // Boltzmann's constant [J/K] (HLW I.3)
    static constexpr double mass = 66.34e-27;      // m [kg]
    static constexpr double epsilon = 119.8 * k_B; // ε [J]
    static constexpr double sigma = 0.341;         // σ [nm]
    // HLW Table 3.1: positions [nm] and velocities [nm/ns], atoms 1..7.
    static constexpr std::array<std::array<double, 2>, atoms> position{{{0.00, 0.00},
                                                                        {0.02, 0.39},
                                                                        {0.34, 0.17},
                                                                        {0.36, -0.21},
                                                                        {-0.02, -0.40},
                                                                        {-0.35, -0.16},
                                                                        {-0.31, 0.21}}};
    static constexpr std::array<std::array<double, 2>, atoms> velocity{{{-30.0, -20.0},
                                                                        {50.0, -90.0},
                                                                        {-70.0, -60.0},
                                                                        {90.0, 40.0},
                                                                        {80.0, 90.0},
                                                                        {-40.0, 100.0},
                                                                        {-80.0, -60.0}}};

    static std::vector<ParamSpec> param_specs() {
        return {{"gamma", 0.0, Range::closed(0.0, 1e3), "damping γ per ns"}};
    }
    static Argon from_params(const ParamMap& m) {
        Argon o;
        o.gamma = m.at("gamma");
        return o;
    }

    Argon() {
        sys.d = 2;
        sys.kind = PairPotential::lennard_jones;
        sys.eps = epsilon;
        sys.sigma = sigma;
        sys.m.assign(atoms, mass);
        for (std::size_t i = 0; i < atoms; ++i) {
            for (std::size_t k = 0; k < 2; ++k) {
                q0.push_back(position[i][k]);
                p0.push_back(mass * velocity[i][k]);
            }
        }
    }

    // HLW(3.8): T = (1/(2N k_B)) Σ m_i |q̇_i|², q̇_i = p_i/m_i, in kelvin.
    double temperature(const Vec& z) const {
        return 2.0 * kinetic_energy(z) / (2.0 * static_cast<double>(sys.bodies()) * k_B);
    }
};

} // namespace dampsym
