// Coefficient functions of the exponential RK families; equations and the γ conversion are in
// exponential_tableaux.hpp.
#include "methods/exponential_tableaux.hpp"

#include "methods/integrating_factor.hpp"
#include "methods/tableaux.hpp"

#include <cmath>
#include <stdexcept>

namespace dampsym {

double exprel(double x) {
    // (e^x − 1)/x = 1 + x/2 + x²/6 + x³/24 + …; below 1e−7 the x³ term is < 1e−22 (relative).
    if (std::abs(x) < 1e-7) return 1.0 + x * (0.5 + x / 6.0);
    return std::expm1(x) / x;
}

double sinh_half_over(double x) {
    // sinh(x/2)/x = ½ + x²/48 + x⁴/3840 + …; below 1e−7 the x⁴ term is < 1e−31.
    if (std::abs(x) < 1e-7) return 0.5 + x * x / 48.0;
    return std::sinh(0.5 * x) / x;
}

void erk_coefficients(const ExponentialRKData& data, double gamma_h, ExponentialTableau& out) {
    out.resize(data.stages);
    data.coefficients(data, gamma_h, out); // x = γh: ERK data is in our γ (B(1.1) convention)
}

void perk_coefficients(const PartitionedExponentialRKData& data, double gamma_h,
                       ExponentialTableau& hat_q, ExponentialTableau& tilde_p) {
    hat_q.resize(data.stages);
    tilde_p.resize(data.stages);
    // B(2.17)–(2.22) write p' = −∇V − γ_B p; ours is p' = −∇V − 2γp (conventions §1), so γ_B = 2γ
    // and B's argument γ_B h is 2γh. This is the only place where B's γ is converted.
    const double x_B = 2.0 * gamma_h;
    data.coefficients_B(x_B, hat_q, tilde_p);
}

namespace {

// ---- ERK ----

// B(2.13), x = γh.
void etdrk2_coefficients(const ExponentialRKData&, double x, ExponentialTableau& t) {
    t.c[0] = 0.5;
    t.A(0, 0) = sinh_half_over(x); // (e^{x/2} − e^{−x/2})/(2x) = 2 sinh(x/2)/(2x)
    t.phi[0] = std::exp(-0.5 * x);
    t.b[0] = exprel(-x); // (1 − e^{−x})/x
    t.phi0 = std::exp(-x);
}

// B(2.5) with constant γ: a_ij = α_ij e^{−(c_i−c_j)x}, φ_i = e^{−c_i x}, b_i = β_i e^{−(1−c_i)x},
// φ_0 = e^{−x}: the one integrating-factor formula (integrating_factor.hpp) with x(a, b) = (b −
// a)x.
void integrating_factor_coefficients(const ExponentialRKData& d, double x, ExponentialTableau& t) {
    const ButcherTableau& u = *d.underlying;
    IntegratingFactors f;
    integrating_factors(
        u, [x](double a, double b) { return (b - a) * x; }, f);
    for (int i = 0; i < u.stages; ++i) {
        t.c[i] = u.c[static_cast<std::size_t>(i)];
        t.phi[i] = f.phi[i];
        t.b[i] = u.b[static_cast<std::size_t>(i)] * f.F[i];
        for (int j = 0; j < u.stages; ++j)
            t.A(i, j) = u.A(i, j) == 0.0 ? 0.0 : u.A(i, j) * f.E(i, j);
    }
    t.phi0 = f.phi0;
}

// ---- PERK, all in B's x_B = γ_B h ----

// Symplectic-Euler skeleton of B(2.18)/(2.19): Q_1 = q_n, P_1 = p_{n+1}.
void symplectic_euler_hat(ExponentialTableau& q) {
    q.c[0] = 0.0;
    q.A(0, 0) = 0.0;
    q.phi[0] = 1.0;
    q.b[0] = 1.0;
    q.phi0 = 1.0;
}

// B(2.18).
void cse_if_coefficients(double xB, ExponentialTableau& q, ExponentialTableau& p) {
    symplectic_euler_hat(q);
    const double e = std::exp(-xB);
    p.c[0] = 1.0;
    p.A(0, 0) = 1.0;
    p.phi[0] = e;
    p.b[0] = 1.0;
    p.phi0 = e;
}

// B(2.19): (1/γ_B)(e^{−x_B} − 1)∇V = −h (1 − e^{−x_B})/x_B ∇V = h exprel(−x_B) F.
void cse_etd_coefficients(double xB, ExponentialTableau& q, ExponentialTableau& p) {
    symplectic_euler_hat(q);
    const double e = std::exp(-xB);
    const double w = exprel(-xB);
    p.c[0] = 1.0;
    p.A(0, 0) = w;
    p.phi[0] = e;
    p.b[0] = w;
    p.phi0 = e;
}

// 2-stage Lobatto IIIA for q (trapezoidal rule), the hat tableau of B(2.20) and B(2.22).
void lobatto_iiia_hat(ExponentialTableau& q) {
    q.c[0] = 0.0;
    q.c[1] = 1.0;
    q.A(1, 0) = 0.5;
    q.A(1, 1) = 0.5;
    q.phi[0] = 1.0;
    q.phi[1] = 1.0;
    q.b[0] = 0.5;
    q.b[1] = 0.5;
    q.phi0 = 1.0;
}

// B(2.20).
void csv1_perk_coefficients(double xB, ExponentialTableau& q, ExponentialTableau& p) {
    lobatto_iiia_hat(q);
    const double e = std::exp(-0.5 * xB);
    p.c[0] = p.c[1] = 0.5;
    p.A(0, 0) = p.A(1, 0) = 0.5;
    p.phi[0] = p.phi[1] = e;
    p.b[0] = p.b[1] = 0.5 * e;
    p.phi0 = std::exp(-xB);
}

// B(2.21), with the factor e^{−x_B/4} of F(2.16) in the second row of Â and in b̂ (header).
void csv2_perk_coefficients(double xB, ExponentialTableau& q, ExponentialTableau& p) {
    const double e4 = std::exp(-0.25 * xB);
    const double e2 = std::exp(-0.5 * xB);
    const double kappa = 2.0 * e4 / (4.0 - xB);
    const double rho = (4.0 + xB) / (4.0 - xB) * e2;
    q.c[0] = 0.0;
    q.c[1] = 1.0;
    q.A(1, 0) = q.A(1, 1) = kappa;
    q.phi[0] = 1.0;
    q.phi[1] = rho;
    q.b[0] = q.b[1] = kappa;
    q.phi0 = rho;
    const double ap = 2.0 / (4.0 + xB);
    p.c[0] = p.c[1] = 0.5;
    p.A(0, 0) = p.A(1, 0) = ap;
    p.phi[0] = p.phi[1] = 4.0 * e4 / (4.0 + xB);
    p.b[0] = (4.0 - xB) / (4.0 + xB) * e4 * 0.5;
    p.b[1] = 0.5 * e4;
    p.phi0 = (4.0 - xB) / (4.0 + xB) * e2;
}

// B(2.22): α = (1 − e^{−x_B/2})/x_B = ½ exprel(−x_B/2).
void etdprk2_coefficients(double xB, ExponentialTableau& q, ExponentialTableau& p) {
    lobatto_iiia_hat(q);
    const double e = std::exp(-0.5 * xB);
    const double alpha = 0.5 * exprel(-0.5 * xB);
    p.c[0] = p.c[1] = 0.5;
    p.A(0, 0) = p.A(1, 0) = alpha;
    p.phi[0] = p.phi[1] = e;
    p.b[0] = p.b[1] = 0.5 * e;
    p.phi0 = std::exp(-xB);
}

} // namespace

const ExponentialRKData& etdrk2_data() {
    static const ExponentialRKData d{"etdrk2", "B(2.13)", "etd", 1, nullptr, etdrk2_coefficients};
    return d;
}

const ExponentialRKData& if_gauss_data(int s) {
    static const ExponentialRKData d[3] = {
        {"if-gauss1", "B(2.5), B(2.11)", "integrating-factor", 1, &gauss_tableau(1),
         integrating_factor_coefficients},
        {"if-gauss2", "B(2.5), B(2.12)", "integrating-factor", 2, &gauss_tableau(2),
         integrating_factor_coefficients},
        {"if-gauss3", "B(2.5), 3-stage Gauss", "integrating-factor", 3, &gauss_tableau(3),
         integrating_factor_coefficients},
    };
    if (s < 1 || s > 3) throw std::out_of_range("if_gauss_data: s must be 1, 2 or 3");
    return d[s - 1];
}

const PartitionedExponentialRKData& cse_if_data() {
    static const PartitionedExponentialRKData d{"cse-if", "B(2.18)", "integrating-factor", 1,
                                                cse_if_coefficients};
    return d;
}
const PartitionedExponentialRKData& cse_etd_data() {
    static const PartitionedExponentialRKData d{"cse-etd", "B(2.19)", "etd", 1,
                                                cse_etd_coefficients};
    return d;
}
const PartitionedExponentialRKData& csv1_perk_data() {
    static const PartitionedExponentialRKData d{"csv1-perk", "B(2.20)", "integrating-factor", 2,
                                                csv1_perk_coefficients};
    return d;
}
const PartitionedExponentialRKData& csv2_perk_data() {
    static const PartitionedExponentialRKData d{"csv2-perk", "B(2.21), F(2.16)",
                                                "integrating-factor", 2, csv2_perk_coefficients};
    return d;
}
const PartitionedExponentialRKData& etdprk2_data() {
    static const PartitionedExponentialRKData d{"etdprk2", "B(2.22)", "etd", 2,
                                                etdprk2_coefficients};
    return d;
}

} // namespace dampsym
