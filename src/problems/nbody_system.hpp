// The reusable core of the damped N-body problems (nbody.hpp has the model and its formulas):
// NBodySystem holds the masses, the space dimension d, the pair potential and every sum (forces,
// their Jacobian, energies, momenta) over the pairs.
#pragma once

#include "core/types.hpp"

#include <array>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace dampsym {

enum class PairPotential { gravity = 0, lennard_jones = 1 };

struct NBodySystem {
    int d = 3;             // space dimension, 2 or 3
    std::vector<double> m; // masses m_i
    PairPotential kind = PairPotential::gravity;
    double G = 1.0;                // gravity: φ = −G m_i m_j / r
    double eps = 1.0, sigma = 1.0; // Lennard-Jones HLW(3.2)

    int bodies() const { return static_cast<int>(m.size()); }
    int n() const { return d * bodies(); }

    // φ_ij(r).
    double phi(int i, int j, double r) const {
        if (kind == PairPotential::gravity) return -G * m[idx(i)] * m[idx(j)] / r;
        const double s6 = sixth(sigma / r);
        return 4.0 * eps * (s6 * s6 - s6);
    }
    // a = φ'(r)/r (B's τ_ij) and b = (φ''(r) − φ'(r)/r)/r², from r² (see the header comment).
    void pair_terms(int i, int j, double r2, double& a, double& b) const {
        if (kind == PairPotential::gravity) {
            const double r = std::sqrt(r2);
            const double gm = G * m[idx(i)] * m[idx(j)];
            a = gm / (r2 * r);
            b = -3.0 * a / r2;
        } else {
            const double s6 = sigma * sigma * sigma * sigma * sigma * sigma / (r2 * r2 * r2);
            const double s12 = s6 * s6;
            a = 24.0 * eps * (s6 - 2.0 * s12) / r2;
            b = eps * (672.0 * s12 - 192.0 * s6) / (r2 * r2);
        }
    }

    // ∇T(p) = M⁻¹p.
    template <class In, class Out>
    void grad_T(const In& p, Out& out) const {
        for (int i = 0; i < bodies(); ++i)
            for (int k = 0; k < d; ++k) out[i * d + k] = p[i * d + k] / m[idx(i)];
    }
    // ∇²T = M⁻¹ = diag(1/m_i I_d).
    template <class In, class Out>
    void hess_T(const In&, Out& out) const {
        out.setZero();
        for (int i = 0; i < bodies(); ++i)
            for (int k = 0; k < d; ++k) out(i * d + k, i * d + k) = 1.0 / m[idx(i)];
    }
    // F = −∇V: F_i = −Σ_{j≠i} τ_ij (q_i − q_j), each pair once (F_j gets the opposite).
    template <class In, class Out>
    void force(const In& q, Out& out) const {
        for (int k = 0; k < n(); ++k) out[k] = 0.0;
        std::array<double, 3> u{};
        for (int i = 0; i < bodies(); ++i) {
            for (int j = i + 1; j < bodies(); ++j) {
                const double r2 = diff(q, i, j, u);
                double a = 0.0, b = 0.0;
                pair_terms(i, j, r2, a, b);
                for (int k = 0; k < d; ++k) {
                    out[i * d + k] -= a * u[idx(k)];
                    out[j * d + k] += a * u[idx(k)];
                }
            }
        }
    }
    // ∂F/∂q (dense, symmetric): blocks −K_ij on the diagonal, +K_ij off it.
    template <class In, class Out>
    void force_jacobian(const In& q, Out& out) const {
        out.setZero();
        std::array<double, 3> u{};
        for (int i = 0; i < bodies(); ++i) {
            for (int j = i + 1; j < bodies(); ++j) {
                const double r2 = diff(q, i, j, u);
                double a = 0.0, b = 0.0;
                pair_terms(i, j, r2, a, b);
                for (int k = 0; k < d; ++k) {
                    for (int l = 0; l < d; ++l) {
                        const double K = (k == l ? a : 0.0) + b * u[idx(k)] * u[idx(l)];
                        out(i * d + k, i * d + l) -= K;
                        out(j * d + k, j * d + l) -= K;
                        out(i * d + k, j * d + l) += K;
                        out(j * d + k, i * d + l) += K;
                    }
                }
            }
        }
    }
    // V(q) = Σ_{i<j} φ_ij(|q_i − q_j|).
    template <class In>
    double potential(const In& q) const {
        double v = 0.0;
        std::array<double, 3> u{};
        for (int i = 0; i < bodies(); ++i)
            for (int j = i + 1; j < bodies(); ++j) v += phi(i, j, std::sqrt(diff(q, i, j, u)));
        return v;
    }
    // T(p) = Σ |p_i|²/(2 m_i).
    template <class In>
    double kinetic(const In& p) const {
        double t = 0.0;
        for (int i = 0; i < bodies(); ++i) {
            double s = 0.0;
            for (int k = 0; k < d; ++k) s += p[i * d + k] * p[i * d + k];
            t += 0.5 * s / m[idx(i)];
        }
        return t;
    }
    // Scales of the momentum laws (docs/conventions.md, "Law residuals and their scales"):
    // Σ‖p_i‖₂ ≥ ‖Σp_i‖₂ and Σ‖q_i‖₂‖p_i‖₂ ≥ every term |q_ia p_ib| of Σ q_i × p_i; both are
    // invariant under rotations and vanish only when every term of the momentum does.
    template <class In>
    double linear_momentum_scale(const In& p) const {
        double s = 0.0;
        for (int i = 0; i < bodies(); ++i) {
            double n2 = 0.0;
            for (int k = 0; k < d; ++k) n2 += p[i * d + k] * p[i * d + k];
            s += std::sqrt(n2);
        }
        return s;
    }
    template <class InQ, class InP>
    double angular_momentum_scale(const InQ& q, const InP& p) const {
        double s = 0.0;
        for (int i = 0; i < bodies(); ++i) {
            double q2 = 0.0, p2 = 0.0;
            for (int k = 0; k < d; ++k) {
                q2 += q[i * d + k] * q[i * d + k];
                p2 += p[i * d + k] * p[i * d + k];
            }
            s += std::sqrt(q2 * p2);
        }
        return s;
    }
    // Σ p_i, length d.
    template <class In>
    void linear_momentum(const In& p, Vec& out) const {
        out.setZero(d);
        for (int i = 0; i < bodies(); ++i)
            for (int k = 0; k < d; ++k) out[k] += p[i * d + k];
    }
    // Σ q_i × p_i: length 3 in 3-D, length 1 (the scalar q_x p_y − q_y p_x) in 2-D.
    template <class InQ, class InP>
    void angular_momentum(const InQ& q, const InP& p, Vec& out) const {
        if (d == 2) {
            out.setZero(1);
            for (int i = 0; i < bodies(); ++i)
                out[0] += q[2 * i] * p[2 * i + 1] - q[2 * i + 1] * p[2 * i];
            return;
        }
        out.setZero(3);
        for (int i = 0; i < bodies(); ++i) {
            const int o = 3 * i;
            out[0] += q[o + 1] * p[o + 2] - q[o + 2] * p[o + 1];
            out[1] += q[o + 2] * p[o] - q[o] * p[o + 2];
            out[2] += q[o] * p[o + 1] - q[o + 1] * p[o];
        }
    }

