// One-step matrix of cimp, csv1, csv2 (and rk3 as a negative control) on the damped oscillator
// (conventions §5, F ch.3). M is always the method's own matrix, obtained by stepping the unit
// vectors with the kernel; the closed forms it is compared with are written out again here,
// independently of src/methods/catalog.cpp, and evaluated in __float128 so that the reference
// carries no round-off.
#include "diagnostics/stability.hpp"
#include "problems/oscillator.hpp"

#include "support/helpers.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <quadmath.h>
#include <string>
#include <vector>

namespace {

using dampsym::Mat;
using dampsym::MethodInfo;
using dampsym::Oscillator;
using Q = __float128;

Oscillator make_oscillator(double omega, double gamma) {
    Oscillator o;
    o.omega = omega;
    o.gamma = gamma;
    return o;
}

using dampsym::test::method;

// The method's own one-step matrix, by its kernel.
Mat kernel_matrix(const std::string& id, double w, double g, double h) {
    const Oscillator osc = make_oscillator(w, g);
    const MethodInfo& info = method(id.c_str());
    return dampsym::one_step_matrix(osc, info, h, dampsym::test::kernel<Oscillator>(info).stepper);
}

// det M with exact products of the double entries (a 113-bit mantissa holds a 106-bit product),
// so the only error left is the one in M itself.
double det_of(const Mat& M) {
    return static_cast<double>(static_cast<Q>(M(0, 0)) * static_cast<Q>(M(1, 1)) -
                               static_cast<Q>(M(0, 1)) * static_cast<Q>(M(1, 0)));
}
double half_trace_of(const Mat& M) {
    return 0.5 * (M(0, 0) + M(1, 1));
}

// ---- Closed forms of F ch.3 in our γ, written out independently (quad precision) ----

// F(3.10): ½trM = e^{−γh}(4 − h²β²)/(4 + h²β²), β² = ω² − γ².
double cimp_half_trace_closed(double w, double g, double h) {
    const Q W = w, G = g, H = h;
    const Q hb2 = H * H * (W - G) * (W + G);
    return static_cast<double>(expq(-G * H) * (4 - hb2) / (4 + hb2));
}
// F(3.15): ½trM = e^{−γh}(1 − h²ω²/2) cosh(γh).
double csv1_half_trace_closed(double w, double g, double h) {
    const Q W = w, G = g, H = h;
    return static_cast<double>(expq(-G * H) * (1 - H * H * W * W / 2) * coshq(G * H));
}
// F(3.20): ½trM = e^{−γh}[(4 + γ²h²) − 2h²ω² cosh(γh/2)] / (4 − γ²h²).
double csv2_half_trace_closed(double w, double g, double h) {
    const Q W = w, G = g, H = h;
    const Q gh2 = G * G * H * H;
    return static_cast<double>(expq(-G * H) * ((4 + gh2) - 2 * H * H * W * W * coshq(G * H / 2)) /
                               (4 - gh2));
}
double closed_half_trace(const std::string& id, double w, double g, double h) {
    if (id == "cimp") return cimp_half_trace_closed(w, g, h);
    if (id == "csv1") return csv1_half_trace_closed(w, g, h);
    return csv2_half_trace_closed(w, g, h);
}

// The exact flow's ½trM: e^{−γh} cos(βh) (cosh(κh) when β² < 0, 1 when β = 0), in quad.
Q exact_half_trace_q(double w, double g, double h) {
    const Q W = w, G = g, H = h;
    const Q b2 = (W - G) * (W + G);
    const Q c = b2 > 0 ? cosq(sqrtq(b2) * H) : (b2 < 0 ? coshq(sqrtq(-b2) * H) : Q(1));
    return expq(-G * H) * c;
}

// Signed leading coefficient c of ½trM − e^{−γh}cos(βh) = c h⁴ + O(h⁵) (conventions §5, derived by
// hand from the closed forms above: cimp +(ω²−γ²)²/12, csv1 −ω²(ω²+4γ²)/24, csv2
// −(2ω⁴+5γ²ω²−4γ⁴)/48).
double h4_signed(const std::string& id, double w, double g) {
    const double w2 = w * w, g2 = g * g;
    if (id == "cimp") return (w2 - g2) * (w2 - g2) / 12.0;
    if (id == "csv1") return -w2 * (w2 + 4.0 * g2) / 24.0;
    return -(2.0 * w2 * w2 + 5.0 * g2 * w2 - 4.0 * g2 * g2) / 48.0;
}

struct Triple {
    double omega, gamma, h;
    const char* what;
};

// (ω, γ, h) triples for each method: γ = 0, tiny γh, moderate values, and points just inside each
// of the method's thresholds (F(3.12), (3.17), (3.22) and γh < 2).
std::vector<Triple> triples_for(const std::string& id) {
    std::vector<Triple> t{{1.0, 0.0, 0.1, "gamma = 0"},
                          {1.0, 1e-5, 0.1, "gamma h = 1e-6"},
                          {2.0, 1e-6, 0.5e-0, "gamma h = 5e-7, larger h"},
                          {1.3, 0.3, 0.1, "moderate"},
                          {2.0, 0.5, 0.25, "moderate"},
                          {3.51, 1.0, 0.3, "moderate (F Fig 3.3 omega)"}};
    const double d = 1e-6; // relative distance to the threshold
    if (id == "cimp") {
        // F(3.12) ω > γ for every h: just above ω = γ, and a very large step.
        t.push_back({0.7 * (1.0 + d), 0.7, 0.2, "omega = gamma (1 + 1e-6)"});
        t.push_back({1.3, 0.3, 10.0, "h = 10 (unconditionally stable)"});
        t.push_back({5.0, 0.01, 3.0, "h beta = 15, half trace near -e^{-gamma h}"});
    } else if (id == "csv1") {
        // F(3.17): 1 − sech(γh) < h²ω²/2 < 1 + sech(γh).
        const double g1 = 0.3, h1 = 0.4;
        t.push_back({std::sqrt(2.0 * (1.0 + 1.0 / std::cosh(g1 * h1)) * (1.0 - d)) / h1, g1, h1,
                     "just below h^2 omega^2/2 = 1 + sech(gamma h)"});
        const double g2 = 0.5, h2 = 0.2;
        t.push_back({std::sqrt(2.0 * (1.0 - 1.0 / std::cosh(g2 * h2)) * (1.0 + d)) / h2, g2, h2,
                     "just above h^2 omega^2/2 = 1 - sech(gamma h)"});
    } else {
        // F(3.22): γ² sech(γh/2) < ω² < 4 sech(γh/2)/h², and γh < 2.
        const double g1 = 0.5, h1 = 0.3;
        t.push_back({std::sqrt(4.0 / std::cosh(0.5 * g1 * h1) * (1.0 - d)) / h1, g1, h1,
                     "just below omega^2 = 4 sech(gamma h/2)/h^2"});
        const double g2 = 0.8, h2 = 0.2;
        t.push_back({g2 * std::sqrt((1.0 + d) / std::cosh(0.5 * g2 * h2)), g2, h2,
                     "just above omega^2 = gamma^2 sech(gamma h/2)"});
        // γh = 1.9 (< 2): the window for ω² is narrow there; take a point 20% into it (its
        // middle would put ½trM at 0, where a relative comparison means nothing).
        const double h3 = 0.5, g3 = 1.9 / h3;
        const double s3 = 1.0 / std::cosh(0.5 * g3 * h3);
        const double lo = g3 * g3 * s3, hi = 4.0 * s3 / (h3 * h3);
        t.push_back({std::sqrt(lo + 0.2 * (hi - lo)), g3, h3, "gamma h = 1.9, near gamma h < 2"});
    }
    return t;
}

} // namespace

