// The observer attached to the step loop when a case asks for trajectory diagnostics. Each part is
// enabled only when requested: states on the output grid (error, energy), per-step conformal laws
// of the problem's invariants (invariants: I_{n+1} = e^{−2(Γ(t_{n+1})−Γ(t_n))} I_n, B Def. 2.3),
// and oscillation maxima of q for d(t) = ln(max U(t)) + Γ(t) (dissipation-drift, F(4.4)).
// Everything is streamed; nothing grows with the number of steps except the requested grid.
#pragma once

#include "core/types.hpp"
#include "diagnostics/capabilities.hpp"
#include "diagnostics/maxima.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

namespace dampsym {

struct InvariantStats {
    double max_step_rel = 0.0;   // max_n |I_{n+1} − e^{−2ΔΓ} I_n| / |I_n|
    double last_step_rel = 0.0;  // the same at the last step
    double max_global_rel = 0.0; // max_n |I_n − e^{−2Γ(t_n)} I_0| / |e^{−2Γ(t_n)} I_0|
    // Least-squares sums for the drift slope of I_n/(e^{−2Γ(t_n)} I_0) − 1 against t.
    double sx = 0, sy = 0, sxx = 0, sxy = 0, count = 0;
    double drift_slope() const {
        const double den = count * sxx - sx * sx;
        return den > 0.0 ? (count * sxy - sx * sy) / den : 0.0;
    }
};

// Per-step conformal law of a vector quantity X (total linear or angular momentum):
// law: X_{n+1} = e^{−2ΔΓ} X_n (B Ex. 1.3); table: X_{n+1} = f X_n with the factor f the method
// declares (B Table 3.1), when it declares one. Residuals are ‖·‖₂ relative to ‖X_n‖₂.
struct VectorLawStats {
    double max_law_rel = 0.0, last_law_rel = 0.0;
    double max_table_rel = 0.0;                                     // only with a table factor
    double first_factor = std::numeric_limits<double>::quiet_NaN(); // X_1·X_0/|X_0|²
    double max_factor_dev = 0.0; // max_n |X_{n+1}·X_n/|X_n|² − f| / f (f = table, else law)
    double initial_norm = 0.0;
};

// Energy balance residual R(t_n) = |D_t H_n − Ḣ_n| with the 8th-order central difference D_t and
// the exact law Ḣ = −2γ(t) p·∇T(p) (B(3.4): for the pendulum Ḣ = −2γp²).
struct EnergyBalanceStats {
    double max = 0.0, last = 0.0, sum = 0.0, max_rate = 0.0;
    std::int64_t count = 0;
};

template <class P>
class Recorder {
public:
    static constexpr int max_invariants = 8;

    Recorder(const P& problem, double t0, double h) : p_(problem), t0_(t0), h_(h) {}

    void record_grid(std::int64_t stride, std::int64_t points) {
        stride_ = stride;
        grid_.resize(p_.dim(), points);
    }
    void track_invariants() { inv_on_ = true; }
    void track_maxima() { max_on_ = true; }
    // table_factor: the method's declared per-step factor of Σp (NaN if it declares none).
    void track_momentum(double table_factor) {
        mom_on_ = true;
        table_factor_ = table_factor;
    }
    void track_energy_balance() { eb_on_ = true; }

    void start(const Vec& z0) {
        if (stride_ > 0) grid_.col(0) = z0;
        if (inv_on_) {
            p_.invariants(t0_, z0, inv_prev_.data());
            inv0_ = inv_prev_;
            stats_.assign(P::invariant_names.size(), InvariantStats{});
        }
        if (max_on_) {
            if constexpr (HasOneDofMaxima<P>) {
                finder_.emplace(p_, t0_);
                finder_->feed(t0_, z0);
            }
        }
        if constexpr (HasMomentum<P>) {
            if (mom_on_) {
                const int k = p_.space_dim() == 3 ? 3 : 1;
                lin_prev_.resize(p_.space_dim());
                lin_now_.resize(p_.space_dim());
                ang_prev_.resize(k);
                ang_now_.resize(k);
                p_.linear_momentum(z0, lin_prev_);
                p_.angular_momentum(z0, ang_prev_);
                lin_.initial_norm = lin_prev_.norm();
                ang_.initial_norm = ang_prev_.norm();
            }
        }
        if constexpr (HasEnergyBalance<P>) {
            if (eb_on_) {
                grad_t_.resize(p_.n());
                eb_push(0, t0_, z0);
            }
        }
    }

    void operator()(std::int64_t n, double t, const Vec& z) {
        if (stride_ > 0 && n % stride_ == 0) grid_.col(n / stride_) = z;
        if (inv_on_) invariants_step(n, t, z);
        if constexpr (HasOneDofMaxima<P>)
            if (max_on_) finder_->feed(t, z);
        if constexpr (HasMomentum<P>)
            if (mom_on_) momentum_step(n, z);
        if constexpr (HasEnergyBalance<P>)
            if (eb_on_) eb_push(n, t, z);
    }

