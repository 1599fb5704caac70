// Coefficient-level checks (see coefficient_checks.hpp for the conditions and citations).
#include "methods/coefficient_checks.hpp"

#include <gsl/gsl_eigen.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstddef>
#include <cstdio>
#include <iterator>
#include <limits>
#include <memory>
#include <mutex>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>

namespace dampsym {
namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

std::size_t ui(int i) {
    return static_cast<std::size_t>(i);
}

// The small dense linear algebra of the GLM checks is done by GSL (gsl_eigen_nonsymm, the SVD)
// rather than Eigen's eigen-, QR- and orthogonal decompositions, whose templates cost this file
// about 15 s of compile time in every build; every GSL status is checked.
void gsl_errors_as_statuses() {
    static std::once_flag once;
    std::call_once(once, [] { gsl_set_error_handler_off(); });
}

struct GslMatrix {
    std::unique_ptr<gsl_matrix, decltype(&gsl_matrix_free)> m;
    explicit GslMatrix(const Mat& a)
        : m(gsl_matrix_alloc(static_cast<std::size_t>(a.rows()),
                             static_cast<std::size_t>(a.cols())),
            &gsl_matrix_free) {
        for (Eigen::Index i = 0; i < a.rows(); ++i)
            for (Eigen::Index j = 0; j < a.cols(); ++j)
                gsl_matrix_set(m.get(), static_cast<std::size_t>(i), static_cast<std::size_t>(j),
                               a(i, j));
    }
};

// Whether the symmetric matrix G is positive definite: its Cholesky factorisation G = L Lᵀ exists
// with every pivot positive.
bool positive_definite(const Mat& G) {
    const Eigen::Index n = G.rows();
    Mat L = Mat::Zero(n, n);
    for (Eigen::Index j = 0; j < n; ++j) {
        double d = G(j, j);
        for (Eigen::Index k = 0; k < j; ++k) d -= L(j, k) * L(j, k);
        if (!(d > 0.0)) return false;
        L(j, j) = std::sqrt(d);
        for (Eigen::Index i = j + 1; i < n; ++i) {
            double x = G(i, j);
            for (Eigen::Index k = 0; k < j; ++k) x -= L(i, k) * L(j, k);
            L(i, j) = x / L(j, j);
        }
    }
    return true;
}

// The eigenvalues of a real square matrix (empty if GSL's QR iteration fails).
std::vector<std::complex<double>> eigenvalues(const Mat& V) {
    gsl_errors_as_statuses();
    const std::size_t n = static_cast<std::size_t>(V.rows());
    GslMatrix a(V);
    std::unique_ptr<gsl_vector_complex, decltype(&gsl_vector_complex_free)> ev(
        gsl_vector_complex_alloc(n), &gsl_vector_complex_free);
    std::unique_ptr<gsl_eigen_nonsymm_workspace, decltype(&gsl_eigen_nonsymm_free)> w(
        gsl_eigen_nonsymm_alloc(n), &gsl_eigen_nonsymm_free);
    std::vector<std::complex<double>> out;
    if (gsl_eigen_nonsymm(a.m.get(), ev.get(), w.get()) != GSL_SUCCESS) return out;
    for (std::size_t i = 0; i < n; ++i) {
        const gsl_complex z = gsl_vector_complex_get(ev.get(), i);
        out.emplace_back(GSL_REAL(z), GSL_IMAG(z));
    }
    return out;
}

// The thin SVD M = U diag(σ) Vᵀ (rows ≥ columns, σ decreasing) by GSL; ok = false if it fails.
struct Svd {
    Mat U, V;
    Vec sigma;
    bool ok = false;
};
Svd svd(const Mat& M) {
    gsl_errors_as_statuses();
    const std::size_t cols = static_cast<std::size_t>(M.cols());
    GslMatrix u(M); // overwritten by U
    GslMatrix v(Mat(M.cols(), M.cols()));
    std::unique_ptr<gsl_vector, decltype(&gsl_vector_free)> sigma(gsl_vector_alloc(cols),
                                                                  &gsl_vector_free);
    std::unique_ptr<gsl_vector, decltype(&gsl_vector_free)> work(gsl_vector_alloc(cols),
                                                                 &gsl_vector_free);
    Svd out;
    if (gsl_linalg_SV_decomp(u.m.get(), v.m.get(), sigma.get(), work.get()) != GSL_SUCCESS)
        return out;
    out.U.resize(M.rows(), M.cols());
    out.V.resize(M.cols(), M.cols());
    out.sigma.resize(M.cols());
    for (Eigen::Index j = 0; j < M.cols(); ++j) {
        const auto jj = static_cast<std::size_t>(j);
        out.sigma[j] = gsl_vector_get(sigma.get(), jj);
        for (Eigen::Index i = 0; i < M.rows(); ++i)
            out.U(i, j) = gsl_matrix_get(u.m.get(), static_cast<std::size_t>(i), jj);
        for (Eigen::Index i = 0; i < M.cols(); ++i)
            out.V(i, j) = gsl_matrix_get(v.m.get(), static_cast<std::size_t>(i), jj);
    }
    out.ok = true;
    return out;
}

// The minimum-norm least-squares solution of M x = rhs (rows ≥ columns) by the SVD, singular
// values below max(rows, cols)·ε·σ_max counted as zero (NaN if the SVD fails).
Vec min_norm_solve(const Mat& M, const Vec& rhs) {
    const Svd d = svd(M);
    if (!d.ok) return Vec::Constant(M.cols(), nan);
    const double cutoff = static_cast<double>(std::max(M.rows(), M.cols())) *
                          std::numeric_limits<double>::epsilon() * d.sigma[0];
    Vec c = d.U.transpose() * rhs; // then (Uᵀ rhs)_k / σ_k, 0 for the σ_k counted as zero
    for (Eigen::Index k = 0; k < c.size(); ++k)
        c[k] = d.sigma[k] > cutoff ? c[k] / d.sigma[k] : 0.0;
    return d.V * c;
}

// The rank of a complex square matrix by the SVD of its real form [Re −Im; Im Re] (each singular
// value twice), singular values above `threshold`·σ_max counted (−1 if the SVD fails).
Eigen::Index complex_rank(const Eigen::MatrixXcd& C, double threshold) {
    const Eigen::Index n = C.rows();
    Mat R(2 * n, 2 * n);
    R << C.real(), -C.imag(), C.imag(), C.real();
    const Svd d = svd(R);
    if (!d.ok) return -1;
    return (d.sigma.array() > threshold * d.sigma[0]).count() / 2;
}

Mat matrix_of(const ButcherTableau& t) {
    Mat A(t.stages, t.stages);
    for (int i = 0; i < t.stages; ++i)
        for (int j = 0; j < t.stages; ++j) A(i, j) = t.A(i, j);
    return A;
}

Vec weights_of(const ButcherTableau& t) {
    Vec b(t.stages);
    for (int i = 0; i < t.stages; ++i) b[i] = t.b[ui(i)];
    return b;
}

// Appends to `out` every non-increasing list of indices ≤ max_index (into `trees`) whose orders
// sum to `remaining`, extending `current`.
void multisets(const std::vector<RootedTree>& trees, int remaining, int max_index,
               std::vector<int>& current, std::vector<std::vector<int>>& out) {
    if (remaining == 0) {
        out.push_back(current);
        return;
    }
    for (int k = max_index; k >= 0; --k) {
        if (trees[ui(k)].order > remaining) continue;
        current.push_back(k);
        multisets(trees, remaining - trees[ui(k)].order, k, current, out);
        current.pop_back();
    }
}

// Elementary weights of the trees with `colours` = A.size() colours: colour k uses (A[k], b[k]).
OrderConditions order_conditions(const std::vector<Mat>& A, const std::vector<Vec>& b,
                                 int max_order, double tol) {
    const int colours = static_cast<int>(A.size());
    const std::vector<RootedTree> trees = rooted_trees(max_order, colours);
    const Eigen::Index s = b[0].size();
    OrderConditions oc;
    oc.residual.assign(ui(max_order), 0.0);
    oc.trees.assign(ui(max_order), 0);
    std::vector<Vec> APsi(trees.size()); // A^{(colour(u))} Ψ(u)
    for (std::size_t k = 0; k < trees.size(); ++k) {
        const RootedTree& t = trees[k];
        Vec psi = Vec::Ones(s);
        for (const int u : t.children) psi = psi.cwiseProduct(APsi[ui(u)]);
        APsi[k] = A[ui(t.colour)] * psi;
        const double phi = b[ui(t.colour)].dot(psi);
        double& r = oc.residual[ui(t.order - 1)];
        r = std::max(r, std::abs(phi - 1.0 / t.gamma));
        oc.trees[ui(t.order - 1)] += 1;
    }
    for (int p = 1; p <= max_order && oc.residual[ui(p - 1)] <= tol; ++p) oc.measured_order = p;
    return oc;
}

double max_abs(const Mat& m) {
    return m.size() == 0 ? 0.0 : m.cwiseAbs().maxCoeff();
}

std::string fmt(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2e", v);
    return buf;
}

} // namespace