    // Smallest initial pair distance accepted: with |q|, σ ≤ 1e6 the force and potential terms
    // (σ/r)^12, G m_i m_j/r² stay far below overflow.
    static constexpr double min_distance = 1e-6;

    // Throws std::invalid_argument (prefixed with `who`) unless d ∈ {2,3}, N ≥ 2, every mass > 0,
    // q and p have dN entries and no two initial positions are closer than min_distance.
    void validate(const std::string& who, const std::vector<double>& q0,
                  const std::vector<double>& p0) const {
        if (d != 2 && d != 3) throw std::invalid_argument(who + ": dim must be 2 or 3");
        if (bodies() < 2)
            throw std::invalid_argument(who + ": masses must list at least 2 bodies, got " +
                                        std::to_string(bodies()));
        for (double mi : m)
            if (!(mi > 0.0) || !std::isfinite(mi))
                throw std::invalid_argument(who + ": every mass must be finite and > 0");
        const auto need = static_cast<std::size_t>(n());
        const std::string shape =
            " (dim = " + std::to_string(d) + ", N = " + std::to_string(bodies()) + " masses)";
        // q and p agree with each other on a body count that differs from the masses': the
        // masses are what is wrong (or dim), not q.
        if (q0.size() == p0.size() && q0.size() != need && q0.size() % idx(d) == 0)
            throw std::invalid_argument(who + ": masses lists N = " + std::to_string(bodies()) +
                                        " bodies, but q and p (" + std::to_string(q0.size()) +
                                        " numbers each, dim = " + std::to_string(d) +
                                        ") describe " + std::to_string(q0.size() / idx(d)) +
                                        "; masses, q and p must describe the same bodies");
        if (q0.size() != need)
            throw std::invalid_argument(who + ": q has " + std::to_string(q0.size()) +
                                        " entries, expected dim*N = " + std::to_string(need) +
                                        shape);
        if (p0.size() != need)
            throw std::invalid_argument(who + ": p has " + std::to_string(p0.size()) +
                                        " entries, expected dim*N = " + std::to_string(need) +
                                        shape);
        std::array<double, 3> u{};
        for (int i = 0; i < bodies(); ++i)
            for (int j = i + 1; j < bodies(); ++j)
                if (!(diff(q0, i, j, u) >= min_distance * min_distance))
                    throw std::invalid_argument(
                        who + ": bodies " + std::to_string(i + 1) + " and " +
                        std::to_string(j + 1) +
                        " start closer than 1e-6 (at the same position or nearly)");
    }

private:
    static std::size_t idx(int i) { return static_cast<std::size_t>(i); }
    static double sixth(double x) {
        const double x2 = x * x;
        return x2 * x2 * x2;
    }
    // u = q_i − q_j (first d entries); returns |u|².
    template <class In>
    double diff(const In& q, int i, int j, std::array<double, 3>& u) const {
        double r2 = 0.0;
        for (int k = 0; k < d; ++k) {
            u[idx(k)] = q[idx(i * d + k)] - q[idx(j * d + k)];
            r2 += u[idx(k)] * u[idx(k)];
        }
        return r2;
    }
};

} // namespace dampsym