TEST_CASE("det M = e^{-2 gamma h} and half trace = F's closed form (cimp, csv1, csv2)",
          "[stability]") {
    for (const std::string id : {"cimp", "csv1", "csv2"}) {
        const MethodInfo& info = method(id.c_str());
        REQUIRE(dampsym::oscillator_formulas(info.id).half_trace != nullptr);
        REQUIRE(dampsym::oscillator_formulas(info.id).F_condition != nullptr);
        for (const Triple& tr : triples_for(id)) {
            INFO(id << " omega=" << tr.omega << " gamma=" << tr.gamma << " h=" << tr.h << " ("
                    << tr.what << ")");
            // Every triple is chosen inside F's stability region.
            REQUIRE(dampsym::oscillator_formulas(info.id).F_condition(tr.omega, tr.gamma, tr.h));
            const Mat M = kernel_matrix(id, tr.omega, tr.gamma, tr.h);
            REQUIRE(M.allFinite());
            const double det_expected = std::exp(-2.0 * tr.gamma * tr.h);
            CHECK_THAT(det_of(M), Catch::Matchers::WithinRel(det_expected, 1e-13));

            const double ht = half_trace_of(M);
            const double closed = closed_half_trace(id, tr.omega, tr.gamma, tr.h);
            CHECK_THAT(ht, Catch::Matchers::WithinRel(closed, 1e-13));
            // The catalog's formula (what the harness reports against) says the same.
            const double catalog =
                dampsym::oscillator_formulas(info.id).half_trace(tr.omega, tr.gamma, tr.h);
            CHECK_THAT(catalog, Catch::Matchers::WithinRel(closed, 1e-13));

            // Inside the region the eigenvalues are complex with modulus e^{-γh} (F ch.3).
            const dampsym::OneStepAnalysis a = dampsym::analyse_one_step(M, tr.gamma, tr.h);
            CHECK(a.F_condition);
            CHECK(a.power_bounded);
            CHECK_THAT(a.spectral_radius,
                       Catch::Matchers::WithinRel(std::exp(-tr.gamma * tr.h), 1e-6));
        }
    }
}