// Checks of a Runge–Kutta tableau: row sums, order conditions through the declared order and
// their failure at the next, symplecticity (expected as given).
void rk_checks(const ButcherTableau& t, int order, bool symplectic_expected,
               const std::string& symplectic_what, std::vector<CoefficientCheck>& out) {
    const double tol = coefficient_tolerance;
    const double rs = row_sum_residual(t);
    out.push_back({"row-sums", "c = A e (stage times)", true, rs <= tol, rs, tol});
    const OrderConditions oc = rk_order_conditions(t);
    const int p = std::min(order, rk_max_tree_order);
    int count = 0;
    double worst = 0.0;
    for (int k = 1; k <= p; ++k) {
        worst = std::max(worst, oc.residual[ui(k - 1)]);
        count += oc.trees[ui(k - 1)];
    }
    out.push_back({"order-conditions-" + std::to_string(p),
                   "Φ(t) = 1/γ(t) for the " + std::to_string(count) + " rooted trees of order ≤ " +
                       std::to_string(p) + " (measured order " + std::to_string(oc.measured_order) +
                       ")",
                   true, worst <= tol, worst, tol});
    if (order < rk_max_tree_order) {
        const double r = oc.residual[ui(order)];
        out.push_back({"order-conditions-" + std::to_string(order + 1),
                       "some order-" + std::to_string(order + 1) +
                           " condition fails (the declared order is sharp)",
                       false, r <= tol, r, tol});
    }
    const double sr = rk_symplecticity_residual(t);
    out.push_back({"symplectic", symplectic_what, symplectic_expected, sr <= tol, sr, tol});
}

