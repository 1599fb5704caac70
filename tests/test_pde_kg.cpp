// Damped Klein–Gordon (B (4.3), §5.1; docs/pde.md): exact solutions (PDE, semi-discrete, box
// scheme), B's schemes (5.3) = csv1 and (5.4) = csv2 on the semi-discrete problem and the MCS box
// scheme (5.5), their consistency and orders, the conformal momentum of Theorem 5.1 with
// non-conformal negative controls (rk4, heun), and the dissipation drift d(t) (5.6); the problem
// klein-gordon-box (the Δt → 0 limit of (5.5)) and (5.5) as the method kg-box on it.
#include "core/method.hpp"
#include "pde/klein_gordon/methods.hpp"
#include "pde/klein_gordon/problem.hpp"
#include "pde/klein_gordon/schemes.hpp"

#include "support/helpers.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

using Catch::Matchers::WithinAbs;
using dampsym::Counters;
using dampsym::KleinGordon;
using dampsym::KleinGordonBox;
using dampsym::MethodInfo;
using dampsym::StepStatus;
using dampsym::Vec;
using dampsym::test::method;
using dampsym::test::verbose;
using namespace dampsym::pde;

namespace {

template <class P = KleinGordon>
P kg(int M, double c, double gamma, int K) {
    dampsym::ParamMap m;
    m["M"] = M;
    m["c"] = c;
    m["gamma"] = gamma;
    m["K"] = K;
    return P::from_params(m);
}

Vec cat(const Vec& a, const Vec& b) {
    Vec z(a.size() + b.size());
    z << a, b;
    return z;
}

// Runs method `id` for n steps from z by the library's (kernel, problem) pair, whose kernel must
// be `kernel`; returns the final state; `each` sees every state.
template <class P, class F>
Vec run(const P& p, const char* id, std::string_view kernel, double h, int n, Vec z, F&& each) {
    Counters cnt;
    const auto k = dampsym::test::stepper_among(p, method(id), h, cnt, {kernel});
    REQUIRE(k != nullptr);
    each(0, z);
    for (int i = 0; i < n; ++i) {
        REQUIRE(k->step(i * h, z) == StepStatus::ok);
        each(i + 1, z);
    }
    return z;
}
template <class P>
Vec run(const P& p, const char* id, std::string_view kernel, double h, int n, Vec z) {
    return run(p, id, kernel, h, n, std::move(z), [](int, const Vec&) {});
}

// A method by id (csv1, csv2, or a tableau of the explicit RK kernel: rk4, heun).
template <class P, class F>
Vec run_id(const P& p, const std::string& id, double h, int n, Vec z, F&& each) {
    const std::string_view kernel =
        id == "csv1" || id == "csv2" ? std::string_view(id) : "explicit-rk";
    return run(p, id.c_str(), kernel, h, n, std::move(z), each);
}

// B (5.3) and (5.4) transcribed literally (F(u) = (δ_x² − c)u).
void b53(const KleinGordon& p, double h, Vec& u, Vec& v) {
    const double g = p.gamma;
    Vec d;
    second_difference(p.grid, u, d);
    const Vec vh = std::exp(-g * h) * v + 0.5 * h * (d - p.c * u);
    u = u + h * vh;
    second_difference(p.grid, u, d);
    v = std::exp(-g * h) * (vh + 0.5 * h * (d - p.c * u));
}
void b54(const KleinGordon& p, double h, Vec& u, Vec& v) {
    const double g = p.gamma, e = std::exp(-0.5 * g * h);
    Vec d;
    second_difference(p.grid, u, d);
    const Vec vh = (e * v + 0.5 * h * (d - p.c * u)) / (1.0 + 0.5 * g * h);
    u = e * ((1.0 + 0.5 * g * h) * e * u + h * vh) / (1.0 - 0.5 * g * h);
    second_difference(p.grid, u, d);
    v = e * ((1.0 - 0.5 * g * h) * vh + 0.5 * h * (d - p.c * u));
}

} // namespace