TEST_CASE("full one-step matrices of cimp and csv1 match their closed forms", "[stability]") {
    // cimp: M = e^{−γh}((1 − h²β²/4) I + hA)/(1 + h²β²/4), A = [γ 1; −ω² −γ] the Jacobian of N
    // (the Cayley transform of A, using A² = −β² I).
    // csv1: M = [1 − x, h e^{−γh}; −e^{−γh} h ω² (1 − x/2), e^{−2γh}(1 − x)], x = h²ω²/2.
    for (const Triple& tr : {Triple{1.3, 0.3, 0.1, ""}, Triple{1.0, 1e-5, 0.1, ""},
                             Triple{2.0, 0.5, 0.25, ""}, Triple{0.5, 1.0, 0.7, "over-damped"}}) {
        INFO("omega=" << tr.omega << " gamma=" << tr.gamma << " h=" << tr.h);
        const double w = tr.omega, g = tr.gamma, h = tr.h;
        const double e = std::exp(-g * h);
        const double b2 = (w - g) * (w + g);
        const double den = 1.0 + 0.25 * h * h * b2;
        const double diag = 1.0 - 0.25 * h * h * b2;
        Mat cimp(2, 2);
        cimp << e * (diag + h * g) / den, e * h / den, -e * h * w * w / den,
            e * (diag - h * g) / den;
        const double x = 0.5 * h * h * w * w;
        Mat csv1(2, 2);
        csv1 << 1.0 - x, h * e, -e * h * w * w * (1.0 - 0.5 * x), e * e * (1.0 - x);
        const Mat Mc = kernel_matrix("cimp", w, g, h);
        const Mat Ms = kernel_matrix("csv1", w, g, h);
        CHECK((Mc - cimp).cwiseAbs().maxCoeff() <= 1e-14 * cimp.cwiseAbs().maxCoeff());
        CHECK((Ms - csv1).cwiseAbs().maxCoeff() <= 1e-14 * csv1.cwiseAbs().maxCoeff());
    }
}

