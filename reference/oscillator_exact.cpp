#include "reference/oscillator_exact.hpp"

#include <cmath>

namespace dampsym {

DampedCS oscillator_damped_cs(double omega, double gamma, double t) {
    const double beta2 = (omega - gamma) * (omega + gamma);
    const double x = beta2 * t * t;
    if (std::abs(x) <= 0.5) {
        // C = Σ (−x)^k/(2k)!, S/t = Σ (−x)^k/(2k+1)!; |x| ≤ ½ gives < 1e-17 after 10 terms.
        double c = 0.0;
        double s = 0.0;
        double term_c = 1.0;
        double term_s = 1.0;
        for (int k = 0; k < 12; ++k) {
            c += term_c;
            s += term_s;
            term_c *= -x / ((2.0 * k + 1.0) * (2.0 * k + 2.0));
            term_s *= -x / ((2.0 * k + 2.0) * (2.0 * k + 3.0));
        }
        const double e = std::exp(-gamma * t);
        return {e * c, e * s * t};
    }
    if (beta2 > 0.0) {
        const double beta = std::sqrt(beta2);
        const double e = std::exp(-gamma * t);
        return {e * std::cos(beta * t), e * std::sin(beta * t) / beta};
    }
    // Over-damped: κ = sqrt(γ² − ω²); γ − κ = ω²/(γ + κ) avoids cancellation.
    const double kappa = std::sqrt(-beta2);
    const double slow = std::exp(-(omega * omega / (gamma + kappa)) * t); // e^{-(γ−κ)t}
    const double fast = std::exp(-(gamma + kappa) * t);                   // e^{-(γ+κ)t}
    return {0.5 * (slow + fast), 0.5 * (slow - fast) / kappa};
}

OscillatorState oscillator_exact(double omega, double gamma, double q0, double p0, double t) {
    const DampedCS cs = oscillator_damped_cs(omega, gamma, t);
    return {q0 * cs.c + (p0 + gamma * q0) * cs.s,
            p0 * cs.c - (gamma * p0 + omega * omega * q0) * cs.s};
}

} // namespace dampsym