TEST_CASE("pde kg: exact solutions of the PDE (5.1) and of the semi-discrete system", "[pde]") {
    const KleinGordon p = kg(32, 1.0, 0.375, 2);
    const PeriodicGrid& g = p.grid;
    // Plane wave with the discrete wavenumber solves the semi-discrete system: the FFT solution
    // from its initial data reproduces it.
    const double Wd = kg_frequency(kg_discrete_k2(g, 2), p.c, p.gamma);
    Vec u0, v0, u, v, ue, ve;
    kg_plane_wave(g, p.gamma, 2, Wd, 0.0, u0, v0);
    for (double t : {0.3, 2.0, 11.0}) {
        kg_semidiscrete_exact(g, p.c, p.gamma, 0.0, u0, v0, t, u, v);
        kg_plane_wave(g, p.gamma, 2, Wd, t, ue, ve);
        CHECK(dampsym::test::max_abs(u - ue) <= 1e-14);
        CHECK(dampsym::test::max_abs(v - ve) <= 1e-14);
    }
    // The semi-discrete solution from the PDE's initial data satisfies u' = v, v' = F(u) − 2γv
    // (6th-order central difference in t).
    const Vec z0 = p.initial_state();
    auto zt = [&](double t) {
        Vec z;
        p.exact(0.0, z0, t, z);
        return z;
    };
    const double t = 1.25, h = 1.0 / 256;
    const Vec dz = (45.0 * (zt(t + h) - zt(t - h)) - 9.0 * (zt(t + 2 * h) - zt(t - 2 * h)) +
                    (zt(t + 3 * h) - zt(t - 3 * h))) /
                   (60.0 * h);
    Vec f(p.dim());
    p.rhs(t, zt(t), f);
    CHECK(dampsym::test::max_abs(dz - f) <= 1e-9);
    // (5.1) solves the PDE: u_tt − u_xx + c u + 2γ u_t = 0 with W² = K² + c − γ² (checked by
    // the same differences in t and x at one point).
    const double W = p.W(), K = 2, x = 0.7;
    auto U = [&](double xx, double tt) {
        return std::exp(-p.gamma * tt) * std::cos(K * xx - W * tt);
    };
    const double e = 1e-3;
    const double utt = (U(x, t + e) - 2 * U(x, t) + U(x, t - e)) / (e * e);
    const double uxx = (U(x + e, t) - 2 * U(x, t) + U(x - e, t)) / (e * e);
    const double ut = (U(x, t + e) - U(x, t - e)) / (2 * e);
    CHECK(std::abs(utt - uxx + p.c * U(x, t) + 2 * p.gamma * ut) <= 1e-5);
}

TEST_CASE("pde kg: csv1 and csv2 on the semi-discrete problem are B's schemes (5.3) and (5.4)",
          "[pde]") {
    const KleinGordon p = kg(32, 1.0, 0.375, 1);
    const double h = 0.05;
    const int n = 200;
    for (int which : {3, 4}) {
        Vec u = p.initial_state().head(32), v = p.initial_state().tail(32);
        double worst = 0;
        const Vec zk = run_id(p, which == 3 ? "csv1" : "csv2", h, n, p.initial_state(),
                              [&](int i, const Vec& z) {
                                  if (i == 0) return;
                                  if (which == 3)
                                      b53(p, h, u, v);
                                  else
                                      b54(p, h, u, v);
                                  worst = std::max(worst, dampsym::test::max_abs(z - cat(u, v)) /
                                                              dampsym::test::max_abs(z));
                              });
        INFO("scheme (5." << which << ")");
        CHECK(worst <= 1e-13);
    }
}

TEST_CASE("pde kg: consistency and orders of (5.3), (5.4) against the semi-discrete solution",
          "[pde]") {
    const KleinGordon p = kg(32, 1.0, 0.375, 2);
    const Vec z0 = p.initial_state();
    for (const char* id : {"csv1", "csv2"}) {
        // Local error of one step from a state on the exact trajectory: O(h³).
        std::vector<double> hs, loc, glob;
        Vec za;
        p.exact(0.0, z0, 0.5, za);
        for (double h : {0.04, 0.02, 0.01, 0.005}) {
            Vec ze;
            p.exact(0.5, za, 0.5 + h, ze);
            const Vec z1 = run_id(p, id, h, 1, za, [](int, const Vec&) {});
            hs.push_back(h);
            loc.push_back(dampsym::test::max_abs(z1 - ze));
            // Global error at T = 2.
            const int n = static_cast<int>(std::lround(2.0 / h));
            Vec zT;
            p.exact(0.0, z0, 2.0, zT);
            glob.push_back(
                dampsym::test::max_abs(run_id(p, id, h, n, z0, [](int, const Vec&) {}) - zT));
        }
        const double sl = dampsym::test::log_log_slope(hs, loc),
                     sg = dampsym::test::log_log_slope(hs, glob);
        if (verbose())
            std::printf("[pde kg] %s: local-error slope %.3f, global order %.3f\n", id, sl, sg);
        INFO(id << " local slope " << sl << ", global order " << sg);
        CHECK_THAT(sl, WithinAbs(3.0, 0.1));
        CHECK_THAT(sg, WithinAbs(2.0, 0.1));
    }
}