TEST_CASE("rk3 is not conformal symplectic: det M != e^{-2 gamma h} (negative control)",
          "[stability]") {
    const Mat M = kernel_matrix("rk3", 1.3, 0.3, 0.1);
    const double expected = std::exp(-2.0 * 0.3 * 0.1);
    const double rel = std::abs(det_of(M) - expected) / expected;
    INFO("rk3 det M = " << det_of(M) << ", e^{-2 gamma h} = " << expected << ", rel " << rel);
    CHECK(rel > 1e-11);
    // and its half trace is none of F's closed forms
    const double ht = half_trace_of(M);
    CHECK(std::abs(ht - cimp_half_trace_closed(1.3, 0.3, 0.1)) > 1e-9);
    CHECK(std::abs(ht - csv1_half_trace_closed(1.3, 0.3, 0.1)) > 1e-9);
}

TEST_CASE("analyse_one_step: F's condition and power-boundedness of rotations, Jordan blocks and "
          "the identity",
          "[stability]") {
    using Catch::Matchers::WithinAbs;
    using Catch::Matchers::WithinRel;
    const double g = 0.3, h = 0.1;
    const double r = std::exp(-g * h);

    SECTION("e^{-gamma h} times a rotation: F holds, power bounded, |lambda| = e^{-gamma h}") {
        const double th = 0.7;
        Mat M(2, 2);
        M << std::cos(th), -std::sin(th), std::sin(th), std::cos(th);
        M *= r;
        const auto a = dampsym::analyse_one_step(M, g, h);
        CHECK(a.finite);
        CHECK(a.F_condition);
        CHECK(a.power_bounded);
        CHECK_THAT(a.det, WithinRel(r * r, 1e-15));
        CHECK_THAT(a.half_trace, WithinRel(r * std::cos(th), 1e-15));
        CHECK_THAT(a.spectral_radius, WithinRel(r, 1e-14));
        CHECK_THAT(std::abs(a.eig[0].imag()), WithinRel(r * std::sin(th), 1e-14));
        CHECK_THAT(a.eig[0].imag() + a.eig[1].imag(), WithinAbs(0.0, 1e-15));
    }
    SECTION("a pure rotation with gamma = 0: on the unit circle, distinct eigenvalues, bounded") {
        Mat M(2, 2);
        M << std::cos(0.3), -std::sin(0.3), std::sin(0.3), std::cos(0.3);
        const auto a = dampsym::analyse_one_step(M, 0.0, h);
        CHECK(a.F_condition);
        CHECK(a.power_bounded);
        CHECK_THAT(a.spectral_radius, WithinRel(1.0, 1e-15));
    }
    SECTION("a Jordan block on the unit circle is not power bounded") {
        for (double lambda : {1.0, -1.0}) {
            INFO("lambda = " << lambda);
            Mat J(2, 2);
            J << lambda, 1.0, 0.0, lambda;
            const auto a = dampsym::analyse_one_step(J, 0.0, h);
            CHECK_THAT(a.spectral_radius, WithinRel(1.0, 1e-15));
            CHECK_FALSE(a.power_bounded);
            CHECK_FALSE(a.F_condition); // |½trM| = 1 is not < e^0
            // (and indeed ‖J^n‖ grows like n)
            Mat P = Mat::Identity(2, 2);
            for (int n = 0; n < 100; ++n) P = P * J;
            CHECK(P.cwiseAbs().maxCoeff() >= 100.0);
        }
        // a similarity-transformed defective matrix, not upper triangular
        Mat S(2, 2), J(2, 2);
        S << 1.0, 2.0, 0.5, 3.0;
        J << 1.0, 1.0, 0.0, 1.0;
        const Mat M = S * J * S.inverse();
        CHECK_FALSE(dampsym::analyse_one_step(M, 0.0, h).power_bounded);
    }
    SECTION("the identity (lambda = 1 twice, not defective) is power bounded") {
        CHECK(dampsym::analyse_one_step(Mat::Identity(2, 2), 0.0, h).power_bounded);
    }
}

