// Periodic grid operators of B (1.14), Lemma 1.8, the spectral derivative and the cyclic solvers
// (src/pde/periodic_grid.hpp).
#include "pde/periodic_grid.hpp"

#include "support/helpers.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <complex>
#include <numbers>
#include <random>

using Catch::Matchers::WithinAbs;
using dampsym::Vec;
using namespace dampsym::pde;

namespace {

Vec sample(const PeriodicGrid& g, auto f) {
    Vec v(g.M);
    for (int n = 0; n < g.M; ++n) v[n] = f(g.x(n));
    return v;
}

Vec random_vec(int M, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Vec v(M);
    for (int n = 0; n < M; ++n) v[n] = u(rng);
    return v;
}

} // namespace

TEST_CASE("pde grid: the operators of B (1.14) act on Fourier modes by their exact symbols",
          "[pde]") {
    for (int M : {7, 16, 33}) {
        const PeriodicGrid g(M, std::numbers::pi);
        const int k = 3;
        const Vec s = sample(g, [&](double x) { return std::sin(k * x); });
        Vec out;
        const double hd = 0.5 * k * g.dx;
        forward_difference(g, s, out);
        CHECK(dampsym::test::max_abs(out - sample(g, [&](double x) {
                                         return 2.0 * std::sin(hd) / g.dx * std::cos(k * x + hd);
                                     })) <= 1e-13);
        forward_average(g, s, out);
        CHECK(dampsym::test::max_abs(out - sample(g, [&](double x) {
                                         return std::cos(hd) * std::sin(k * x + hd);
                                     })) <= 1e-13);
        central_difference(g, s, out);
        CHECK(dampsym::test::max_abs(out - sample(g, [&](double x) {
                                         return std::sin(k * g.dx) / g.dx * std::cos(k * x);
                                     })) <= 1e-13);
        second_difference(g, s, out);
        CHECK(dampsym::test::max_abs(out - sample(g, [&](double x) {
                                         return -4.0 * std::sin(hd) * std::sin(hd) / (g.dx * g.dx) *
                                                std::sin(k * x);
                                     })) <= 1e-12);
        shift(g, s, out);
        CHECK(dampsym::test::max_abs(
                  out - sample(g, [&](double x) { return std::sin(k * (x - g.dx)); })) <= 1e-13);
    }
}

TEST_CASE("pde grid: delta_x and delta_x^2 are second order (error ratio 4 per halving)", "[pde]") {
    double prev1 = 0, prev2 = 0;
    for (int M : {32, 64, 128, 256}) {
        const PeriodicGrid g(M, std::numbers::pi);
        const Vec f = sample(g, [](double x) { return std::exp(std::sin(x)); });
        Vec d1, d2;
        central_difference(g, f, d1);
        second_difference(g, f, d2);
        const double e1 = dampsym::test::max_abs(
            d1 - sample(g, [](double x) { return std::cos(x) * std::exp(std::sin(x)); }));
        const double e2 = dampsym::test::max_abs(
            d2 - sample(g, [](double x) {
                return (std::cos(x) * std::cos(x) - std::sin(x)) * std::exp(std::sin(x));
            }));
        if (prev1 > 0) {
            CHECK_THAT(std::log2(prev1 / e1), WithinAbs(2.0, 0.1));
            CHECK_THAT(std::log2(prev2 / e2), WithinAbs(2.0, 0.1));
        }
        prev1 = e1;
        prev2 = e2;
    }
}

TEST_CASE("pde grid: Lemma 1.8 (ii) product rule and (iii) summation by parts", "[pde]") {
    std::mt19937_64 rng(15);
    for (int M : {5, 8, 64}) {
        const PeriodicGrid g(M, 2.0);
        const Vec a = random_vec(M, rng), b = random_vec(M, rng);
        Vec da, db, aa, ab, dab;
        // (ii) with α = 0: D_x(ab) = D_x a A_x b + A_x a D_x b, exactly up to round-off.
        forward_difference(g, a, da);
        forward_difference(g, b, db);
        forward_average(g, a, aa);
        forward_average(g, b, ab);
        forward_difference(g, Vec(a.cwiseProduct(b)), dab);
        CHECK(dampsym::test::max_abs(dab - da.cwiseProduct(ab) - aa.cwiseProduct(db)) <=
              1e-13 / g.dx);
        // (iii) Σ a δ_x b = −Σ δ_x a b and Σ a δ_x² b = Σ δ_x² a b.
        Vec ca, cb, sa, sb;
        central_difference(g, a, ca);
        central_difference(g, b, cb);
        second_difference(g, a, sa);
        second_difference(g, b, sb);
        CHECK(std::abs(a.dot(cb) + ca.dot(b)) <= 1e-14 * M / g.dx);
        CHECK(std::abs(a.dot(sb) - sa.dot(b)) <= 1e-14 * M / (g.dx * g.dx));
    }
}

