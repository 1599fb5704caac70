#include "pde/burgers/schemes.hpp"

#include <cmath>
#include <limits>
#include <numbers>

namespace dampsym::pde {

void burgers_central_rhs(const PeriodicGrid& g, double gamma, const Vec& u, Vec& out) {
    const int M = g.M;
    out.resize(M);
    const double s = 0.25 / g.dx;
    for (int j = 0; j < M; ++j) {
        const double r = u[g.wrap(j + 1)], l = u[g.wrap(j - 1)];
        out[j] = -(r * r - l * l) * s - 2.0 * gamma * u[j];
    }
}

void burgers_upwind_rhs(const PeriodicGrid& g, double gamma, const Vec& u, Vec& out) {
    const int M = g.M;
    out.resize(M);
    for (int j = 0; j < M; ++j)
        out[j] = -u[j] * (u[j] - u[g.wrap(j - 1)]) / g.dx - 2.0 * gamma * u[j];
}

Vec burgers_gaussian(const PeriodicGrid& g) {
    Vec u(g.M);
    for (int n = 0; n < g.M; ++n)
        u[n] = std::exp(-0.5 * g.x(n) * g.x(n)) / std::sqrt(2.0 * std::numbers::pi);
    return u;
}

namespace {
// s(τ) = (1 − e^{−2γτ})/(2γ), in the expm1 form (τ when γ = 0)
double characteristic_s(double gamma, double tau) {
    return gamma == 0.0 ? tau : -std::expm1(-2.0 * gamma * tau) / (2.0 * gamma);
}
} // namespace

double burgers_gaussian_shock_time(double gamma) {
    const double sb = std::sqrt(2.0 * std::numbers::pi * std::exp(1.0)); // 1/φ(1)
    if (gamma == 0.0) return sb;
    if (2.0 * gamma * sb >= 1.0) return std::numeric_limits<double>::infinity();
    return -std::log1p(-2.0 * gamma * sb) / (2.0 * gamma); // s(τ) = sb
}

bool burgers_characteristic_solution(const PeriodicGrid& g, double gamma, double tau, Vec& out) {
    if (!(tau >= 0.0) || tau >= burgers_gaussian_shock_time(gamma)) return false;
    const double s = characteristic_s(gamma, tau);
    const double period = 2.0 * g.L;
    auto u0 = [&](double xi) { // the periodic extension of the density from [−L, L)
        const double w = xi - period * std::floor((xi + g.L) / period);
        return std::exp(-0.5 * w * w) / std::sqrt(2.0 * std::numbers::pi);
    };
    const double umax = 1.0 / std::sqrt(2.0 * std::numbers::pi); // u0 <= φ(0)
    out.resize(g.M);
    for (int n = 0; n < g.M; ++n) {
        const double x = g.x(n);
        // F(ξ) = ξ + u0(ξ) s − x: F(x − umax s) <= 0 <= F(x), increasing before the shock
        double lo = x - umax * s, hi = x;
        for (int it = 0; it < 200; ++it) {
            const double mid = 0.5 * (lo + hi);
            if (mid <= lo || mid >= hi) break;
            (mid + u0(mid) * s - x < 0.0 ? lo : hi) = mid;
        }
        out[n] = u0(0.5 * (lo + hi)) * std::exp(-2.0 * gamma * tau);
    }
    return true;
}

double solve_cyclic_bidiagonal(const Vec& a, const Vec& b, const Vec& r, Vec& x) {
    const int M = static_cast<int>(r.size());
    // Direction: forward substitution divides by b, backward by a; take the one whose transfer
    // product is at most 1 in modulus (Σ ln|a/b| ≤ 0: forward), so that errors do not grow.
    double lsum = 0.0;
    for (int n = 0; n < M; ++n) lsum += std::log(std::abs(a[n])) - std::log(std::abs(b[n]));
    Vec al(M + 1), be(M + 1);
    double closure, rel;
    if (lsum <= 0.0) {
        al[0] = 0.0;
        be[0] = 1.0;
        for (int n = 0; n < M; ++n) {
            al[n + 1] = (r[n] - a[n] * al[n]) / b[n];
            be[n + 1] = -a[n] * be[n] / b[n];
        }
        closure = 1.0 - be[M];
        rel = std::abs(closure) / (1.0 + std::abs(be[M]));
        if (!(rel > 0.0) || !std::isfinite(rel)) return 0.0;
        x.resize(M);
        x[0] = al[M] / closure;
        for (int n = 1; n < M; ++n) x[n] = al[n] + be[n] * x[0];
    } else {
        // X_n = α_n + β_n X_0 from n = M (X_M = X_0) down: X_n = (r_n − b_n X_{n+1})/a_n.
        al[M] = 0.0;
        be[M] = 1.0;
        for (int n = M - 1; n >= 0; --n) {
            al[n] = (r[n] - b[n] * al[n + 1]) / a[n];
            be[n] = -b[n] * be[n + 1] / a[n];
        }
        closure = 1.0 - be[0];
        rel = std::abs(closure) / (1.0 + std::abs(be[0]));
        if (!(rel > 0.0) || !std::isfinite(rel)) return 0.0;
        x.resize(M);
        x[0] = al[0] / closure;
        for (int n = 1; n < M; ++n) x[n] = al[n] + be[n] * x[0];
    }
    return rel;
}

BurgersStepper::BurgersStepper(const PeriodicGrid& g, double gamma, double dt, BurgersScheme s)
    : g_(g), gamma_(gamma), dt_(dt), s_(s) {}

bool BurgersStepper::step(Vec& u) {
    switch (s_) {
    case BurgersScheme::csv_split:
        return step_split(u);
    case BurgersScheme::box:
        return step_box(u);
    case BurgersScheme::nsfd:
        return step_nsfd(u);
    }
    return false;
}

bool BurgersStepper::step_split(Vec& u) {
    // B (5.10) on the full grid: w = odd j, v = even j (schemes.hpp).
    const int M = g_.M;
    if (M % 2 != 0) {
        why_ = "scheme (5.10) needs an even M (even-odd split (5.9))";
        return false;
    }
    const double e = std::exp(-gamma_ * dt_), h = dt_, s = 0.25 / g_.dx;
    auto flux = [&](int j) { // (u_{j+1}² − u_{j−1}²)/(4Δx), the ∂^± of (5.9)
        const double r = u[g_.wrap(j + 1)], l = u[g_.wrap(j - 1)];
        return (r * r - l * l) * s;
    };
    for (int j = 1; j < M; j += 2) u[j] = e * u[j] - 0.5 * h * flux(j);   // w^{i+½}
    for (int j = 0; j < M; j += 2) u[j] = e * (e * u[j] - h * flux(j));   // v^{i+1}
    for (int j = 1; j < M; j += 2) u[j] = e * (u[j] - 0.5 * h * flux(j)); // w^{i+1}
    return true;
}

bool BurgersStepper::step_nsfd(Vec& u) {
    // (1/φ + u_n/Δx) X_n − (u_n/Δx) X_{n−1} = u_n (1/φ − 2γ), X = u^{i+1}; rows re-indexed
    // m = n − 1: a_m X_m + b_m X_{m+1} = r_m with a_m = −u_{m+1}/Δx, b_m = 1/φ + u_{m+1}/Δx.
    const int M = g_.M;
    const double phi = gamma_ == 0.0 ? dt_ : -std::expm1(-2.0 * gamma_ * dt_) / (2.0 * gamma_);
    Vec a(M), b(M), r(M), x;
    for (int m = 0; m < M; ++m) {
        const double un = u[g_.wrap(m + 1)];
        a[m] = -un / g_.dx;
        b[m] = 1.0 / phi + un / g_.dx;
        r[m] = un * (1.0 / phi - 2.0 * gamma_);
    }
    if (solve_cyclic_bidiagonal(a, b, r, x) < 1e-12) {
        why_ = "NSFD (4.18): singular periodic bidiagonal system";
        return false;
    }
    u = x;
    return true;
}

bool BurgersStepper::step_box(Vec& u) {
    // F_n(X) = (X_n + X_{n+1} − Y_n − Y_{n+1})/(2Δt) + (W_{n+1}² − W_n²)/(2Δx) = 0,
    // W = (X + Y)/2, X = e^{γΔt}u^{i+1}, Y = e^{−γΔt}u^i. Newton from X = Y.
    const int M = g_.M;
    const double h = dt_, dx = g_.dx;
    const Vec Y = std::exp(-gamma_ * h) * u;
    Vec X = Y, W(M), F(M), a(M), b(M), d;
    double prev = std::numeric_limits<double>::infinity();
    bool converged = false;
    int it = 0;
    while (!converged && it < 50) {
        ++it;
        W = 0.5 * (X + Y);
        for (int n = 0; n < M; ++n) {
            const int m = g_.wrap(n + 1);
            F[n] =
                (X[n] + X[m] - Y[n] - Y[m]) / (2.0 * h) + (W[m] * W[m] - W[n] * W[n]) / (2.0 * dx);
            a[n] = 1.0 / (2.0 * h) - W[n] / (2.0 * dx);
            b[n] = 1.0 / (2.0 * h) + W[m] / (2.0 * dx);
        }
        const double rel = solve_cyclic_bidiagonal(a, b, Vec(-F), d);
        if (rel < 1e-10) {
            why_ = "box scheme (5.12): Newton Jacobian singular (alternating mode of A_x, even M, "
                   "with |sum W| too small; use odd M)";
            return false;
        }
        X += d;
        const double nd = d.cwiseAbs().maxCoeff();
        const double scale = std::max(1.0, X.cwiseAbs().maxCoeff());
        // Converged at round-off, or when the corrections stop shrinking below 1e-10.
        converged = nd <= 4.0 * std::numeric_limits<double>::epsilon() * scale ||
                    (nd <= 1e-10 * scale && nd >= 0.5 * prev);
        prev = nd;
    }
    stats_.newton_iterations += it;
    stats_.max_newton_iterations = std::max(stats_.max_newton_iterations, it);
    if (!converged || !X.allFinite()) {
        why_ = "box scheme (5.12): Newton did not converge in 50 iterations";
        return false;
    }
    u = std::exp(-gamma_ * h) * X;
    return true;
}

} // namespace dampsym::pde
