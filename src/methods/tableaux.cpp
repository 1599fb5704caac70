// Generated and small fixed tableaux (see tableaux.hpp for the definitions and citations).
#include "methods/tableaux.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <stdexcept>
#include <utility>

namespace dampsym {
namespace {

__extension__ typedef __float128 quad; // 113-bit significand; arithmetic lives in libgcc

quad quad_abs(quad x) {
    return x < 0 ? -x : x;
}

// P_s(x) and P_s'(x) by the three-term recurrence (k+1) P_{k+1} = (2k+1) x P_k − k P_{k−1}.
std::pair<quad, quad> legendre(int s, quad x) {
    quad p0 = 1, p1 = x;
    if (s == 0) return {1, 0};
    for (int k = 1; k < s; ++k) {
        const quad p2 = (quad(2 * k + 1) * x * p1 - quad(k) * p0) / quad(k + 1);
        p0 = p1;
        p1 = p2;
    }
    // P_s'(x) = s (x P_s − P_{s−1}) / (x² − 1), valid inside (−1, 1) where the roots are.
    return {p1, quad(s) * (x * p1 - p0) / (x * x - 1)};
}

// Solves V x = r (n×n, row-major) by Gaussian elimination with partial pivoting, in quad.
template <std::size_t N>
std::array<quad, N> solve(std::array<quad, N * N> V, std::array<quad, N> r, int n) {
    const auto at = [&](int i, int j) -> quad& { return V[static_cast<std::size_t>(i * n + j)]; };
    for (int k = 0; k < n; ++k) {
        int piv = k;
        for (int i = k + 1; i < n; ++i)
            if (quad_abs(at(i, k)) > quad_abs(at(piv, k))) piv = i;
        if (piv != k) {
            for (int j = 0; j < n; ++j) std::swap(at(k, j), at(piv, j));
            std::swap(r[static_cast<std::size_t>(k)], r[static_cast<std::size_t>(piv)]);
        }
        for (int i = k + 1; i < n; ++i) {
            const quad f = at(i, k) / at(k, k);
            for (int j = k; j < n; ++j) at(i, j) -= f * at(k, j);
            r[static_cast<std::size_t>(i)] -= f * r[static_cast<std::size_t>(k)];
        }
    }
    std::array<quad, N> x{};
    for (int i = n - 1; i >= 0; --i) {
        quad acc = r[static_cast<std::size_t>(i)];
        for (int j = i + 1; j < n; ++j) acc -= at(i, j) * x[static_cast<std::size_t>(j)];
        x[static_cast<std::size_t>(i)] = acc / at(i, i);
    }
    return x;
}

ButcherTableau make_gauss(int s) {
    constexpr std::size_t M = max_gauss_stages;
    // Nodes: roots x of P_s on (−1, 1) by Newton from the asymptotic guesses cos(π(i−¼)/(s+½)),
    // mapped to c = (1 + x)/2 and sorted increasingly.
    std::array<quad, M> c{};
    for (int i = 0; i < s; ++i) {
        quad x = std::cos(std::numbers::pi * (i + 0.75) / (s + 0.5));
        for (int it = 0; it < 100; ++it) {
            const auto [p, dp] = legendre(s, x);
            const quad dx = p / dp;
            x -= dx;
            if (quad_abs(dx) <= quad(1e-32)) break;
        }
        c[static_cast<std::size_t>(i)] = (1 + x) / 2;
    }
    std::sort(c.begin(), c.begin() + s);
    // Vandermonde matrix V_kj = c_j^{k−1}.
    std::array<quad, M * M> V{};
    for (int k = 0; k < s; ++k)
        for (int j = 0; j < s; ++j) {
            quad v = 1;
            for (int e = 0; e < k; ++e) v *= c[static_cast<std::size_t>(j)];
            V[static_cast<std::size_t>(k * s + j)] = v;
        }
    ButcherTableau t{s, {}, {}, {}};
    t.a.resize(static_cast<std::size_t>(s * s));
    // B(s): Σ_j b_j c_j^{k−1} = 1/k.
    std::array<quad, M> rb{};
    for (int k = 0; k < s; ++k) rb[static_cast<std::size_t>(k)] = quad(1) / quad(k + 1);
    const std::array<quad, M> b = solve<M>(V, rb, s);
    // C(s), row i: Σ_j a_ij c_j^{k−1} = c_i^k / k.
    for (int i = 0; i < s; ++i) {
        std::array<quad, M> ra{};
        quad ck = 1;
        for (int k = 0; k < s; ++k) {
            ck *= c[static_cast<std::size_t>(i)];
            ra[static_cast<std::size_t>(k)] = ck / quad(k + 1);
        }
        const std::array<quad, M> ai = solve<M>(V, ra, s);
        for (int j = 0; j < s; ++j)
            t.a[static_cast<std::size_t>(i * s + j)] =
                static_cast<double>(ai[static_cast<std::size_t>(j)]);
    }
    for (int j = 0; j < s; ++j) {
        t.b.push_back(static_cast<double>(b[static_cast<std::size_t>(j)]));
        t.c.push_back(static_cast<double>(c[static_cast<std::size_t>(j)]));
    }
    return t;
}

} // namespace

const ButcherTableau& gauss_tableau(int s) {
    static const std::array<ButcherTableau, max_gauss_stages> all = [] {
        std::array<ButcherTableau, max_gauss_stages> r;
        for (int s = 1; s <= max_gauss_stages; ++s)
            r[static_cast<std::size_t>(s - 1)] = make_gauss(s);
        return r;
    }();
    if (s < 1 || s > max_gauss_stages)
        throw std::out_of_range("gauss_tableau: stages out of range");
    return all[static_cast<std::size_t>(s - 1)];
}

const ButcherTableau& implicit_euler_tableau() {
    static const ButcherTableau t{1, {1.0}, {1.0}, {1.0}};
    return t;
}
const ButcherTableau& explicit_euler_tableau() {
    static const ButcherTableau t{1, {0.0}, {1.0}, {0.0}};
    return t;
}
const ButcherTableau& lobatto_iiia2_tableau() {
    static const ButcherTableau t{2, {0.0, 0.0, 0.5, 0.5}, {0.5, 0.5}, {0.0, 1.0}};
    return t;
}
const ButcherTableau& lobatto_iiib2_tableau() {
    static const ButcherTableau t{2, {0.5, 0.0, 0.5, 0.0}, {0.5, 0.5}, {0.0, 1.0}};
    return t;
}

} // namespace dampsym
