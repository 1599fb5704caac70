#include "pde/periodic_grid.hpp"

#include <gsl/gsl_fft_complex.h>

#include <cmath>
#include <numbers>

namespace dampsym::pde {

void forward_difference(const PeriodicGrid& g, const Vec& in, Vec& out) {
    const int M = g.M;
    out.resize(M);
    for (int n = 0; n + 1 < M; ++n) out[n] = (in[n + 1] - in[n]) / g.dx;
    out[M - 1] = (in[0] - in[M - 1]) / g.dx;
}

void forward_average(const PeriodicGrid& g, const Vec& in, Vec& out) {
    const int M = g.M;
    out.resize(M);
    for (int n = 0; n + 1 < M; ++n) out[n] = 0.5 * (in[n + 1] + in[n]);
    out[M - 1] = 0.5 * (in[0] + in[M - 1]);
}

void shift(const PeriodicGrid& g, const Vec& in, Vec& out) {
    const int M = g.M;
    out.resize(M);
    out[0] = in[M - 1];
    for (int n = 1; n < M; ++n) out[n] = in[n - 1];
}

void central_difference(const PeriodicGrid& g, const Vec& in, Vec& out) {
    const int M = g.M;
    out.resize(M);
    const double s = 0.5 / g.dx;
    out[0] = (in[1 % M] - in[M - 1]) * s;
    for (int n = 1; n + 1 < M; ++n) out[n] = (in[n + 1] - in[n - 1]) * s;
    if (M > 1) out[M - 1] = (in[0] - in[M - 2]) * s;
}

void second_difference(const PeriodicGrid& g, const Vec& in, Vec& out) {
    const int M = g.M;
    out.resize(M);
    const double s = 1.0 / (g.dx * g.dx);
    out[0] = (in[1 % M] - 2.0 * in[0] + in[M - 1]) * s;
    for (int n = 1; n + 1 < M; ++n) out[n] = (in[n + 1] - 2.0 * in[n] + in[n - 1]) * s;
    if (M > 1) out[M - 1] = (in[0] - 2.0 * in[M - 1] + in[M - 2]) * s;
}

SpectralDerivative::SpectralDerivative(const PeriodicGrid& g)
    : g_(g), wavetable_(gsl_fft_complex_wavetable_alloc(static_cast<size_t>(g.M))),
      workspace_(gsl_fft_complex_workspace_alloc(static_cast<size_t>(g.M))),
      buf_(2 * static_cast<size_t>(g.M)) {}

SpectralDerivative::~SpectralDerivative() {
    gsl_fft_complex_wavetable_free(static_cast<gsl_fft_complex_wavetable*>(wavetable_));
    gsl_fft_complex_workspace_free(static_cast<gsl_fft_complex_workspace*>(workspace_));
}

void SpectralDerivative::forward(std::vector<double>& data) {
    gsl_fft_complex_forward(data.data(), 1, static_cast<size_t>(g_.M),
                            static_cast<gsl_fft_complex_wavetable*>(wavetable_),
                            static_cast<gsl_fft_complex_workspace*>(workspace_));
}

void SpectralDerivative::inverse(std::vector<double>& data) {
    gsl_fft_complex_inverse(data.data(), 1, static_cast<size_t>(g_.M),
                            static_cast<gsl_fft_complex_wavetable*>(wavetable_),
                            static_cast<gsl_fft_complex_workspace*>(workspace_));
}

double SpectralDerivative::wavenumber(int j) const {
    const int M = g_.M;
    if (2 * j == M) return 0.0;
    const int jj = (2 * j > M) ? j - M : j;
    return std::numbers::pi * jj / g_.L;
}

namespace {
// buf ← ik · buf for every DFT index (the Nyquist coefficient becomes 0).
void multiply_ik(const SpectralDerivative& d, std::vector<double>& buf, int M) {
    for (int j = 0; j < M; ++j) {
        const double k = d.wavenumber(j);
        const double re = buf[2 * j], im = buf[2 * j + 1];
        buf[2 * j] = -k * im;
        buf[2 * j + 1] = k * re;
    }
}
} // namespace

void SpectralDerivative::apply(const Vec& in, Vec& out) {
    const int M = g_.M;
    for (int n = 0; n < M; ++n) {
        buf_[2 * n] = in[n];
        buf_[2 * n + 1] = 0.0;
    }
    forward(buf_);
    multiply_ik(*this, buf_, M);
    inverse(buf_);
    out.resize(M);
    for (int n = 0; n < M; ++n) out[n] = buf_[2 * n];
}

void SpectralDerivative::apply(const std::vector<std::complex<double>>& in,
                               std::vector<std::complex<double>>& out) {
    const int M = g_.M;
    for (int n = 0; n < M; ++n) {
        buf_[2 * n] = in[n].real();
        buf_[2 * n + 1] = in[n].imag();
    }
    forward(buf_);
    multiply_ik(*this, buf_, M);
    inverse(buf_);
    out.resize(M);
    for (int n = 0; n < M; ++n) out[n] = {buf_[2 * n], buf_[2 * n + 1]};
}

bool solve_cyclic_tridiagonal(const Vec& lo, const Vec& di, const Vec& up, const Vec& r, Vec& x) {
    // Numerical Recipes' "cyclic": A = T + u vᵀ with the corners α = A(M−1, 0) = up_{M−1},
    // β = A(0, M−1) = lo_0, u = (g, 0, …, 0, α), v = (1, 0, …, 0, β/g), g = −di_0.
    const int M = static_cast<int>(r.size());
    const double alpha = up[M - 1], beta = lo[0], g = -di[0];
    if (g == 0.0) return false;
    Vec bb = di;
    bb[0] = di[0] - g;
    bb[M - 1] = di[M - 1] - alpha * beta / g;
    // Thomas on T for two right-hand sides (r and u) at once.
    Vec c(M), y(M), z(M);
    Vec u = Vec::Zero(M);
    u[0] = g;
    u[M - 1] = alpha;
    double piv = bb[0];
    if (piv == 0.0) return false;
    c[0] = up[0] / piv;
    y[0] = r[0] / piv;
    z[0] = u[0] / piv;
    for (int n = 1; n < M; ++n) {
        piv = bb[n] - lo[n] * c[n - 1];
        if (piv == 0.0) return false;
        c[n] = (n + 1 < M) ? up[n] / piv : 0.0;
        y[n] = (r[n] - lo[n] * y[n - 1]) / piv;
        z[n] = (u[n] - lo[n] * z[n - 1]) / piv;
    }
    for (int n = M - 2; n >= 0; --n) {
        y[n] -= c[n] * y[n + 1];
        z[n] -= c[n] * z[n + 1];
    }
    const double denom = 1.0 + z[0] + beta * z[M - 1] / g;
    if (denom == 0.0) return false;
    const double fact = (y[0] + beta * y[M - 1] / g) / denom;
    x = y - fact * z;
    return true;
}

void solve_cyclic_tridiagonal(double a, double b, const Vec& r, Vec& x) {
    const int M = static_cast<int>(r.size());
    const Vec lo = Vec::Constant(M, a), up = Vec::Constant(M, a), di = Vec::Constant(M, b);
    solve_cyclic_tridiagonal(lo, di, up, r, x);
}

} // namespace dampsym::pde
