// B(2.30), B(2.31), B(2.23) and B Thm 2.10 on exponential RK coefficient data; see the header.
#include "methods/exponential_conditions.hpp"

#include <algorithm>
#include <cmath>

namespace dampsym {

// B(2.30) is B(2.23) of the pair (t, t): its first condition vanishes identically, its second is
// (2.30) term for term.
double erk_condition_residual(const ExponentialTableau& t) {
    return perk_condition_residual(t, t);
}

double erk_condition_residual(const ExponentialRKData& data, double gamma_h) {
    ExponentialTableau t;
    erk_coefficients(data, gamma_h, t);
    return erk_condition_residual(t);
}

double erk_phi0_residual(const ExponentialRKData& data, double gamma_h) {
    ExponentialTableau t;
    erk_coefficients(data, gamma_h, t);
    return std::abs(t.phi0 - std::exp(-gamma_h));
}

double perk_condition_residual(const ExponentialTableau& q, const ExponentialTableau& p) {
    double worst = 0.0;
    for (int i = 0; i < q.stages; ++i) {
        const double first = q.b[i] * (p.phi0 / p.phi[i]) - p.b[i] * (q.phi0 / q.phi[i]);
        worst = std::max(worst, std::abs(first));
        for (int j = 0; j < q.stages; ++j) {
            const double second = q.b[i] * p.A(i, j) * (p.phi0 / p.phi[i]) +
                                  p.b[j] * q.A(j, i) * (q.phi0 / q.phi[j]) - q.b[i] * p.b[j];
            worst = std::max(worst, std::abs(second));
        }
    }
    return worst;
}

double perk_condition_residual(const PartitionedExponentialRKData& data, double gamma_h) {
    ExponentialTableau q, p;
    perk_coefficients(data, gamma_h, q, p);
    return perk_condition_residual(q, p);
}

double perk_phi0_residual(const PartitionedExponentialRKData& data, double gamma_h) {
    ExponentialTableau q, p;
    perk_coefficients(data, gamma_h, q, p);
    return std::abs(q.phi0 * p.phi0 - std::exp(-2.0 * gamma_h)); // e^{−γ_B h}, γ_B = 2γ
}

} // namespace dampsym