TEST_CASE("pde kg: space order 2 of the semi-discretisation against the PDE solution (5.1)",
          "[pde]") {
    std::vector<double> dxs, errs;
    for (int M : {16, 32, 64, 128}) {
        const KleinGordon p = kg(M, 1.0, 0.375, 2);
        const double h = 1e-3, T = 1.0;
        const Vec z = run_id(p, "csv1", h, static_cast<int>(std::lround(T / h)), p.initial_state(),
                             [](int, const Vec&) {});
        Vec ue, ve;
        kg_plane_wave(p.grid, p.gamma, p.K, p.W(), T, ue, ve);
        dxs.push_back(p.grid.dx);
        errs.push_back(dampsym::test::max_abs(z.head(M) - ue));
    }
    const double s = dampsym::test::log_log_slope(dxs, errs);
    if (verbose())
        std::printf("[pde kg] csv1 space order %.3f (error at M=128: %.2e)\n", s, errs.back());
    CHECK_THAT(s, WithinAbs(2.0, 0.1));
}

TEST_CASE("pde kg: the box scheme (5.5) against its own exact discrete plane wave", "[pde]") {
    // u^{n,i} = e^{−γt_i} cos(K x_n − Ω t_i) with the scheme's dispersion relation: the scheme
    // reproduces it to round-off (pins every coefficient of the step, the periodic solve included).
    for (int M : {16, 17, 64}) {
        const PeriodicGrid g(M, std::numbers::pi);
        const double c = 1.0, gamma = 0.375, h = 0.1;
        const int K = 3;
        const double Om = kg_box_frequency(g, c, gamma, K, h);
        KGBox box(g, c, gamma, h);
        Vec a, b, va, vb;
        kg_plane_wave(g, gamma, K, Om, 0.0, a, va);
        kg_plane_wave(g, gamma, K, Om, h, b, vb);
        box.set_state(a, b);
        double worst = 0;
        for (int i = 1; i < 500; ++i) {
            box.step();
            kg_plane_wave(g, gamma, K, Om, (i + 1) * h, a, va);
            worst = std::max(worst, dampsym::test::max_abs(box.u_curr() - a) *
                                        std::exp(gamma * (i + 1) * h));
        }
        INFO("M = " << M << ", max relative error " << worst);
        CHECK(worst <= 1e-11);
    }
}

TEST_CASE("pde kg: box scheme (5.5) consistency, time order 2 and space order 2", "[pde]") {
    const double c = 1.0, gamma = 0.375;
    const int K = 2;
    // Time: against the scheme's Δt → 0 limit, the plane wave with Ω̃² = (2/Δx)² tan²(KΔx/2) + c −
    // γ².
    const PeriodicGrid g(32, std::numbers::pi);
    const double tx = 2.0 / g.dx * std::tan(0.5 * K * g.dx);
    const double Wt = std::sqrt(tx * tx + c - gamma * gamma);
    std::vector<double> hs, loc, glob;
    for (double h : {0.04, 0.02, 0.01, 0.005}) {
        KGBox box(g, c, gamma, h);
        Vec a, b, e, va;
        kg_plane_wave(g, gamma, K, Wt, 0.5, a, va);
        kg_plane_wave(g, gamma, K, Wt, 0.5 + h, b, va);
        kg_plane_wave(g, gamma, K, Wt, 0.5 + 2 * h, e, va);
        box.set_state(a, b);
        box.step();
        hs.push_back(h);
        loc.push_back(dampsym::test::max_abs(box.u_curr() - e));
        // Global: second-order start from (u, u_t) at 0, error at T = 2.
        Vec u0, v0;
        kg_plane_wave(g, gamma, K, Wt, 0.0, u0, v0);
        KGBox run(g, c, gamma, h);
        run.start(u0, v0);
        const int n = static_cast<int>(std::lround(2.0 / h));
        for (int i = 1; i < n; ++i) run.step();
        kg_plane_wave(g, gamma, K, Wt, n * h, e, va);
        glob.push_back(dampsym::test::max_abs(run.u_curr() - e));
    }
    const double sl = dampsym::test::log_log_slope(hs, loc),
                 sg = dampsym::test::log_log_slope(hs, glob);
    INFO("box local slope " << sl << ", global order " << sg);
    CHECK_THAT(sl, WithinAbs(4.0, 0.1)); // two-level scheme: O(Δt⁴) per step, order 2
    CHECK_THAT(sg, WithinAbs(2.0, 0.1));
    // Space: against (5.1) at small Δt.
    std::vector<double> dxs, errs;
    for (int M : {16, 32, 64, 128}) {
        const PeriodicGrid gm(M, std::numbers::pi);
        const double h = 1e-3, W = kg_frequency(double(K) * K, c, gamma);
        Vec u0, v0, ue, ve;
        kg_plane_wave(gm, gamma, K, W, 0.0, u0, v0);
        KGBox run(gm, c, gamma, h);
        run.start(u0, v0);
        for (int i = 1; i < 1000; ++i) run.step();
        kg_plane_wave(gm, gamma, K, W, 1.0, ue, ve);
        dxs.push_back(gm.dx);
        errs.push_back(dampsym::test::max_abs(run.u_curr() - ue));
    }
    const double ss = dampsym::test::log_log_slope(dxs, errs);
    if (verbose())
        std::printf("[pde kg] box: local slope %.3f, time order %.3f, space order %.3f\n", sl, sg,
                    ss);
    CHECK_THAT(ss, WithinAbs(2.0, 0.1));
}

