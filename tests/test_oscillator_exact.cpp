// dampsym::oscillator_exact (reference/oscillator_exact.hpp) against the naive closed form of
// q'' + 2γq' + ω²q = 0 evaluated in __float128, in all three regimes and across ω = γ.
#include "reference/oscillator_exact.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <quadmath.h>
#include <vector>

namespace {

using Q = __float128;
constexpr double kEpsOsc = std::numeric_limits<double>::epsilon();

struct QState {
    Q q, p;
    Q terms; // Σ of the magnitudes of the terms summed: the scale of the round-off
};

// The textbook closed form, p = q':
//   q = e^{−γt}[q0 C + (p0 + γq0) S],  p = e^{−γt}[p0 C − (γp0 + ω²q0) S]
// with C = cos βt, S = sin βt/β (β² = ω² − γ² > 0); C = 1, S = t (β = 0); C = cosh κt,
// S = sinh κt/κ (κ² = γ² − ω² > 0). Quad precision (113 bits) makes the 0/0-like loss near
// β = 0 irrelevant: at |ω − γ| = 1e-9γ it costs about 5 of its 34 digits.
QState exact_q(double omega, double gamma, double q0, double p0, double t) {
    const Q w = omega, g = gamma, T = t, Q0 = q0, P0 = p0;
    const Q b2 = (w - g) * (w + g);
    Q c, s;
    if (b2 > 0) {
        const Q b = sqrtq(b2);
        c = cosq(b * T);
        s = sinq(b * T) / b;
    } else if (b2 < 0) {
        const Q k = sqrtq(-b2);
        c = coshq(k * T);
        s = sinhq(k * T) / k;
    } else {
        c = 1;
        s = T;
    }
    const Q e = expq(-g * T);
    const Q a = P0 + g * Q0, b = g * P0 + w * w * Q0;
    const Q terms = fabsq(e * c) * (fabsq(Q0) + fabsq(P0)) + fabsq(e * s) * (fabsq(a) + fabsq(b));
    return {e * (Q0 * c + a * s), e * (P0 * c - b * s), terms};
}

struct Errors {
    double rel;   // ‖z − z_ref‖ / ‖z_ref‖
    double norm;  // ‖z_ref‖
    double terms; // scale of the summed terms (≈ ‖z_ref‖ unless the sum cancels)
};

Errors errors(double omega, double gamma, double q0, double p0, double t) {
    const dampsym::OscillatorState z = dampsym::oscillator_exact(omega, gamma, q0, p0, t);
    const QState r = exact_q(omega, gamma, q0, p0, t);
    const Q dq = static_cast<Q>(z.q) - r.q, dp = static_cast<Q>(z.p) - r.p;
    const Q norm = sqrtq(r.q * r.q + r.p * r.p);
    return {static_cast<double>(sqrtq(dq * dq + dp * dp) / norm), static_cast<double>(norm),
            static_cast<double>(r.terms)};
}

// Round-off floor of any double evaluation, relative to the state norm: a few ulps of the summed
// terms (which exceed ‖z‖ only when the initial state nearly cancels one mode), times the growth
// from the phase βt (or κt) and the decay γt, each of which carries a relative rounding error of
// a few ulps, i.e. an absolute error ~ ε·(|β| + γ)·t. So ~1e-14 for t = O(1), growing like t.
double tolerance(double omega, double gamma, double t, const Errors& e) {
    const double b = std::sqrt(std::abs((omega - gamma) * (omega + gamma)));
    return 16.0 * kEpsOsc * (e.terms / e.norm) * (1.0 + (b + gamma) * t);
}

struct Regime {
    double omega, gamma;
    const char* name;
};

void check_regime(const std::vector<Regime>& params, double& worst_small_t) {
    const double ics[][2] = {{1.0, 0.0}, {0.0, 1.0}, {0.7, -1.3}};
    for (const Regime& r : params) {
        std::vector<double> ts{0.0, 1e-3, 0.1, 1.0, 2.5, 10.0, 50.0, 500.0, 5000.0};
        // on both sides of the series/closed-form switch of the implementation (|β²t²| = ½)
        const double b2 = (r.omega - r.gamma) * (r.omega + r.gamma);
        if (b2 != 0.0) {
            const double ts_switch = std::sqrt(0.5 / std::abs(b2));
            for (double f : {1.0 - 1e-9, 1.0, 1.0 + 1e-9, 2.0}) ts.push_back(ts_switch * f);
        }
        for (double t : ts) {
            for (const auto& ic : ics) {
                const Errors e = errors(r.omega, r.gamma, ic[0], ic[1], t);
                if (!(e.norm > 1e-280)) continue; // the state underflows a double: nothing to do
                INFO(r.name << ": omega=" << r.omega << " gamma=" << r.gamma << " q0=" << ic[0]
                            << " p0=" << ic[1] << " t=" << t << " |z|=" << e.norm
                            << " terms/|z|=" << e.terms / e.norm << " rel err=" << e.rel);
                CHECK(e.rel <= tolerance(r.omega, r.gamma, t, e));
                // measured error relative to the scale of the terms, for t = O(1)
                if (t <= 10.0) worst_small_t = std::max(worst_small_t, e.rel * e.norm / e.terms);
            }
        }
    }
}

} // namespace