void prk_checks(const ButcherTableau& q, const ButcherTableau& p, int order, bool expected,
                std::vector<CoefficientCheck>& out) {
    const double tol = coefficient_tolerance;
    // Time is a position variable integrated with the q tableau (partitioned_rk.hpp), so the stage
    // times are t + c_i h with c = A e; the p tableau's ĉ is not used (and Lobatto IIIB has
    // ĉ ≠ Â e: ĉ = (0, 1), Â e = (½, ½)).
    const double rs = row_sum_residual(q);
    out.push_back(
        {"row-sums", "c = A e for the q tableau (stage times)", true, rs <= tol, rs, tol});
    const OrderConditions oc = prk_order_conditions(q, p);
    const int pc = std::min(order, prk_max_tree_order);
    int count = 0;
    double worst = 0.0;
    for (int k = 1; k <= pc; ++k) {
        worst = std::max(worst, oc.residual[ui(k - 1)]);
        count += oc.trees[ui(k - 1)];
    }
    out.push_back({"order-conditions-" + std::to_string(pc),
                   "Φ(t) = 1/γ(t) for the " + std::to_string(count) +
                       " bi-coloured trees of order ≤ " + std::to_string(pc) + " (measured order " +
                       std::to_string(oc.measured_order) + ")",
                   true, worst <= tol, worst, tol});
    if (order < prk_max_tree_order) {
        const double r = oc.residual[ui(order)];
        out.push_back({"order-conditions-" + std::to_string(order + 1),
                       "some order-" + std::to_string(order + 1) +
                           " condition fails (the declared order is sharp)",
                       false, r <= tol, r, tol});
    }
    const PrkSymplecticity ps = prk_symplecticity(q, p);
    const double v = std::max(ps.condition, ps.weights);
    out.push_back({"symplectic",
                   "b_i â_ij + b̂_j a_ji − b_i b̂_j = 0 and b = b̂ (HLW VI.4) [condition " +
                       fmt(ps.condition) + ", |b − b̂| " + fmt(ps.weights) + "]",
                   expected, v <= tol, v, tol});
}