TEST_CASE("pde kg: Theorem 5.1, conformal momentum residual r^i of (5.3), (5.4), (5.5), rk4 and "
          "heun are negative controls",
          "[pde]") {
    const KleinGordon p = kg(64, 1.0, 0.375, 1);
    const double h = 0.05, T = 50.0;
    const int n = static_cast<int>(std::lround(T / h));
    // r^i = ln(I^{i+1}/I^i) + 2γΔt (B §5.1.2); also the scaled residual |I^{i+1} − e^{−2γh}I^i|/S.
    auto residuals = [&](const std::string& id, double& rmax, double& smax) {
        rmax = smax = 0;
        double Iprev = 0, Sprev = 0;
        run_id(p, id, h, n, p.initial_state(), [&](int i, const Vec& z) {
            double I, S;
            p.invariants(0, z, &I);
            p.invariant_scales(0, z, &S);
            if (i > 0) {
                rmax = std::max(rmax, std::abs(std::log(I / Iprev) + 2 * p.gamma * h));
                smax = std::max(smax, std::abs(I - std::exp(-2 * p.gamma * h) * Iprev) / Sprev);
            }
            Iprev = I;
            Sprev = S;
        });
    };
    for (const char* id : {"csv1", "csv2", "rk4", "heun"}) {
        double r, s;
        residuals(id, r, s);
        if (verbose()) std::printf("[pde kg] %s: max |r^i| %.2e, max scaled %.2e\n", id, r, s);
        INFO(id << ": max |r^i| " << r << ", scaled " << s);
        if (std::string(id) == "csv1" || std::string(id) == "csv2") {
            CHECK(r <= 1e-13);
            CHECK(s <= 1e-13);
        } else {
            CHECK(r >= 1e-8);
            CHECK(s >= 1e-8);
        }
    }
    // Box scheme: P^i from (u^i, u^{i+1}).
    KGBox box(p.grid, p.c, p.gamma, h);
    const Vec z0 = p.initial_state();
    box.start(z0.head(64), z0.tail(64));
    double rmax = 0, smax = 0, Iprev = box.momentum(), Sprev = box.momentum_scale();
    for (int i = 1; i < n; ++i) {
        box.step();
        const double I = box.momentum();
        rmax = std::max(rmax, std::abs(std::log(I / Iprev) + 2 * p.gamma * h));
        smax = std::max(smax, std::abs(I - std::exp(-2 * p.gamma * h) * Iprev) / Sprev);
        Iprev = I;
        Sprev = box.momentum_scale();
    }
    if (verbose()) std::printf("[pde kg] box (5.5): max |r^i| %.2e, max scaled %.2e\n", rmax, smax);
    CHECK(rmax <= 1e-13);
    CHECK(smax <= 1e-13);
}