    const Mat& grid() const { return grid_; }
    const std::vector<InvariantStats>& invariant_stats() const { return stats_; }
    std::vector<Maximum> maxima() const {
        return finder_ ? finder_->maxima() : std::vector<Maximum>{};
    }
    const VectorLawStats& linear_momentum_stats() const { return lin_; }
    const VectorLawStats& angular_momentum_stats() const { return ang_; }
    const EnergyBalanceStats& energy_balance_stats() const { return eb_; }

private:
    void vector_law(VectorLawStats& s, const Vec& prev, const Vec& now, double law, double table) {
        const double norm2 = std::max(prev.squaredNorm(), 1e-300);
        const double norm = std::sqrt(norm2);
        const double rel = (now - law * prev).norm() / norm;
        s.max_law_rel = std::max(s.max_law_rel, rel);
        s.last_law_rel = rel;
        const double factor = now.dot(prev) / norm2;
        if (std::isnan(s.first_factor)) s.first_factor = factor;
        const double f = std::isnan(table) ? law : table;
        s.max_factor_dev = std::max(s.max_factor_dev, std::abs(factor - f) / std::abs(f));
        if (!std::isnan(table))
            s.max_table_rel = std::max(s.max_table_rel, (now - table * prev).norm() / norm);
    }

    void momentum_step(std::int64_t n, const Vec& z) {
        if constexpr (HasMomentum<P>) {
            const double law = std::exp(-2.0 * p_.dGamma(time_at(t0_, h_, n - 1), h_));
            p_.linear_momentum(z, lin_now_);
            p_.angular_momentum(z, ang_now_);
            vector_law(lin_, lin_prev_, lin_now_, law, table_factor_);
            vector_law(ang_, ang_prev_, ang_now_, law, std::numeric_limits<double>::quiet_NaN());
            lin_prev_.swap(lin_now_);
            ang_prev_.swap(ang_now_);
        }
    }

    // Sliding window of the last 9 energies; R at the window's centre once it is full.
    void eb_push(std::int64_t n, double t, const Vec& z) {
        if constexpr (HasEnergyBalance<P>) {
            const int nq = p_.n();
            const std::size_t slot = static_cast<std::size_t>(n % 9);
            eb_energy_[slot] = p_.energy(z);
            p_.grad_T(z.tail(nq), grad_t_);
            eb_rate_[slot] = -2.0 * p_.gamma_at(t) * z.tail(nq).dot(grad_t_);
            if (n < 8) return;
            static constexpr std::array<double, 4> c{4.0 / 5.0, -1.0 / 5.0, 4.0 / 105.0,
                                                     -1.0 / 280.0};
            const std::int64_t m = n - 4; // centre
            double d = 0.0;
            for (std::int64_t k = 4; k >= 1; --k)
                d += c[static_cast<std::size_t>(k - 1)] *
                     (eb_energy_[static_cast<std::size_t>((m + k) % 9)] -
                      eb_energy_[static_cast<std::size_t>((m - k) % 9)]);
            const double rate = eb_rate_[static_cast<std::size_t>(m % 9)];
            const double r = std::abs(d / h_ - rate);
            eb_.max = std::max(eb_.max, r);
            eb_.last = r;
            eb_.sum += r;
            eb_.max_rate = std::max(eb_.max_rate, std::abs(rate));
            ++eb_.count;
        }
    }

    void invariants_step(std::int64_t n, double t, const Vec& z) {
        std::array<double, max_invariants> now{};
        p_.invariants(t, z, now.data());
        const double decay_step = std::exp(-2.0 * p_.dGamma(time_at(t0_, h_, n - 1), h_));
        const double two_gamma = 2.0 * (p_.Gamma(t) - p_.Gamma(t0_));
        for (std::size_t k = 0; k < stats_.size(); ++k) {
            InvariantStats& s = stats_[k];
            const double expected = decay_step * inv_prev_[k];
            const double rel =
                std::abs(now[k] - expected) / std::max(std::abs(inv_prev_[k]), 1e-300);
            s.max_step_rel = std::max(s.max_step_rel, rel);
            s.last_step_rel = rel;
            // ratio I_n / (e^{−2Γ} I_0) in log form so that long runs do not underflow
            double ratio = 0.0;
            if (now[k] != 0.0 && inv0_[k] != 0.0) {
                const double sign = (now[k] > 0) == (inv0_[k] > 0) ? 1.0 : -1.0;
                ratio = sign * std::exp(std::log(std::abs(now[k])) - std::log(std::abs(inv0_[k])) +
                                        two_gamma);
            }
            const double g = ratio - 1.0;
            s.max_global_rel = std::max(s.max_global_rel, std::abs(g));
            const double x = t - t0_;
            s.sx += x;
            s.sy += g;
            s.sxx += x * x;
            s.sxy += x * g;
            s.count += 1.0;
            inv_prev_[k] = now[k];
        }
    }

    const P& p_;
    double t0_, h_;
    std::int64_t stride_ = 0;
    Mat grid_;
    bool inv_on_ = false, max_on_ = false, mom_on_ = false, eb_on_ = false;
    std::array<double, max_invariants> inv_prev_{}, inv0_{};
    std::vector<InvariantStats> stats_;
    std::optional<MaximaFinder<P>> finder_;
    double table_factor_ = std::numeric_limits<double>::quiet_NaN();
    Vec lin_prev_, lin_now_, ang_prev_, ang_now_;
    VectorLawStats lin_, ang_;
    std::array<double, 9> eb_energy_{}, eb_rate_{};
    Vec grad_t_;
    EnergyBalanceStats eb_;
};

} // namespace dampsym
