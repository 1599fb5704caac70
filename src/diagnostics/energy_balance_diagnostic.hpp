// Diagnostic "energy-balance": R(t_n) = |D_t H_n − Ḣ_n|, the 8th-order central difference of the
// energy against the exact rate Ḣ = −2γ(t) p·∇T(p) (B(3.4)). The per-step part is
// EnergyBalanceWindow (below).
#pragma once

#include "diagnostics/capabilities.hpp"
#include "diagnostics/diagnostic.hpp"
#include "diagnostics/metric_json.hpp"
#include "diagnostics/observer_part.hpp"
#include "diagnostics/series.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string_view>

namespace dampsym {

struct EnergyBalanceStats {
    double max = 0.0, last = 0.0, sum = 0.0, max_rate = 0.0;
    std::int64_t count = 0;
};

// A sliding window of the last 9 energies and rates; once it is full, R at its centre t_{n−4}
// (with a series, also R against that time).
template <class P>
class EnergyBalanceWindow {
public:
    EnergyBalanceWindow(const P& p, const PartContext& ctx)
        : p_(p), t0_(ctx.t0), h_(ctx.h), grad_t_(p.n()) {
        if (ctx.series_steps > 0) series_.emplace(ctx.series_steps);
    }

    void start(const Vec& z0) { (*this)(0, t0_, z0); }

    void operator()(std::int64_t n, double t, const Vec& z) {
        const int nq = p_.n();
        const std::size_t slot = static_cast<std::size_t>(n % 9);
        energy_[slot] = p_.energy(z);
        p_.grad_T(z.tail(nq), grad_t_);
        rate_[slot] = -2.0 * p_.gamma_at(t) * z.tail(nq).dot(grad_t_);
        if (n < 8) return;
        // the 8th-order central difference D_t H at the centre m
        static constexpr std::array<double, 4> c{4.0 / 5.0, -1.0 / 5.0, 4.0 / 105.0, -1.0 / 280.0};
        const std::int64_t m = n - 4;
        double d = 0.0;
        for (std::int64_t k = 4; k >= 1; --k)
            d += c[static_cast<std::size_t>(k - 1)] *
                 (energy_[static_cast<std::size_t>((m + k) % 9)] -
                  energy_[static_cast<std::size_t>((m - k) % 9)]);
        const double rate = rate_[static_cast<std::size_t>(m % 9)];
        const double r = std::abs(d / h_ - rate);
        stats_.max = std::max(stats_.max, r);
        stats_.last = r;
        stats_.sum += r;
        stats_.max_rate = std::max(stats_.max_rate, std::abs(rate));
        ++stats_.count;
        if (series_) series_->push(time_at(t0_, h_, m), r);
    }

    const EnergyBalanceStats& stats() const { return stats_; }
    void series(nlohmann::json& s) {
        if (series_) s["energy-balance.residual"] = series_->to_json();
    }

private:
    const P& p_;
    double t0_, h_;
    std::array<double, 9> energy_{}, rate_{};
    Vec grad_t_;
    EnergyBalanceStats stats_;
    std::optional<MinMaxDecimator> series_;
};

struct EnergyBalanceDiagnostic {
    static constexpr std::string_view name = "energy-balance";
    static DiagnosticInfo info();
    template <class P>
    static constexpr bool supports = HasEnergyBalance<P>;
    template <class P>
    using Part = EnergyBalanceWindow<P>;
    // Its metrics of one run from the run's view (harness/run/view.hpp: the problem, the case's
    // facts, the recorder and grid, the method, h, the final state, the counters).
    template <class V>
    static json produce(const V& run);
};
DAMPSYM_DIAGNOSTIC(EnergyBalanceDiagnostic, 110);

json energy_balance_metrics(const EnergyBalanceStats& e);

template <class V>
json EnergyBalanceDiagnostic::produce(const V& run) {
    return energy_balance_metrics(run.rec.template part<EnergyBalanceDiagnostic>().stats());
}

} // namespace dampsym