TEST_CASE("pde kg: dissipation drift d(t) = ln max_x u + γt (5.6) stays level", "[pde]") {
    const KleinGordon p = kg(64, 1.0, 0.375, 1);
    const double h = 0.05, T = 50.0;
    const int n = static_cast<int>(std::lround(T / h));
    // Least-squares slope of d(t) over the run, and its range.
    auto fit = [&](const std::vector<double>& d, double& sl, double& range) {
        double st = 0, sd = 0, stt = 0, std_ = 0, lo = 1e300, hi = -1e300;
        const int m = static_cast<int>(d.size());
        for (int i = 0; i < m; ++i) {
            const double t = i * h;
            st += t;
            sd += d[i];
            stt += t * t;
            std_ += t * d[i];
            lo = std::min(lo, d[i]);
            hi = std::max(hi, d[i]);
        }
        sl = (m * std_ - st * sd) / (m * stt - st * st);
        range = hi - lo;
    };
    // Sampling bound: max_n cos(K x_n − φ) ≥ cos(KΔx/2), so a drift-free d(t) stays within
    // [ln cos(KΔx/2), 0] plus the phase/amplitude error of the scheme.
    const double band = -std::log(std::cos(0.5 * p.K * p.grid.dx));
    for (const char* id : {"csv1", "csv2", "heun"}) {
        std::vector<double> d;
        run_id(p, id, h, n, p.initial_state(), [&](int i, const Vec& z) {
            d.push_back(std::log(z.head(64).maxCoeff()) + p.gamma * i * h);
        });
        double sl, range;
        fit(d, sl, range);
        if (verbose())
            std::printf("[pde kg] %s: d(t) slope %.2e, range %.2e (sampling band %.2e)\n", id, sl,
                        range, band);
        INFO(id << ": d(t) slope " << sl << ", range " << range);
        if (std::string(id) == "heun") {
            CHECK(std::abs(sl) >= 1e-4); // negative control: drifts
        } else {
            CHECK(std::abs(sl) <= 1e-5);
            CHECK(range <= 2 * band);
        }
    }
    KGBox box(p.grid, p.c, p.gamma, h);
    const Vec z0 = p.initial_state();
    box.start(z0.head(64), z0.tail(64));
    std::vector<double> d{std::log(box.u_prev().maxCoeff()),
                          std::log(box.u_curr().maxCoeff()) + p.gamma * h};
    for (int i = 2; i <= n; ++i) {
        box.step();
        d.push_back(std::log(box.u_curr().maxCoeff()) + p.gamma * i * h);
    }
    double sl, range;
    fit(d, sl, range);
    if (verbose()) std::printf("[pde kg] box: d(t) slope %.2e, range %.2e\n", sl, range);
    CHECK(std::abs(sl) <= 1e-5);
    CHECK(range <= 2 * band);
}

TEST_CASE("pde kg: klein-gordon-box, the dt -> 0 limit of (5.5): force against its symbol, "
          "Jacobian, exact solution, conformal momentum",
          "[pde]") {
    const KleinGordonBox p = kg<KleinGordonBox>(17, 1.0, 0.375, 1);
    const int M = 17;
    // F(cos jx) = −(c + 4 tan²(πj/M)/Δx²) cos jx for every mode j (the cyclic solve against the
    // symbol), relative to the largest symbol (the solve's rounding reaches every mode), and F is
    // linear: its Jacobian is F applied to the unit vectors, symmetric.
    double worst = 0.0, kmax = 0.0;
    for (int j = 0; j < M; ++j) kmax = std::max(kmax, p.c + kg_mode_k2(p.grid, j, KGSymbol::box));
    for (int j = 0; j < M; ++j) {
        Vec q(M), f(M);
        for (int n = 0; n < M; ++n) q[n] = std::cos(j * p.grid.x(n));
        p.force(0.0, q, f);
        const double k2 = p.c + kg_mode_k2(p.grid, j, KGSymbol::box);
        worst = std::max(worst, dampsym::test::max_abs(f + k2 * q) / kmax);
    }
    INFO("force vs symbol " << worst);
    CHECK(worst <= 1e-13);
    dampsym::Mat J(M, M), Jf(M, M);
    p.force_jacobian(0.0, Vec::Zero(M), J);
    for (int k = 0; k < M; ++k) {
        Vec e = Vec::Zero(M), f(M);
        e[k] = 1.0;
        p.force(0.0, e, f);
        Jf.col(k) = f;
    }
    const double js = J.cwiseAbs().maxCoeff();
    CHECK((J - Jf).cwiseAbs().maxCoeff() <= 1e-14 * js);
    CHECK((J - J.transpose()).cwiseAbs().maxCoeff() <= 1e-14 * js);
    // The exact solution from a multi-mode state against rk4 at h = 2e-4 (its error ~ (ωh)⁴ with
    // ω = 19 for sin 7x: 4e-11).
    Vec z0 = p.initial_state();
    for (int n = 0; n < M; ++n) {
        const double x = p.grid.x(n);
        z0[n] += 0.3 * std::cos(3 * x) + 0.1 * std::sin(7 * x);
        z0[M + n] += 0.2 * std::sin(5 * x);
    }
    Vec ex;
    p.exact(0.0, z0, 1.0, ex);
    const Vec rk = run(p, "rk4", "explicit-rk", 2e-4, 5000, z0);
    INFO("exact vs rk4 " << dampsym::test::max_abs(rk - ex));
    CHECK(dampsym::test::max_abs(rk - ex) <= 1e-10);
    // Theorem 5.1 on this semi-discretisation: δ_x commutes with L, so csv1 keeps
    // I_{n+1} = e^{−2γh} I_n; rk4 does not (negative control).
    auto residual = [&](const char* id) {
        double r = 0.0, I0 = 0.0;
        p.invariants(0.0, z0, &I0);
        run_id(p, id, 0.05, 40, z0, [&](int i, const Vec& z) {
            double I, S;
            p.invariants(0.0, z, &I);
            p.invariant_scales(0.0, z, &S);
            if (i > 0) r = std::max(r, std::abs(I - std::exp(-2 * p.gamma * 0.05) * I0) / S);
            I0 = I;
        });
        return r;
    };
    const double r_csv1 = residual("csv1"), r_rk4 = residual("rk4");
    if (verbose())
        std::printf("[pde kg] klein-gordon-box: force vs symbol %.2e, exact vs rk4 %.2e, momentum "
                    "residual csv1 %.2e, rk4 %.2e\n",
                    worst, dampsym::test::max_abs(rk - ex), r_csv1, r_rk4);
    CHECK(r_csv1 <= 1e-13);
    CHECK(r_rk4 >= 1e-8);
    dampsym::ParamMap m;
    m["M"] = 16;
    m["c"] = 1.0;
    m["gamma"] = 0.375;
    m["K"] = 1;
    CHECK_THROWS_AS(KleinGordonBox::from_params(m), std::invalid_argument); // even M
}