TEST_CASE("analyse_one_step: F's condition and power-boundedness with real eigenvalues, spectral "
          "radius > 1 and a non-finite matrix",
          "[stability]") {
    using Catch::Matchers::WithinAbs;
    using Catch::Matchers::WithinRel;
    const double g = 0.3, h = 0.1;
    const double r = std::exp(-g * h);

    SECTION("real eigenvalues with e^{-gamma h} < |lambda| <= 1: F fails, yet power bounded") {
        // det = e^{−2γh} like a conformal method, but the eigenvalues are real and distinct, so
        // |½trM| > e^{−γh} (AM > GM): F calls it unstable, while ρ(M) = 0.99 < 1.
        const double l1 = 0.99, l2 = r * r / l1;
        Mat S(2, 2), D = Mat::Zero(2, 2);
        S << 1.0, 0.3, -0.2, 1.0;
        D(0, 0) = l1;
        D(1, 1) = l2;
        const Mat M = S * D * S.inverse();
        const auto a = dampsym::analyse_one_step(M, g, h);
        CHECK_THAT(a.det, WithinRel(r * r, 1e-14));
        CHECK(std::abs(a.half_trace) > r);
        CHECK_FALSE(a.F_condition);
        CHECK(a.power_bounded);
        CHECK_THAT(a.spectral_radius, WithinRel(l1, 1e-13));
        CHECK_THAT(std::abs(a.eig[0].imag()) + std::abs(a.eig[1].imag()), WithinAbs(0.0, 0.0));
        // λ = 1 exactly with a distinct partner is still bounded
        D(0, 0) = 1.0;
        D(1, 1) = 0.5;
        const auto b = dampsym::analyse_one_step(S * D * S.inverse(), g, h);
        CHECK(b.power_bounded);
        CHECK_THAT(b.spectral_radius, WithinRel(1.0, 1e-14));
    }
    SECTION("spectral radius > 1 is not power bounded") {
        Mat M(2, 2);
        M << 1.01, 0.0, 0.0, 0.2;
        const auto a = dampsym::analyse_one_step(M, g, h);
        CHECK_FALSE(a.power_bounded);
        CHECK_THAT(a.spectral_radius, WithinRel(1.01, 1e-15));
    }
    SECTION("a non-finite matrix is flagged, not analysed") {
        Mat M(2, 2);
        M << 1.0, std::nan(""), 0.0, 1.0;
        const auto a = dampsym::analyse_one_step(M, g, h);
        CHECK_FALSE(a.finite);
        CHECK_FALSE(a.F_condition);
        CHECK_FALSE(a.power_bounded);
    }
}

namespace {

// Compares the catalog's closed-form condition with the sign of e^{γh}|½trM| − 1 of the kernel's
// own M over a (ω, γ, h) grid; returns the number of disagreements (points within 1e-9 of the
// boundary are skipped) and counts points on each side.
struct GridResult {
    int mismatches = 0, inside = 0, outside = 0, skipped = 0;
    std::string first;
};
GridResult compare_on_grid(const std::string& id, const std::vector<double>& omegas,
                           double gamma_max, double h_max, bool only_gh_below_2,
                           bool only_gh_above_2) {
    const MethodInfo& info = method(id.c_str());
    GridResult res;
    for (double w : omegas) {
        for (int ig = 0; ig <= 14; ++ig) {
            const double g = gamma_max * ig / 14.0;
            for (int ih = 1; ih <= 40; ++ih) {
                const double h = h_max * ih / 40.0;
                if (only_gh_below_2 && !(g * h < 1.99)) continue;
                if (only_gh_above_2 && !(g * h > 2.01)) continue;
                const Mat M = kernel_matrix(id, w, g, h);
                const double s = std::exp(g * h) * std::abs(half_trace_of(M)) - 1.0;
                if (!std::isfinite(s) || std::abs(s) < 1e-9) {
                    ++res.skipped;
                    continue;
                }
                const bool empirical = s < 0.0;
                (empirical ? res.inside : res.outside) += 1;
                if (dampsym::oscillator_formulas(info.id).F_condition(w, g, h) != empirical) {
                    if (res.mismatches == 0)
                        res.first = "omega=" + std::to_string(w) + " gamma=" + std::to_string(g) +
                                    " h=" + std::to_string(h) +
                                    " e^{gh}|trM/2|-1=" + std::to_string(s);
                    ++res.mismatches;
                }
            }
        }
    }
    return res;
}

} // namespace

