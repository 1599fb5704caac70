#include "pde/nls/schemes.hpp"

#include <cmath>
#include <limits>
#include <numbers>

namespace dampsym::pde {

using cd = std::complex<double>;

NLSStepper::NLSStepper(const PeriodicGrid& g, const NLSParams& p, double dt, NLSScheme s)
    : g_(g), p_(p), dt_(dt), s_(s), fft_(g), buf_(2 * static_cast<size_t>(g.M)),
      inv_sym_(static_cast<size_t>(g.M)), Y_(static_cast<size_t>(g.M)),
      Phi_(static_cast<size_t>(g.M)) {
    // Everything that depends only on the stepper, once: the factor e^{−γΔt} of Y and of the
    // update (1 for IMP), 2iκ/Δt, and the inverse of the linear operator's symbol,
    // 2iκ/Δt + δ_x²'s −4 sin²(θ_j/2)/Δx² (+ 2iγ for IMP).
    const double h = dt_, gam = p_.gamma;
    const bool imp = s_ == NLSScheme::implicit_midpoint;
    const double kappa = (s_ == NLSScheme::etd && gam != 0.0) ? gam * h / std::sinh(gam * h) : 1.0;
    const cd lin_extra = imp ? cd(0.0, 2.0 * gam) : cd(0.0);
    ey_ = imp ? 1.0 : std::exp(-gam * h);
    c2_ = cd(0.0, 2.0 * kappa / h);
    const cd c2 = c2_;
    for (int j = 0; j < g_.M; ++j) {
        const double sj = std::sin(std::numbers::pi * j / g_.M);
        inv_sym_[static_cast<size_t>(j)] = 1.0 / (c2 + lin_extra - 4.0 * sj * sj / (g_.dx * g_.dx));
    }
}

bool NLSStepper::step(double t, CVec& psi) {
    const int M = g_.M;
    const double h = dt_, ey = ey_;
    const cd F = p_.drive == 0.0
                     ? cd(0.0)
                     : p_.drive * std::exp(cd(0.0, p_.omega0 * (t + 0.5 * h) + p_.alpha));
    const cd c2 = c2_;
    CVec& Y = Y_;
    CVec& Phi = Phi_;
    for (int n = 0; n < M; ++n) Y[n] = ey * psi[n];
    Phi = Y;
    auto vprime = [&](double eta) { return p_.cubic ? p_.lambda * eta : p_.lambda; };
    const double eps = std::numeric_limits<double>::epsilon();
    double prev = std::numeric_limits<double>::infinity();
    bool converged = false;
    int it = 0;
    while (!converged && it < 200) {
        ++it;
        for (int n = 0; n < M; ++n) {
            const cd r = c2 * Y[n] - vprime(std::norm(Phi[n])) * Phi[n] + F;
            buf_[2 * n] = r.real();
            buf_[2 * n + 1] = r.imag();
        }
        fft_.forward(buf_);
        for (int j = 0; j < M; ++j) { // divided by the symbol: times its precomputed inverse
            const double a = buf_[2 * j], b = buf_[2 * j + 1];
            const double c = inv_sym_[static_cast<size_t>(j)].real();
            const double d = inv_sym_[static_cast<size_t>(j)].imag();
            buf_[2 * j] = a * c - b * d;
            buf_[2 * j + 1] = a * d + b * c;
        }
        fft_.inverse(buf_);
        // max-norms of the update and of the iterate, from the squared moduli (one sqrt each)
        double diff2 = 0.0, mag2 = 0.0;
        bool finite = true;
        for (int n = 0; n < M; ++n) {
            const cd v(buf_[2 * n], buf_[2 * n + 1]);
            const double m2 = std::norm(v);
            finite = finite && std::isfinite(m2);
            diff2 = std::max(diff2, std::norm(v - Phi[n]));
            mag2 = std::max(mag2, m2);
            Phi[n] = v;
        }
        if (!finite) { // an iteration that overflowed (or met a NaN) has failed, not converged
            max_its_ = std::max(max_its_, it);
            last_its_ = it;
            why_ = "NLS step: the fixed-point iteration produced a non-finite iterate";
            return false;
        }
        const double diff = std::sqrt(diff2), mag = std::sqrt(mag2);
        converged = diff <= 4.0 * eps * std::max(mag, 1e-300) ||
                    (diff <= 1e-12 * mag && diff >= 0.5 * prev);
        prev = diff;
    }
    max_its_ = std::max(max_its_, it);
    last_its_ = it;
    if (!converged) {
        why_ = "NLS step: fixed-point iteration did not converge in 200 iterations";
        return false;
    }
    for (int n = 0; n < M; ++n) psi[n] = ey * (2.0 * Phi[n] - Y[n]); // e^{−γΔt}(2Φ − Y)
    return true;
}

NLSInvariants nls_invariants(const PeriodicGrid& g, const NLSParams& p, SpectralDerivative& D,
                             const CVec& psi) {
    CVec d;
    D.apply(psi, d);
    double i1 = 0, i2 = 0, i3 = 0;
    for (int n = 0; n < g.M; ++n) {
        const double eta = std::norm(psi[n]);
        i1 += (std::conj(psi[n]) * d[n]).imag();
        i2 += eta;
        i3 += -std::norm(d[n]) + (p.cubic ? 0.5 * p.lambda * eta * eta : p.lambda * eta);
    }
    return {g.dx * i1, g.dx * i2, g.dx * i3};
}

CVec nls_plane_wave(const PeriodicGrid& g, const NLSParams& p, double A, int k, double t,
                    bool discrete_k) {
    const double sk = std::sin(0.5 * k * g.dx);
    const double k2 = discrete_k ? 4.0 * sk * sk / (g.dx * g.dx) : double(k) * k;
    const double gam = p.gamma;
    double phase;
    if (!p.cubic) {
        phase = -(k2 - p.lambda) * t;
    } else {
        const double f = gam == 0.0 ? t : -std::expm1(-4.0 * gam * t) / (4.0 * gam);
        phase = -k2 * t + p.lambda * A * A * f;
    }
    CVec out(g.M);
    for (int n = 0; n < g.M; ++n)
        out[n] = A * std::exp(-2.0 * gam * t) * std::exp(cd(0.0, k * g.x(n) + phase));
    return out;
}

} // namespace dampsym::pde