TEST_CASE("pde grid: A_x has the alternating mode as kernel exactly when M is even", "[pde]") {
    for (int M : {6, 7, 64, 65}) {
        const PeriodicGrid g(M, std::numbers::pi);
        Vec alt(M), out;
        for (int n = 0; n < M; ++n) alt[n] = (n % 2 == 0) ? 1.0 : -1.0;
        forward_average(g, alt, out);
        // The smallest |symbol| of A_x over all modes: cos(θ/2) at θ = 2πj/M closest to π.
        double smallest = 1.0;
        for (int j = 0; j < M; ++j)
            smallest = std::min(smallest, std::abs(std::cos(std::numbers::pi * j / M)));
        if (M % 2 == 0) {
            CHECK(dampsym::test::max_abs(out) == 0.0);
            CHECK(smallest < 1e-15);
        } else {
            CHECK(dampsym::test::max_abs(out) > 0.0); // one wrap-around pair does not cancel
            CHECK(smallest >= std::sin(std::numbers::pi / (2.0 * M)) * 0.999);
        }
    }
}

TEST_CASE("pde grid: spectral derivative is exact on trigonometric polynomials (any M)", "[pde]") {
    for (int M : {16, 30, 31, 64}) {
        const PeriodicGrid g(M, std::numbers::pi);
        SpectralDerivative D(g);
        const Vec f =
            sample(g, [](double x) { return std::sin(3 * x) + 0.5 * std::cos(5 * x) + 1.0; });
        Vec df;
        D.apply(f, df);
        CHECK(dampsym::test::max_abs(df - sample(g, [](double x) {
                                         return 3 * std::cos(3 * x) - 2.5 * std::sin(5 * x);
                                     })) <= 1e-12);
        std::vector<std::complex<double>> e(M), de;
        for (int n = 0; n < M; ++n) e[n] = std::exp(std::complex<double>(0, 4 * g.x(n)));
        D.apply(e, de);
        double err = 0;
        for (int n = 0; n < M; ++n)
            err = std::max(err, std::abs(de[n] - std::complex<double>(0, 4) * e[n]));
        CHECK(err <= 1e-12);
        if (M % 2 == 0) { // the Nyquist mode (alternating) has derivative 0 (kept real)
            Vec alt(M), da;
            for (int n = 0; n < M; ++n) alt[n] = (n % 2 == 0) ? 1.0 : -1.0;
            D.apply(alt, da);
            CHECK(dampsym::test::max_abs(da) <= 1e-13);
        }
    }
    // On a half-length L ≠ π the wavenumbers scale by π/L.
    const PeriodicGrid g(40, 10.0);
    SpectralDerivative D(g);
    const double k = std::numbers::pi / 10.0 * 2;
    Vec df;
    D.apply(sample(g, [&](double x) { return std::sin(k * x); }), df);
    CHECK(dampsym::test::max_abs(df - sample(g, [&](double x) { return k * std::cos(k * x); })) <=
          1e-12);
}

TEST_CASE("pde grid: cyclic tridiagonal solver against a dense solve", "[pde]") {
    std::mt19937_64 rng(7);
    for (int M : {3, 4, 9, 64}) {
        const Vec lo = random_vec(M, rng), up = random_vec(M, rng);
        Vec di = random_vec(M, rng);
        for (int n = 0; n < M; ++n) di[n] += (di[n] >= 0 ? 2.5 : -2.5); // diagonally dominant
        const Vec r = random_vec(M, rng);
        Vec x;
        REQUIRE(solve_cyclic_tridiagonal(lo, di, up, r, x));
        dampsym::Mat A = dampsym::Mat::Zero(M, M);
        for (int n = 0; n < M; ++n) {
            A(n, n) += di[n];
            A(n, (n + M - 1) % M) += lo[n];
            A(n, (n + 1) % M) += up[n];
        }
        CHECK(dampsym::test::max_abs(A * x - r) <= 1e-14 * M);
        Vec y;
        solve_cyclic_tridiagonal(0.3, -1.0, r, y); // constant coefficients
        dampsym::Mat B = dampsym::Mat::Zero(M, M);
        for (int n = 0; n < M; ++n) {
            B(n, n) += -1.0;
            B(n, (n + M - 1) % M) += 0.3;
            B(n, (n + 1) % M) += 0.3;
        }
        CHECK(dampsym::test::max_abs(B * y - r) <= 1e-14 * M);
    }
}
