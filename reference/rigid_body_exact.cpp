#include "reference/rigid_body_exact.hpp"

#include "reference/gsl_reference.hpp"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_integration.h>
#include <gsl/gsl_sf_ellint.h>
#include <gsl/gsl_sf_elljac.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>

namespace dampsym {
namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();
constexpr double pi_hi = 3.141592653589793116;      // double(π)
constexpr double pi_lo = 1.2246467991473532072e-16; // π − double(π)

// 20-point Gauss–Legendre nodes and weights (GSL's precomputed table), allocated once.
const gsl_integration_glfixed_table* gauss_legendre20() {
    static const gsl_integration_glfixed_table* table = gsl_integration_glfixed_table_alloc(20);
    return table;
}

// 1/Ia − 1/Ib without cancellation.
double inv_diff(double Ia, double Ib) {
    return (Ib - Ia) / (Ia * Ib);
}

bool is_even(const std::array<int, 3>& p) {
    return (p[0] == 0 && p[1] == 1 && p[2] == 2) || (p[0] == 1 && p[1] == 2 && p[2] == 0) ||
           (p[0] == 2 && p[1] == 0 && p[2] == 1);
}

double carlson_rf(double x, double y, double z, bool& ok) {
    gsl_sf_result r;
    if (gsl_sf_ellint_RF_e(x, y, z, GSL_PREC_DOUBLE, &r) != GSL_SUCCESS) {
        ok = false;
        return nan;
    }
    return r.val;
}

// e^{−Γ(s)} = e^{−x sin 2s}, x = ε/4.
double exp_minus_gamma(double s, void* params) {
    const double x = *static_cast<const double*>(params);
    return std::exp(-x * std::sin(2.0 * s));
}

// sn, cn, dn(u|m) given m and m1 = 1 − m (both accurate). gsl_sf_elljac_e starts from
// sqrt(1 − m) formed from m, which loses the relative accuracy of 1 − m near m = 1 (and with it
// dn ≈ √m1 near u = K). For m1 < ½ the descending Landen transformation (A&S 16.12.2–4) is applied
// first, with k' = √m1 and μ = (1 − k')/(1 + k'), m' = μ², v = u/(1 + μ):
//   sn(u|m) = (1+μ) sn/(1 + μ sn²),  cn(u|m) = cn dn/(1 + μ sn²),
//   dn(u|m) = ((1−μ) + μ cn²)/(1 + μ sn²)      (all on the right at (v|m')),
// where 1 − μ = 2k'/(1+k') and 1 − m' = 4k'/(1+k')² are formed without cancellation. Each step
// maps k' to 2√k'/(1+k'), so a few steps reach m1 ≥ ½. At m1 = 0: sn = tanh u, cn = dn = sech u.
bool jacobi(double u, double m, double m1, double& sn, double& cn, double& dn) {
    if (m1 == 0.0) {
        sn = std::tanh(u);
        cn = dn = 1.0 / std::cosh(u);
        return true;
    }
    if (m1 >= 0.5) return gsl_sf_elljac_e(u, m, &sn, &cn, &dn) == GSL_SUCCESS;
    const double kc = std::sqrt(m1);
    const double mu = (1.0 - kc) / (1.0 + kc);
    const double one_minus_mu = 2.0 * kc / (1.0 + kc);
    const double m1_next = 4.0 * kc / ((1.0 + kc) * (1.0 + kc));
    double s, c, d;
    if (!jacobi(u / (1.0 + mu), mu * mu, m1_next, s, c, d)) return false;
    const double den = 1.0 + mu * s * s;
    sn = (1.0 + mu) * s / den;
    cn = c * d / den;
    dn = (one_minus_mu + mu * c * c) / den;
    return true;
}

} // namespace

