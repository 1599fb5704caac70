#include "pde/klein_gordon/schemes.hpp"

#include "reference/oscillator_exact.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

namespace dampsym::pde {

double kg_frequency(double k2, double c, double gamma) {
    return std::sqrt(k2 + c - gamma * gamma);
}

double kg_discrete_k2(const PeriodicGrid& g, int K) {
    const double s = std::sin(0.5 * K * g.dx);
    return 4.0 * s * s / (g.dx * g.dx);
}

double kg_box_frequency(const PeriodicGrid& g, double c, double gamma, int K, double dt) {
    const double tx = std::tan(0.5 * K * g.dx) * 2.0 / g.dx;
    const double rhs = tx * tx + c - gamma * gamma;
    return 2.0 / dt * std::atan(0.5 * dt * std::sqrt(rhs));
}

void kg_plane_wave(const PeriodicGrid& g, double gamma, int K, double W, double t, Vec& u, Vec& v) {
    u.resize(g.M);
    v.resize(g.M);
    const double e = std::exp(-gamma * t);
    for (int n = 0; n < g.M; ++n) {
        const double ph = K * g.x(n) - W * t;
        u[n] = e * std::cos(ph);
        v[n] = e * (-gamma * std::cos(ph) + W * std::sin(ph));
    }
}

double kg_mode_k2(const PeriodicGrid& g, int j, KGSymbol s) {
    const double th2 = std::numbers::pi * j / g.M; // θ/2
    switch (s) {
    case KGSymbol::central: {
        const double sn = std::sin(th2);
        return 4.0 * sn * sn / (g.dx * g.dx);
    }
    case KGSymbol::box: {
        const double tn = std::tan(th2);
        return 4.0 * tn * tn / (g.dx * g.dx);
    }
    case KGSymbol::pde:
        break;
    }
    const double k = std::min(j, g.M - j); // the PDE's wavenumber of mode j
    return k * k;
}

void kg_box_space_operator(const PeriodicGrid& g, const Vec& u, Vec& out) {
    Vec d2;
    second_difference(g, u, d2);
    solve_cyclic_tridiagonal(0.25, 0.5, d2, out);
}

void kg_semidiscrete_exact(const PeriodicGrid& g, double c, double gamma, double t0, const Vec& u0,
                           const Vec& v0, double t, Vec& u, Vec& v, KGSymbol symbol) {
    const int M = g.M;
    SpectralDerivative fft(g);
    std::vector<double> U(2 * static_cast<size_t>(M)), V(2 * static_cast<size_t>(M));
    for (int n = 0; n < M; ++n) {
        U[2 * n] = u0[n];
        U[2 * n + 1] = 0.0;
        V[2 * n] = v0[n];
        V[2 * n + 1] = 0.0;
    }
    fft.forward(U);
    fft.forward(V);
    for (int j = 0; j < M; ++j) {
        const double omega = std::sqrt(c + kg_mode_k2(g, j, symbol));
        for (int part = 0; part < 2; ++part) {
            const OscillatorState st =
                oscillator_exact(omega, gamma, U[2 * j + part], V[2 * j + part], t - t0);
            U[2 * j + part] = st.q;
            V[2 * j + part] = st.p;
        }
    }
    fft.inverse(U);
    fft.inverse(V);
    u.resize(M);
    v.resize(M);
    for (int n = 0; n < M; ++n) {
        u[n] = U[2 * n];
        v[n] = V[2 * n];
    }
}

double kg_momentum(const PeriodicGrid& g, const Vec& u, const Vec& v) {
    Vec du;
    central_difference(g, u, du);
    return g.dx * v.dot(du);
}

double kg_momentum_scale(const PeriodicGrid& g, const Vec& u, const Vec& v) {
    Vec du;
    central_difference(g, u, du);
    return g.dx * v.cwiseAbs().dot(du.cwiseAbs());
}

namespace {
// Centred A_c² = (1,2,1)/4 and D_c² = (1,−2,1)/Δx² (the forward A_x², D_x² shifted by one).
void avg2(const PeriodicGrid& g, const Vec& in, Vec& out) {
    const int M = g.M;
    out.resize(M);
    for (int n = 0; n < M; ++n)
        out[n] = 0.25 * (in[g.wrap(n - 1)] + 2.0 * in[n] + in[g.wrap(n + 1)]);
}

// The two factors of (5.5)'s conformal momentum (B §5.1.2) at the levels u⁰ = u0, u¹ = u1
// (KGBox::momentum and its scale): D_t^{γ/2} A_x² u and δ_x A_t^{γ/2} A_x² u.
std::pair<Vec, Vec> box_momentum_factors(const PeriodicGrid& g, const Vec& u0, const Vec& u1,
                                         double gamma, double dt) {
    const double E = std::exp(0.5 * gamma * dt);
    Vec a0, a1;
    avg2(g, u0, a0);
    avg2(g, u1, a1);
    Vec Dt = (E * a1 - a0 / E) / dt;
    const Vec At = 0.5 * (E * a1 + a0 / E);
    Vec dA;
    central_difference(g, At, dA);
    return {std::move(Dt), std::move(dA)};
}
} // namespace

KGBox::KGBox(const PeriodicGrid& g, double c, double gamma, double dt)
    : g_(g), c_(c), gamma_(gamma), dt_(dt), E2_(std::exp(gamma * dt)) {
    // Step matrix on X = e^{γΔt} u^{i+1} (schemes.hpp): s A_c² − D_c²/4, s = 1/Δt² − (γ²−c)/4.
    const double s = 1.0 / (dt * dt) - 0.25 * (gamma * gamma - c);
    const double idx2 = 1.0 / (g.dx * g.dx);
    a_ = 0.25 * s - 0.25 * idx2;
    b_ = 0.5 * s + 0.5 * idx2;
    factorise();
}

// The step matrix is constant: its Sherman–Morrison/Thomas factorisation (the same operations,
// in the same order, as periodic_grid.cpp's solve_cyclic_tridiagonal with lo = up = a, di = b) is
// computed once, so that a step is two O(M) sweeps with no allocation (bench/bench_pde.cpp).
void KGBox::factorise() {
    const int M = g_.M;
    const double alpha = a_, beta = a_, g = -b_;
    piv_.resize(M);
    cf_.resize(M);
    zf_.resize(M);
    wa_.resize(M);
    wd_.resize(M);
    rhs_.resize(M);
    tmp_.resize(M);
    Vec bb = Vec::Constant(M, b_), u = Vec::Zero(M);
    bb[0] = b_ - g;
    bb[M - 1] = b_ - alpha * beta / g;
    u[0] = g;
    u[M - 1] = alpha;
    piv_[0] = bb[0];
    cf_[0] = a_ / piv_[0];
    zf_[0] = u[0] / piv_[0];
    for (int n = 1; n < M; ++n) {
        piv_[n] = bb[n] - a_ * cf_[n - 1];
        cf_[n] = (n + 1 < M) ? a_ / piv_[n] : 0.0;
        zf_[n] = (u[n] - a_ * zf_[n - 1]) / piv_[n];
    }
    for (int n = M - 2; n >= 0; --n) zf_[n] -= cf_[n] * zf_[n + 1];
    denom_ = 1.0 + zf_[0] + beta * zf_[M - 1] / g;
}

// x = (step matrix)⁻¹ r with the factorisation above (r and x may not alias).
void KGBox::solve_factorised(const Vec& r, Vec& x) const {
    const int M = g_.M;
    x[0] = r[0] / piv_[0];
    for (int n = 1; n < M; ++n) x[n] = (r[n] - a_ * x[n - 1]) / piv_[n];
    for (int n = M - 2; n >= 0; --n) x[n] -= cf_[n] * x[n + 1];
    const double fact = (x[0] + a_ * x[M - 1] / (-b_)) / denom_; // β = a, g = −b
    for (int n = 0; n < M; ++n) x[n] -= fact * zf_[n];
}

void KGBox::set_state(const Vec& u_prev, const Vec& u_curr) {
    u0_ = u_prev;
    u1_ = u_curr;
}

void KGBox::start(const Vec& u0, const Vec& v0) {
    // In y = e^{γt}u the scheme is the undamped three-level box scheme; its equation at i = 0 with
    // the central value y^{−1} = y^1 − 2Δt y'(0), y'(0) = v0 + γu0, gives y^1 by the same
    // cyclic solve as a step (schemes.hpp).
    const double h = dt_, gg = gamma_ * gamma_ - c_;
    const Vec yd = v0 + gamma_ * u0;
    const Vec wa = (u0 + h * yd) / (h * h) + 0.25 * gg * (u0 - h * yd);
    const Vec wd = 0.25 * (u0 - h * yd);
    Vec aw, dw;
    avg2(g_, wa, aw);
    second_difference(g_, wd, dw);
    rhs_ = aw + dw;
    solve_cyclic_tridiagonal(a_, b_, rhs_, tmp_);
    u0_ = u0;
    u1_ = tmp_ / E2_;
}

void KGBox::step() {
    // rhs = A²[(2u − E⁻²u_p)/h²] + D²[(2u + E⁻²u_p)/4] + g A²[(2u + E⁻²u_p)/4], in member buffers
    // (A² = (1,2,1)/4 and D² = δ_x², as avg2 and second_difference).
    const int M = g_.M;
    const double h = dt_, gg = gamma_ * gamma_ - c_;
    const double ie2 = 1.0 / E2_, idx2 = 1.0 / (g_.dx * g_.dx);
    for (int n = 0; n < M; ++n) {
        const double p = 2.0 * u1_[n], m = ie2 * u0_[n];
        wa_[n] = (p - m) / (h * h) + 0.25 * gg * (p + m);
        wd_[n] = 0.25 * (p + m);
    }
    for (int n = 0; n < M; ++n) {
        const int l = n == 0 ? M - 1 : n - 1, r = n + 1 == M ? 0 : n + 1;
        rhs_[n] = 0.25 * (wa_[l] + 2.0 * wa_[n] + wa_[r]) + (wd_[r] - 2.0 * wd_[n] + wd_[l]) * idx2;
    }
    solve_factorised(rhs_, tmp_);
    u0_.swap(u1_);
    for (int n = 0; n < M; ++n) u1_[n] = tmp_[n] * ie2;
}

double KGBox::momentum() const {
    const auto [Dt, dA] = box_momentum_factors(g_, u0_, u1_, gamma_, dt_);
    return g_.dx * Dt.dot(dA);
}

double KGBox::momentum_scale() const {
    const auto [Dt, dA] = box_momentum_factors(g_, u0_, u1_, gamma_, dt_);
    return g_.dx * Dt.cwiseAbs().dot(dA.cwiseAbs());
}

} // namespace dampsym::pde