TEST_CASE("pde kg: kg-box is pde::KGBox continued through the state, with a second-order v, "
          "only on klein-gordon-box",
          "[pde]") {
    const KleinGordonBox p = kg<KleinGordonBox>(17, 1.0, 0.375, 1);
    const int M = 17;
    const Vec z0 = p.initial_state();
    // A caller that passes back what it got continues (5.5) exactly: bitwise the library stepper.
    {
        const double h = 0.05;
        Counters cnt;
        const auto k = dampsym::test::stepper_among(p, method("kg-box"), h, cnt, {"kg-box"});
        Vec z = z0;
        REQUIRE(dampsym::test::steps_from_zero(k.get(), h, 20, z));
        KGBox box(p.grid, p.c, p.gamma, h);
        box.start(z0.head(M), z0.tail(M));
        for (int i = 1; i < 20; ++i) box.step();
        CHECK(z.head(M) == box.u_curr());
        CHECK(cnt.rhs_evals == 20);
    }
    // u and v both of order 2 against the exact solution of klein-gordon-box (v: the trapezoidal
    // first step, then the three-level difference).
    std::vector<double> hs, eu, ev;
    for (double h : {0.02, 0.01, 0.005}) {
        const int n = static_cast<int>(std::lround(1.0 / h));
        const Vec z = run(p, "kg-box", "kg-box", h, n, z0);
        Vec ex;
        p.exact(0.0, z0, n * h, ex);
        hs.push_back(h);
        eu.push_back(dampsym::test::max_abs(z.head(M) - ex.head(M)));
        ev.push_back(dampsym::test::max_abs(z.tail(M) - ex.tail(M)));
    }
    const double su = dampsym::test::log_log_slope(hs, eu),
                 sv = dampsym::test::log_log_slope(hs, ev);
    if (verbose())
        std::printf("[pde kg] kg-box on klein-gordon-box: order of u %.3f, of v %.3f (errors at "
                    "h = 0.005: %.2e, %.2e)\n",
                    su, sv, eu.back(), ev.back());
    CHECK_THAT(su, WithinAbs(2.0, 0.1));
    CHECK_THAT(sv, WithinAbs(2.0, 0.1));
    STATIC_REQUIRE(dampsym::KGBoxScheme<KleinGordonBox>::applies<KleinGordonBox>);
    STATIC_REQUIRE(!dampsym::KGBoxScheme<KleinGordonBox>::applies<KleinGordon>);
}