FreeRigidBody::FreeRigidBody(const Vec3& I, const Vec3& y0) : y0_(y0) {
    gsl_errors_off();
    const int nonzero = (y0[0] != 0.0) + (y0[1] != 0.0) + (y0[2] != 0.0);
    if (nonzero <= 1) return; // 0 or a principal axis: an equilibrium (also the middle axis)

    // lo, mid, hi: a = 1/I increasing, i.e. I decreasing.
    std::array<int, 3> o{0, 1, 2};
    std::sort(o.begin(), o.end(), [&](int p, int q) { return I[p] > I[q]; });
    const int lo = o[0], mid = o[1], hi = o[2];
    if (I[lo] == I[mid] && I[mid] == I[hi]) return; // sphere: N ≡ 0
    if (I[lo] == I[mid] || I[mid] == I[hi]) {
        kind_ = Kind::symmetric;
        l_ = I[lo] == I[mid] ? hi : lo; // the distinct axis
        i_ = (l_ + 1) % 3;
        j_ = (l_ + 2) % 3;
        omega_ = inv_diff(I[l_], I[i_]) * y0[l_]; // (1/I_l − 1/I_i) y_l
        return;
    }

    kind_ = Kind::elliptic;
    const double d_mid_lo = inv_diff(I[mid], I[lo]); // a_mid − a_lo > 0
    const double d_hi_mid = inv_diff(I[hi], I[mid]); // a_hi − a_mid > 0
    const double d31 = inv_diff(I[hi], I[lo]);       // a_hi − a_lo (= b3 − b1 in both cases)
    const double delta = d_hi_mid * y0[hi] * y0[hi] - d_mid_lo * y0[lo] * y0[lo];
    double d21, d32, s;
    if (delta >= 0.0) {
        perm_ = {lo, mid, hi};
        s = 1.0;
        d21 = d_mid_lo;
        d32 = d_hi_mid;
    } else {
        perm_ = {hi, mid, lo};
        s = -1.0;
        d21 = d_hi_mid;
        d32 = d_mid_lo;
    }
    if ((is_even(perm_) ? 1.0 : -1.0) != s) sign_[1] = -1.0; // make det(R P) = s
    Vec3 w;
    for (int k = 0; k < 3; ++k) w[k] = sign_[k] * y0[perm_[k]];

    const double A1 = d31 * w[0] * w[0] + d32 * w[1] * w[1];
    const double A3 = d21 * w[1] * w[1] + d31 * w[2] * w[2];
    const double delta_b = std::max(0.0, d32 * w[2] * w[2] - d21 * w[0] * w[0]); // = |delta|
    m_ = std::min(1.0, d21 * A1 / (d32 * A3));
    m1_ = std::min(1.0, d31 * delta_b / (d32 * A3));
    lambda_ = std::sqrt(d32 * A3);
    const double alpha1 = A1 / d31, beta1 = A1 / d32, alpha3 = A3 / d31;
    const double s1 = w[0] >= 0.0 ? 1.0 : -1.0;
    const double s3 = w[2] >= 0.0 ? 1.0 : -1.0; // w3 ≠ 0 here: w3 = 0 with δ_b ≥ 0 forces w1 = 0
    c1_ = s1 * std::sqrt(alpha1);
    c2_ = -s1 * s3 * std::sqrt(beta1);
    c3_ = s3 * std::sqrt(alpha3);

    // am(u0) = φ0 ∈ [−π/2, π/2]: cos φ0 = w1(0)/c1 ≥ 0, sin φ0 = w2(0)/c2.
    double cn0 = w[0] / c1_, sn0 = w[1] / c2_;
    const double r = std::hypot(cn0, sn0);
    cn0 /= r;
    sn0 /= r;
    u0_ = sn0 * carlson_rf(cn0 * cn0, cn0 * cn0 + m1_ * sn0 * sn0, 1.0, ok_); // F(φ0|m)
    four_k_ = m1_ > 0.0 ? 4.0 * carlson_rf(0.0, m1_, 1.0, ok_) : 0.0;         // 4K(m)
}

Vec3 FreeRigidBody::at(double s) const {
    switch (kind_) {
    case Kind::constant:
        return y0_;
    case Kind::symmetric: {
        const double c = std::cos(omega_ * s), sn = std::sin(omega_ * s);
        Vec3 y;
        y[i_] = y0_[i_] * c + y0_[j_] * sn;
        y[j_] = y0_[j_] * c - y0_[i_] * sn;
        y[l_] = y0_[l_];
        return y;
    }
    case Kind::elliptic:
        break;
    }
    if (!ok_) return {nan, nan, nan};
    double u = lambda_ * s + u0_;
    if (four_k_ > 0.0 && std::isfinite(four_k_)) u = std::remainder(u, four_k_);
    double sn, cn, dn;
    if (!jacobi(u, m_, m1_, sn, cn, dn)) return {nan, nan, nan};
    const Vec3 w{c1_ * cn, c2_ * sn, c3_ * dn};
    Vec3 y;
    for (int k = 0; k < 3; ++k) y[perm_[k]] = sign_[k] * w[k];
    return y;
}

double rigid_body_tau(double epsilon, double t) {
    if (epsilon == 0.0) return t;
    gsl_errors_off();
    double x = 0.25 * epsilon;
    const int pieces = 8 * static_cast<int>(std::max(1.0, std::ceil(std::abs(x))));
    const double len = pi_hi / pieces;
    gsl_function f{&exp_minus_gamma, &x};
    const gsl_integration_glfixed_table* gl = gauss_legendre20();
    auto integral = [&](double a, double b) { return gsl_integration_glfixed(&f, a, b, gl); };

    // t = nπ + r with r ∈ [0, π), r by a two-part π so that n·(π − double(π)) is not lost.
    double n = std::floor(t / pi_hi);
    double r = (t - n * pi_hi) - n * pi_lo;
    if (r < 0.0) {
        n -= 1.0;
        r = (t - n * pi_hi) - n * pi_lo;
    } else if (r >= pi_hi) {
        n += 1.0;
        r = (t - n * pi_hi) - n * pi_lo;
    }
    double period = 0.0, rest = 0.0;
    for (int k = 0; k < pieces; ++k) {
        const double a = k * len, b = (k + 1) * len;
        const double piece = integral(a, b);
        period += piece;
        if (b <= r) {
            rest += piece;
        } else if (a < r) {
            rest += integral(a, r);
        }
    }
    period += pi_lo; // ∫ over [double(π), π]: the integrand is 1 there
    return n * period + rest;
}

Vec3 rigid_body_exact(const Vec3& inertia, const Vec3& z0, double epsilon, double t0, double t) {
    if (t == t0) return z0;
    const double gamma0 = 0.25 * epsilon * std::sin(2.0 * t0); // Γ(t0)
    const double tau =
        std::exp(gamma0) * (rigid_body_tau(epsilon, t) - rigid_body_tau(epsilon, t0));
    const FreeRigidBody free(inertia, z0);
    const Vec3 y = free.at(tau);
    const double e = std::exp(-(0.25 * epsilon * std::sin(2.0 * t) - gamma0));
    return {e * y[0], e * y[1], e * y[2]};
}

} // namespace dampsym