namespace {

// The linear test y' = λy, z = hλ: one step of the method maps its r values by
// M(z) = V + z B (I − zA)⁻¹ U, the starting method produces S(z) = V₀ + z B₀ (I − zA₀)⁻¹ U₀ from
// y₀, and the values it carries after a step are those of the exact solution when
// M(z) S(z) = e^z S(z) (BD §2). Returns the largest difference of the power-series coefficients of
// the two sides (exact series: (I − zA)⁻¹ = Σ z^k A^k): through z^p for the principal values (V₀_i
// ≠ 0: the values that approximate the solution, whose order p this is necessary for), through
// z^{p−2} for the others — BS Theorem 3 gives glm4's second value y₂ ≈ (√3/12) h² y'' to its
// leading term only (its O(h³) error alternates in sign with V's eigenvalue −1 and does not lower
// the order of y₁: measured 1.3e-6, 3.5e-8, 1.0e-9 at z = 0.1, 0.05, 0.025, O(z⁵)). It reads every
// coefficient of A, U, B, V and of the starting method. A starting method without stages
// (s0 = 0: y^[0] = V₀ y₀, e.g. an RK method written as a GLM with r = 1) has S(z) = V₀.
double glm_linear_order_residual(const GlmCoefficients& m, int p) {
    std::vector<Mat> M{m.V};
    std::vector<Vec> S{m.V0};
    Mat Ak = Mat::Identity(m.s, m.s);
    Mat A0k = Mat::Identity(m.s0, m.s0);
    for (int k = 1; k <= p; ++k) {
        M.push_back(m.B * Ak * m.U);
        S.push_back(m.s0 == 0 ? Vec::Zero(m.r) : Vec(m.B0 * A0k * m.U0));
        Ak = Ak * m.A;
        A0k = A0k * m.A0;
    }
    double worst = 0.0, fact = 1.0;
    std::vector<double> inv_fact{1.0};
    for (int k = 1; k <= p; ++k) inv_fact.push_back(1.0 / (fact *= k));
    for (int k = 0; k <= p; ++k) {
        Vec lhs = Vec::Zero(m.r), rhs = Vec::Zero(m.r);
        for (int j = 0; j <= k; ++j) {
            lhs += M[ui(j)] * S[ui(k - j)];
            rhs += inv_fact[ui(j)] * S[ui(k - j)];
        }
        for (int i = 0; i < m.r; ++i)
            if (m.V0[i] != 0.0 || k <= p - 2) worst = std::max(worst, std::abs(lhs[i] - rhs[i]));
    }
    return worst;
}

// Stage times: a stage Y = hAF + Uy approximates y(t₀ + c h) when c = A e + U (B₀ e) (the h y'
// part of the starting values y = V₀ y₀ + h B₀ F + …), and the starting method's own stages when
// c₀ = A₀ e (U₀ = e). Without starting stages (s0 = 0) the values start as V₀ y₀, so c = A e.
double glm_stage_time_residual(const GlmCoefficients& m) {
    const Vec e = Vec::Ones(m.s);
    if (m.s0 == 0) return (m.c - m.A * e).cwiseAbs().maxCoeff();
    const Vec e0 = Vec::Ones(m.s0);
    const double main = (m.c - (m.A * e + m.U * (m.B0 * e0))).cwiseAbs().maxCoeff();
    const double start = (m.c0 - m.A0 * e0).cwiseAbs().maxCoeff();
    return std::max(main, start);
}

} // namespace

void glm_order_checks(const GlmCoefficients& m, int order, std::vector<CoefficientCheck>& out) {
    const double tol = coefficient_tolerance;
    const double lin = glm_linear_order_residual(m, order);
    out.push_back({"linear-order-" + std::to_string(order),
                   "M(z) S(z) = e^z S(z) on y' = λy with the starting method S through z^p for "
                   "the principal values, z^{p−2} for the others (BD §2, BS Thm 3; necessary for "
                   "order p)",
                   true, lin <= tol, lin, tol});
    const double st = glm_stage_time_residual(m);
    out.push_back({"stage-times", "c = A e + U B₀ e and c₀ = A₀ e (stage abscissae)", true,
                   st <= tol, st, tol});
}