TEST_CASE("F's closed-form conditions (3.12)/(3.17)/(3.22) agree with the sign of "
          "e^{gamma h}|tr M/2| - 1",
          "[stability]") {
    const std::vector<double> omegas{0.3, 1.0, 1.5, 3.51, 8.0};
    for (const std::string id : {"cimp", "csv1", "csv2"}) {
        // csv2's (3.22) is derived for γh < 2 (F divides by 4 − γ²h²); γh ≥ 2 is tested below.
        const GridResult r =
            compare_on_grid(id, omegas, 3.5, id == "cimp" ? 4.0 : 1.0, id == "csv2", false);
        INFO(id << ": inside " << r.inside << ", outside " << r.outside << ", skipped " << r.skipped
                << ", first mismatch: " << r.first);
        CHECK(r.mismatches == 0);
        // the grid sees both sides of the boundary (else this check could not fail)
        CHECK(r.inside > 50);
        CHECK(r.outside > 50);
    }
}

TEST_CASE("csv2 beyond gamma h = 2: F's condition against the one-step matrix", "[stability]") {
    // conventions §5 adds "also needs γh < 2" to F(3.22) and the catalog returns false whenever γh
    // ≥ 2. For γh > 2 the factor 4 − γ²h² in F(3.20) is negative and the inequality flips: the
    // matrix then satisfies |½trM| < e^{−γh} exactly when 4 sech(γh/2)/h² < ω² < γ² sech(γh/2).
    // This checks the catalog's condition against the kernel's matrix there as well.
    const GridResult r =
        compare_on_grid("csv2", {0.3, 1.0, 1.5, 1.8, 3.51, 8.0}, 3.5, 1.0, false, true);
    INFO("inside " << r.inside << ", outside " << r.outside << ", mismatches " << r.mismatches
                   << ", first mismatch: " << r.first);
    CHECK(r.outside > 20);
    CHECK(r.mismatches == 0);
}

TEST_CASE("h^4 coefficient of tr M/2 - e^{-gamma h} cos(beta h) (conventions §5)", "[stability]") {
    // Measured from the kernels' M: f(h) = (½trM − e^{−γh}cos βh)/h⁴ = c + c₅h + c₆h² + …;
    // Richardson on h, h/2, h/4 removes c₅ and c₆.
    struct WG {
        double w, g;
    };
    for (const std::string id : {"cimp", "csv1", "csv2"}) {
        const MethodInfo& info = method(id.c_str());
        for (const WG p : {WG{1.0, 0.0}, WG{1.0, 0.4}, WG{1.3, 0.3}, WG{2.0, 0.1}, WG{0.5, 1.0}}) {
            INFO(id << " omega=" << p.w << " gamma=" << p.g);
            auto f = [&](double h) {
                const Mat M = kernel_matrix(id, p.w, p.g, h);
                return static_cast<double>(
                    (static_cast<Q>(half_trace_of(M)) - exact_half_trace_q(p.w, p.g, h)) /
                    (static_cast<Q>(h) * h * h * h));
            };
            const double h = 0.04;
            const double f1 = f(h), f2 = f(h / 2), f3 = f(h / 4);
            const double r1 = 2.0 * f2 - f1, r2 = 2.0 * f3 - f2; // c₅ removed
            const double c = (4.0 * r2 - r1) / 3.0;              // c₆ removed
            const double expected = h4_signed(id, p.w, p.g);
            INFO("measured " << c << " (f(h/4) = " << f3 << "), expected " << expected);

            CHECK_THAT(c, Catch::Matchers::WithinRel(expected, 5e-5));
            // and the catalog's coefficient is the same number up to sign (the harness takes |.|)
            CHECK_THAT(std::abs(dampsym::oscillator_formulas(info.id).h4_coefficient(p.w, p.g)),
                       Catch::Matchers::WithinRel(std::abs(expected), 1e-14));
        }
    }
}
