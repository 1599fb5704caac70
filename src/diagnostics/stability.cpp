#include "diagnostics/stability.hpp"

#include <cmath>

namespace dampsym {

OneStepAnalysis analyse_one_step(const Mat& M, double gamma, double h) {
    OneStepAnalysis a;
    a.finite = M.allFinite();
    if (!a.finite || M.rows() != 2) {
        a.det = a.half_trace = a.spectral_radius = std::numeric_limits<double>::quiet_NaN();
        a.eig[0] = a.eig[1] = {a.det, 0.0};
        return a;
    }
    a.det = M(0, 0) * M(1, 1) - M(0, 1) * M(1, 0);
    a.half_trace = 0.5 * (M(0, 0) + M(1, 1));
    // λ± = ½tr ± sqrt((½tr)² − det)  (F(3.4))
    const std::complex<double> disc =
        std::sqrt(std::complex<double>(a.half_trace * a.half_trace - a.det, 0.0));
    a.eig[0] = a.half_trace + disc;
    a.eig[1] = a.half_trace - disc;
    a.spectral_radius = std::max(std::abs(a.eig[0]), std::abs(a.eig[1]));
    a.F_condition = std::abs(a.half_trace) < std::exp(-gamma * h);
    constexpr double tol = 1e-12;
    if (a.spectral_radius < 1.0 - tol) {
        a.power_bounded = true;
    } else if (a.spectral_radius <= 1.0 + tol) {
        // On the unit circle: bounded only if M is diagonalizable (distinct eigenvalues, or M =
        // λI).
        const bool distinct = std::abs(a.eig[0] - a.eig[1]) > 1e-8;
        const bool scalar =
            std::abs(M(0, 1)) + std::abs(M(1, 0)) + std::abs(M(0, 0) - M(1, 1)) < 1e-14;
        a.power_bounded = distinct || scalar;
    } else {
        a.power_bounded = false;
    }
    return a;
}

std::complex<double> rk_stability_function(const ButcherTableau& t, std::complex<double> z) {
    using CMat = Eigen::MatrixXcd;
    using CVec = Eigen::VectorXcd;
    const int s = t.stages;
    CMat I_zA = CMat::Identity(s, s);
    for (int i = 0; i < s; ++i)
        for (int j = 0; j < s; ++j) I_zA(i, j) -= z * t.A(i, j);
    const CVec k = I_zA.partialPivLu().solve(CVec::Ones(s)); // (I − zA)⁻¹1
    std::complex<double> bk = 0.0;
    for (int i = 0; i < s; ++i) bk += t.b[static_cast<std::size_t>(i)] * k[i];
    return 1.0 + z * bk;
}

RKPowerAnalysis rk_power_analysis(const ButcherTableau& t, double omega, double gamma, double h) {
    // λ± = −γ ± sqrt((γ − ω)(γ + ω)): complex pair (under-damped), double (critical) or real.
    const std::complex<double> root =
        std::sqrt(std::complex<double>((gamma - omega) * (gamma + omega), 0.0));
    const std::complex<double> r1 = rk_stability_function(t, h * (-gamma + root));
    const std::complex<double> r2 = rk_stability_function(t, h * (-gamma - root));
    RKPowerAnalysis a;
    a.spectral_radius = std::max(std::abs(r1), std::abs(r2));
    constexpr double tol = 1e-12; // as analyse_one_step
    if (a.spectral_radius < 1.0 - tol)
        a.power_bounded = true;
    else if (a.spectral_radius <= 1.0 + tol)
        a.power_bounded = omega != gamma && std::abs(r1 - r2) > 1e-8; // A diagonalizable
    return a;
}

} // namespace dampsym