void glm_checks(const GlmCoefficients& m, bool g_expected, std::vector<CoefficientCheck>& out) {
    const double tol = coefficient_tolerance;
    const GSymplecticity g = glm_g_symplecticity(m);
    const double gv = g.max();
    out.push_back({"g-symplectic",
                   "DA + AᵀD = BᵀGB, G = VᵀGV, DU = BᵀGV with the data's G, D positive definite "
                   "(BS) [" +
                       fmt(g.stages) + ", " + fmt(g.values) + ", " + fmt(g.coupling) + "]",
                   g_expected, g.certificate_valid && gv <= tol, gv, tol});
    const GlmStability st = glm_stability(m);
    out.push_back({"stable",
                   "V power-bounded (BD Def 2.1) [spectral radius " + fmt(st.spectral_radius) +
                       ", max_k≤1000 ‖V^k‖∞ " + fmt(st.max_power_norm) + "]",
                   true, st.power_bounded, st.spectral_radius, 1.0});
    const GlmVectorCondition pre = glm_preconsistency(m);
    out.push_back({"pre-consistent", "V u = u, U u = e for some u (BD Def 2.2)", true,
                   pre.residual <= tol, pre.residual, tol});
    const GlmVectorCondition con = glm_consistency(m);
    out.push_back({"consistent", "B e + V v = u + v for some v (BD Def 2.3)", true,
                   con.residual <= tol, con.residual, tol});
}

std::vector<RootedTree> rooted_trees(int max_order, int colours) {
    std::vector<RootedTree> trees;
    for (int n = 1; n <= max_order; ++n) {
        const int smaller = static_cast<int>(trees.size()); // every tree of order < n
        std::vector<std::vector<int>> children;
        std::vector<int> current;
        multisets(trees, n - 1, smaller - 1, current, children);
        for (int colour = 0; colour < colours; ++colour)
            for (const auto& ch : children) {
                double gamma = n;
                for (const int u : ch) gamma *= trees[ui(u)].gamma;
                trees.push_back({n, colour, ch, gamma});
            }
    }
    return trees;
}

OrderConditions rk_order_conditions(const ButcherTableau& t, int max_order, double tol) {
    return order_conditions({matrix_of(t)}, {weights_of(t)}, max_order, tol);
}

OrderConditions prk_order_conditions(const ButcherTableau& q, const ButcherTableau& p,
                                     int max_order, double tol) {
    return order_conditions({matrix_of(q), matrix_of(p)}, {weights_of(q), weights_of(p)}, max_order,
                            tol);
}

double rk_symplecticity_residual(const ButcherTableau& t) {
    double r = 0.0;
    for (int i = 0; i < t.stages; ++i)
        for (int j = 0; j < t.stages; ++j) {
            const double bi = t.b[ui(i)], bj = t.b[ui(j)];
            r = std::max(r, std::abs(bi * t.A(i, j) + bj * t.A(j, i) - bi * bj));
        }
    return r;
}

double row_sum_residual(const ButcherTableau& t) {
    double r = 0.0;
    for (int i = 0; i < t.stages; ++i) {
        double sum = 0.0;
        for (int j = 0; j < t.stages; ++j) sum += t.A(i, j);
        r = std::max(r, std::abs(t.c[ui(i)] - sum));
    }
    return r;
}

PrkSymplecticity prk_symplecticity(const ButcherTableau& q, const ButcherTableau& p) {
    PrkSymplecticity r{0.0, 0.0};
    for (int i = 0; i < q.stages; ++i) {
        r.weights = std::max(r.weights, std::abs(q.b[ui(i)] - p.b[ui(i)]));
        for (int j = 0; j < q.stages; ++j)
            r.condition =
                std::max(r.condition, std::abs(q.b[ui(i)] * p.A(i, j) + p.b[ui(j)] * q.A(j, i) -
                                               q.b[ui(i)] * p.b[ui(j)]));
    }
    return r;
}

double GSymplecticity::max() const {
    return std::max({stages, values, coupling});
}