TEST_CASE("oscillator_exact agrees with a quad-precision closed form in every regime",
          "[oscillator][reference]") {
    double worst = 0.0;
    SECTION("under-damped (omega > gamma)") {
        check_regime({{1.0, 0.0, "undamped"},
                      {1.0, 0.001, "under"},
                      {1.0, 0.025, "under"},
                      {1.3, 0.3, "under"},
                      {10.0, 0.5, "under"},
                      {1.0, 0.9, "under"}},
                     worst);
    }
    SECTION("critically damped (omega == gamma)") {
        check_regime({{1.0, 1.0, "critical"}, {0.3, 0.3, "critical"}, {2.5, 2.5, "critical"}},
                     worst);
    }
    SECTION("over-damped (omega < gamma)") {
        check_regime({{0.5, 1.0, "over"}, {1.0, 10.0, "over"}, {0.01, 1.0, "over"}}, worst);
    }
    SECTION("near omega = gamma, on both sides") {
        std::vector<Regime> near;
        for (double g : {1.0, 0.3, 4.0})
            for (double d : {1e-9, -1e-9, 1e-6, -1e-6})
                near.push_back(
                    {g * (1.0 + d), g, d > 0 ? "just under-damped" : "just over-damped"});
        check_regime(near, worst);
    }
    // Measured: for t <= 10 the error is at round-off level relative to the state (to the summed
    // terms, which differ from ‖z‖ only where the initial state nearly cancels a mode).
    INFO("worst relative error for t <= 10: " << worst);
    CHECK(worst <= 1e-14);
}

TEST_CASE("oscillator_exact at t = 0 returns the initial state exactly", "[oscillator]") {
    for (double g : {0.0, 0.5, 1.0, 2.0}) {
        const auto z = dampsym::oscillator_exact(1.0, g, 0.7, -1.3, 0.0);
        CHECK(z.q == 0.7);
        CHECK(z.p == -1.3);
    }
}

TEST_CASE("oscillator_exact is continuous through omega = gamma, to O(|omega - gamma|)",
          "[oscillator]") {
    // At ω = γ: C = 1, S = t, ∂C/∂ω = −ωt², ∂S/∂ω = −ωt³/3 (from the series in β²t², with
    // ∂β²/∂ω = 2ω). So z(ω) − z(γ) = (ω − γ)·∂z/∂ω + O((ω − γ)²) from either side.
    for (double g : {0.3, 1.0, 2.0}) {
        for (double t : {0.5, 1.0, 3.0, 10.0}) {
            const double q0 = 0.7, p0 = -1.3;
            const double e = std::exp(-g * t);
            const double dC = -g * t * t, dS = -g * t * t * t / 3.0;
            const double S = t;
            const double dq = e * (q0 * dC + (p0 + g * q0) * dS);
            const double dp = e * (p0 * dC - 2.0 * g * q0 * S - (g * p0 + g * g * q0) * dS);
            const auto z0 = dampsym::oscillator_exact(g, g, q0, p0, t);
            for (double d : {1e-9, 1e-6}) {
                const double above = g * (1.0 + d), below = g * (1.0 - d);
                const auto zp = dampsym::oscillator_exact(above, g, q0, p0, t);
                const auto zm = dampsym::oscillator_exact(below, g, q0, p0, t);
                const double hp = above - g, hm = g - below; // the actual double differences
                INFO("gamma=" << g << " t=" << t << " delta=" << d);
                // one-sided difference quotients from above and from below both equal ∂z/∂ω
                const double scale = std::abs(dq) + std::abs(dp);
                // round-off in z over |ω − γ|, plus the O(|ω − γ|) second-order term
                const double tol = 8.0 * kEpsOsc * (std::abs(z0.q) + std::abs(z0.p) + e) / (d * g) +
                                   10.0 * d * g * (1.0 + t * t * t * t) * e + 1e-15 * scale;
                CHECK(std::abs((zp.q - z0.q) / hp - dq) <= tol);
                CHECK(std::abs((zp.p - z0.p) / hp - dp) <= tol);
                CHECK(std::abs((z0.q - zm.q) / hm - dq) <= tol);
                CHECK(std::abs((z0.p - zm.p) / hm - dp) <= tol);
                // and the jump across ω = γ is O(|ω − γ|): no 0/0, no switch artefact
                const double jump = std::hypot(zp.q - zm.q, zp.p - zm.p);
                CHECK(jump <= 2.0 * d * g * (2.0 * scale + tol));
            }
        }
    }
}

