#include "reference/kepler_exact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace dampsym {
namespace {

// 2π = kTwoPi1 + kTwoPi2: kTwoPi1 = fl(2π) = 2 fl(π), kTwoPi2 = 2(π − fl(π)) (fl(π) < π).
constexpr double kTwoPi1 = 6.283185307179586;
constexpr double kTwoPi2 = 2.4492935982947064e-16;
constexpr double kPi = 3.141592653589793;

// E − sin E without cancellation.
double e_minus_sin(double E) {
    if (std::abs(E) >= 1.0) return E - std::sin(E);
    // Σ_{k≥1} (−1)^{k+1} E^{2k+1}/(2k+1)!; 9 terms reach round-off for |E| < 1.
    const double E2 = E * E;
    double term = E * E2 / 6.0, sum = 0.0;
    for (int k = 1; k <= 9; ++k) {
        sum += term;
        term *= -E2 / static_cast<double>((2 * k + 2) * (2 * k + 3));
    }
    return sum;
}

// 2 sin²(E/2) = 1 − cos E without cancellation.
double one_minus_cos(double E) {
    const double s = std::sin(0.5 * E);
    return 2.0 * s * s;
}

} // namespace

double kepler_mean_anomaly(double t) {
    const double k = std::nearbyint(t / kTwoPi1);
    // t − k C1 exactly rounded once (fma), then the tail − k C2.
    double M = std::fma(-k, kTwoPi1, t) - k * kTwoPi2;
    // k from the rounded quotient can be off by one at the ±π boundary; fold back.
    if (M > kPi) M = (M - kTwoPi1) - kTwoPi2;
    if (M < -kPi) M = (M + kTwoPi1) + kTwoPi2;
    return M;
}

double kepler_eccentric_anomaly(double e, double M) {
    if (!(e >= 0.0 && e < 1.0)) throw std::invalid_argument("kepler: need 0 <= e < 1");
    M = kepler_mean_anomaly(M);
    if (e == 0.0 || M == 0.0) return M;
    const double sign = M < 0.0 ? -1.0 : 1.0;
    const double m = std::abs(M); // in (0, π]
    // f(E) = E − e sin E − m is increasing and convex on [0, π]; f(min(m + e, π)) ≥ 0, so Newton
    // from there decreases monotonically to the root. Stop when the step no longer decreases E.
    double E = std::min(m + e, kPi);
    for (int it = 0; it < 100; ++it) {
        const double f = (1.0 - e) * E + e * e_minus_sin(E) - m;
        const double fp = (1.0 - e) + e * one_minus_cos(E);
        const double step = f / fp;
        const double next = E - step;
        if (!(step > 0.0) || !(next < E)) break;
        E = next;
    }
    return sign * E;
}

KeplerState kepler_exact(double e, double t) {
    const double E = kepler_eccentric_anomaly(e, t);
    const double root = std::sqrt((1.0 - e) * (1.0 + e)); // √(1−e²) = L0
    const double omc = one_minus_cos(E);
    const double sE = std::sin(E), cE = std::cos(E);
    const double r = (1.0 - e) + e * omc; // 1 − e cos E
    return {(1.0 - e) - omc, root * sE, -sE / r, root * cE / r};
}

KeplerState kepler_propagate(const KeplerState& z0, double dt) {
    if (dt == 0.0) return z0;
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    const double r0 = std::hypot(z0.q1, z0.q2);
    const double v2 = z0.p1 * z0.p1 + z0.p2 * z0.p2;
    const double H = 0.5 * v2 - 1.0 / r0;
    if (!(H < 0.0) || !(r0 > 0.0)) return {nan, nan, nan, nan};
    const double a = -0.5 / H;
    const double sa = std::sqrt(a);
    const double n = 1.0 / (a * sa);
    const double sigma0 = z0.q1 * z0.p1 + z0.q2 * z0.p2;
    const double ecos0 = 1.0 - r0 / a, esin0 = sigma0 / sa;
    const double e = std::hypot(ecos0, esin0);
    if (!(e < 1.0)) return {nan, nan, nan, nan};
    const double E0 = (ecos0 == 0.0 && esin0 == 0.0) ? 0.0 : std::atan2(esin0, ecos0);
    const double M = (E0 - esin0) + n * dt;
    const double dE = kepler_eccentric_anomaly(e, M) - E0;
    const double omc = one_minus_cos(dE), sdE = std::sin(dE);
    const double f = 1.0 - (a / r0) * omc;
    const double g = sa * r0 * sdE + a * sigma0 * omc;
    const double r = r0 + (a - r0) * omc + sigma0 * sa * sdE;
    const double fd = -sa * sdE / (r * r0);
    const double gd = 1.0 - (a / r) * omc;
    return {f * z0.q1 + g * z0.p1, f * z0.q2 + g * z0.p2, fd * z0.q1 + gd * z0.p1,
            fd * z0.q2 + gd * z0.p2};
}

} // namespace dampsym