GSymplecticity glm_g_symplecticity(const GlmCoefficients& m) {
    if (m.G.rows() != m.r || m.G.cols() != m.r || m.D.rows() != m.s || m.D.cols() != m.s)
        return {nan, nan, nan, false};
    GSymplecticity g;
    g.stages = max_abs(m.D * m.A + m.A.transpose() * m.D - m.B.transpose() * m.G * m.B);
    g.values = max_abs(m.G - m.V.transpose() * m.G * m.V);
    g.coupling = max_abs(m.D * m.U - m.B.transpose() * m.G * m.V);
    const Mat Dd = m.D.diagonal().asDiagonal();
    const bool G_spd = max_abs(m.G - m.G.transpose()) == 0.0 && positive_definite(m.G);
    const bool D_pd = max_abs(m.D - Dd) == 0.0 && m.D.diagonal().minCoeff() > 0.0;
    g.certificate_valid = G_spd && D_pd;
    return g;
}

GlmStability glm_stability(const GlmCoefficients& m) {
    const double tol = 1e-12;
    GlmStability st{0.0, true, 0.0};
    const std::vector<std::complex<double>> lambda = eigenvalues(m.V);
    if (lambda.size() != static_cast<std::size_t>(m.r)) return {nan, false, nan};
    for (std::size_t i = 0; i < lambda.size(); ++i) {
        const double a = std::abs(lambda[i]);
        st.spectral_radius = std::max(st.spectral_radius, a);
        if (a > 1.0 + tol) st.power_bounded = false;
        if (std::abs(a - 1.0) > tol) continue;
        // On the unit circle: algebraic multiplicity must equal geometric multiplicity.
        Eigen::Index mult = 0;
        for (std::size_t j = 0; j < lambda.size(); ++j)
            if (std::abs(lambda[j] - lambda[i]) <= 1e-8) ++mult;
        if (mult > 1) {
            const Eigen::MatrixXcd shifted =
                m.V.cast<std::complex<double>>() - lambda[i] * Eigen::MatrixXcd::Identity(m.r, m.r);
            if (m.r - complex_rank(shifted, 1e-10) != mult) st.power_bounded = false;
        }
    }
    Mat P = Mat::Identity(m.r, m.r);
    for (int k = 1; k <= 1000; ++k) {
        P = P * m.V;
        st.max_power_norm = std::max(st.max_power_norm, P.cwiseAbs().rowwise().sum().maxCoeff());
    }
    return st;
}

GlmVectorCondition glm_preconsistency(const GlmCoefficients& m) {
    Mat M(m.r + m.s, m.r);
    M.topRows(m.r) = m.V - Mat::Identity(m.r, m.r);
    M.bottomRows(m.s) = m.U;
    Vec rhs = Vec::Zero(m.r + m.s);
    rhs.tail(m.s).setOnes();
    GlmVectorCondition out;
    out.vector = min_norm_solve(M, rhs);
    out.residual = (M * out.vector - rhs).cwiseAbs().maxCoeff();
    return out;
}

GlmVectorCondition glm_consistency(const GlmCoefficients& m) {
    const Vec u = glm_preconsistency(m).vector;
    const Mat M = m.V - Mat::Identity(m.r, m.r);
    const Vec rhs = u - m.B * Vec::Ones(m.s);
    GlmVectorCondition out;
    out.vector = min_norm_solve(M, rhs);
    out.residual = (M * out.vector - rhs).cwiseAbs().maxCoeff();
    return out;
}

std::vector<std::string> claim_words(unsigned claims) {
    static const std::pair<unsigned, const char*> names[] = {
        {claim_conformal_symplectic, "conformal-symplectic"},
        {claim_conformal_quadratic, "conformal-quadratic"},
        {claim_angular_momentum, "angular-momentum"},
        {claim_linear_momentum, "linear-momentum"},
        {claim_symplectic_if_undamped, "symplectic-if-undamped"},
        {claim_linear_momentum_cayley, "linear-momentum-cayley"},
        {claim_g_symplectic, "g-symplectic"}};
    std::vector<std::string> out;
    for (unsigned bit = 0; bit < 32; ++bit) {
        const unsigned mask = 1u << bit;
        if ((claims & mask) == 0) continue;
        const auto* it = std::find_if(std::begin(names), std::end(names),
                                      [&](const auto& n) { return n.first == mask; });
        if (it != std::end(names))
            out.emplace_back(it->second);
        else
            out.push_back("claim-bit-" + std::to_string(bit));
    }
    return out;
}

} // namespace dampsym
