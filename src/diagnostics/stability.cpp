#include "diagnostics/stability.hpp"

#include <cmath>

namespace dampsym {
namespace {

// ---- F ch.3 closed forms on the oscillator (our γ) ----
double beta2(double w, double g) {
    return (w - g) * (w + g);
}

// F(3.10): ½trM = e^{−γh}(1 − h²β²/4)/(1 + h²β²/4).
double cimp_half_trace(double w, double g, double h) {
    const double x = 0.25 * h * h * beta2(w, g);
    return std::exp(-g * h) * (1.0 - x) / (1.0 + x);
}
// F(3.12): ω > γ.
bool cimp_condition(double w, double g, double) {
    return w > g;
}
double cimp_h4(double w, double g) {
    return beta2(w, g) * beta2(w, g) / 12.0;
}

// F(3.15): ½trM = e^{−γh}(1 − h²ω²/2) cosh(γh).
double csv1_half_trace(double w, double g, double h) {
    return std::exp(-g * h) * (1.0 - 0.5 * h * h * w * w) * std::cosh(g * h);
}
// F(3.17): 1 − sech(γh) < h²ω²/2 < 1 + sech(γh).
bool csv1_condition(double w, double g, double h) {
    const double x = 0.5 * h * h * w * w;
    const double sech = 1.0 / std::cosh(g * h);
    return 1.0 - sech < x && x < 1.0 + sech;
}
double csv1_h4(double w, double g) {
    return w * w * (w * w + 4.0 * g * g) / 24.0;
}

// F(3.20): ½trM = e^{−γh}[(4+γ²h²)/(4−γ²h²) − 2h²ω² cosh(γh/2)/(4−γ²h²)].
double csv2_half_trace(double w, double g, double h) {
    const double gh2 = g * g * h * h;
    return std::exp(-g * h) *
           ((4.0 + gh2) / (4.0 - gh2) - 2.0 * h * h * w * w * std::cosh(0.5 * g * h) / (4.0 - gh2));
}
// F(3.22): γ² sech(γh/2) < ω² < 4 sech(γh/2)/h², derived by F multiplying |½trM| < e^{−γh} by
// 4 − γ²h², i.e. assuming γh < 2. For γh > 2 that factor is negative and the same condition on
// F(3.20) reverses to 4 sech(γh/2)/h² < ω² < γ² sech(γh/2); at γh = 2 the scheme is undefined.
bool csv2_condition(double w, double g, double h) {
    const double sech = 1.0 / std::cosh(0.5 * g * h);
    const double lo = g * g * sech, hi = 4.0 * sech / (h * h);
    if (g * h < 2.0) return lo < w * w && w * w < hi;
    if (g * h > 2.0) return hi < w * w && w * w < lo;
    return false;
}
double csv2_h4(double w, double g) {
    return (2.0 * w * w * w * w + 5.0 * g * g * w * w - 4.0 * g * g * g * g) / 48.0;
}

} // namespace

OscillatorFormulas oscillator_formulas(std::string_view method_id) {
    if (method_id == "cimp") return {cimp_half_trace, cimp_condition, cimp_h4, "F(3.10), F(3.12)"};
    if (method_id == "csv1" || method_id == "csv1-perk")
        return {csv1_half_trace, csv1_condition, csv1_h4, "F(3.15), F(3.17)"};
    if (method_id == "csv2" || method_id == "csv2-perk")
        return {csv2_half_trace, csv2_condition, csv2_h4, "F(3.20), F(3.22)"};
    return {};
}

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