namespace {

// e^{−γt}C and e^{−γt}S of the exact solution by their power series in x = β²t² (β² = ω² − γ²
// of either sign), summed in __float128 until the terms vanish: C = Σ (−x)^k/(2k)!,
// S = t Σ (−x)^k/(2k+1)!. No closed form, no switch between regimes, no 0/0 at β = 0.
QState series_q(double omega, double gamma, double q0, double p0, double t) {
    const Q w = omega, g = gamma, T = t, Q0 = q0, P0 = p0;
    const Q x = (w - g) * (w + g) * T * T;
    Q c = 0, s = 0, tc = 1, ts = 1;
    for (int k = 0; k < 200 && (fabsq(tc) > static_cast<Q>(1e-40) * fabsq(c) || k < 2); ++k) {
        c += tc;
        s += ts;
        tc *= -x / ((2 * k + 1) * (2 * k + 2));
        ts *= -x / ((2 * k + 2) * (2 * k + 3));
    }
    s *= T;
    const Q e = expq(-g * T);
    const Q a = P0 + g * Q0, b = g * P0 + w * w * Q0;
    const Q terms = fabsq(e * c) * (fabsq(Q0) + fabsq(P0)) + fabsq(e * s) * (fabsq(a) + fabsq(b));
    return {e * (Q0 * c + a * s), e * (P0 * c - b * s), terms};
}

} // namespace

TEST_CASE("oscillator_exact at omega = gamma (1 +- 1e-12) and omega = gamma against a quad series",
          "[oscillator][reference][stress]") {
    // The stress suite's near-critical cases (verify/cases/stress-near-critical-*.json) rely on
    // the reference there. Compared with the __float128 power series (and, where β ≠ 0, with the
    // quad closed form exact_q): relative error at round-off, 16 ε (1 + (|β| + γ)t) ·
    // terms/|z|. The textbook over-damped form (e^{−(γ−κ)t} − e^{−(γ+κ)t})/(2κ) in double would
    // lose ε/(κt) ~ 1e-11 here (κ = γ sqrt(2e-12)) and fail.
    double worst = 0.0;
    for (double g : {1.0, 0.3, 4.0, 1e3}) {
        for (double d : {1e-12, -1e-12, 0.0}) {
            const double w = g * (1.0 + d);
            for (double t : {1e-3, 0.1, 1.0, 4.0, 20.0, 100.0}) {
                for (const auto& ic : {std::pair{1.0, 0.0}, {0.0, 1.0}, {1.0, 0.5}, {0.7, -1.3}}) {
                    const dampsym::OscillatorState z =
                        dampsym::oscillator_exact(w, g, ic.first, ic.second, t);
                    const QState r = series_q(w, g, ic.first, ic.second, t);
                    const Q norm = sqrtq(r.q * r.q + r.p * r.p);
                    if (!(norm > static_cast<Q>(1e-280))) continue; // underflows a double
                    const Q dq = static_cast<Q>(z.q) - r.q, dp = static_cast<Q>(z.p) - r.p;
                    const double rel = static_cast<double>(sqrtq(dq * dq + dp * dp) / norm);
                    const Errors e{rel, static_cast<double>(norm), static_cast<double>(r.terms)};
                    INFO("gamma=" << g << " omega=gamma(1" << (d >= 0 ? "+" : "") << d
                                  << ") t=" << t << " q0=" << ic.first << " p0=" << ic.second
                                  << " rel err=" << rel);
                    CHECK(rel <= tolerance(w, g, t, e));
                    if (g * t <= 10.0) worst = std::max(worst, rel * e.norm / e.terms);
                    if (w != g) { // the quad closed form agrees with the series (β ≠ 0)
                        const QState cf = exact_q(w, g, ic.first, ic.second, t);
                        const Q diff =
                            sqrtq((cf.q - r.q) * (cf.q - r.q) + (cf.p - r.p) * (cf.p - r.p));
                        CHECK(static_cast<double>(diff / norm) <= 1e-25);
                    }
                }
            }
        }
    }
    INFO("worst relative error (g t <= 10): " << worst);
    CHECK(worst <= 1e-15);
}
