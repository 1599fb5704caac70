// The kernel of a C plugin's method (include/dampsym/plugin.h, ABI v1, docs/plugins.md): the
// plugin's step function called through its function pointer, with a table of host callbacks
// that evaluate this problem's forms. One class template, instantiated per problem form:
// PluginPlain (z' = f(t, z)), PluginConformal (z' = N(t, z) − γz) and PluginSeparable
// (q' = ∇T(p), p' = F(q, t) − 2γp); a row's form selects one, and it applies only to problems
// offering that form.
//
// The step writes into a buffer of dim + guard cells filled with a sentinel; a plugin that writes
// a guard cell has written past z_next[dim) and the run ends with an error naming it (never a
// crash of the report writer; a write beyond the guard cells is caught by the ASan build). A
// nonzero return is a step that could not be taken (the run's status solve-failed); a non-finite
// z_next is a divergence, as for every kernel. Buffers are allocated in the constructor: the step
// allocates nothing.
//
// step_jacobian(): the plugin's own Jacobian when it exports one; otherwise central differences
// of the plugin's step, column j with δ_j = ε^{1/3} max(1, |z_j|) (2d extra steps):
// truncation O(δ²‖∂³Φ‖) plus rounding O(ε‖Φ‖/δ), so each entry of Ψ to about ε^{2/3} ≈ 4e-11
// relative to the scale of the step map's derivatives (docs/plugins.md). This is the one
// kernel whose E_n may come from finite differences; the report names the source
// (plugin-jacobian or central-differences).
#pragma once

#include "core/method.hpp"
#include "dampsym/plugin.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace dampsym {

template <class P, int FormCode>
class PluginKernel {
public:
    static constexpr std::string_view kernel_id = "plugin";
    using Data = PluginStep;
    static bool accepts(const Data& d) { return d.method && d.method->form == FormCode; }
    template <class Q>
    static constexpr bool applies = [] {
        if constexpr (FormCode == DAMPSYM_FORM_CONFORMAL)
            return Q::has_conformal;
        else if constexpr (FormCode == DAMPSYM_FORM_SEPARABLE)
            return Q::has_separable;
        else
            return true; // every problem offers the plain form
    }();
    static constexpr bool has_step_jacobian = true;
    static constexpr int guard_cells = 8;

    PluginKernel(const P& problem, const MethodInfo& info, double h, Counters& counters)
        : prob_(problem), m_(std::get<PluginStep>(info.data).method), h_(h), c_(counters),
          d_(problem.dim()), n_(d_ / 2), in_(d_), out_(d_), a_(d_), b_(d_),
          next_(static_cast<std::size_t>(d_ + guard_cells)), zj_(d_), zp_(d_), zm_(d_),
          jac_(static_cast<std::size_t>(d_) * static_cast<std::size_t>(d_)) {
        host_.host_ctx = this;
        host_.dim = &dim_cb;
        host_.gamma = &gamma_cb;
        host_.damping_factor = &damping_cb;
        host_.rhs = &rhs_cb;
        host_.conformal_N = nullptr;
        host_.grad_T = nullptr;
        host_.force = nullptr;
        if constexpr (requires(const P& p, double tt, const Vec& zz, Vec& o) { p.N(tt, zz, o); })
            host_.conformal_N = &conformal_cb;
        if constexpr (FormCode == DAMPSYM_FORM_SEPARABLE) {
            host_.grad_T = &grad_T_cb;
            host_.force = &force_cb;
        }
    }

    StepStatus step(double t, Vec& z) {
        const StepStatus s = call_step(t, z.data(), next_.data());
        if (s == StepStatus::ok) std::memcpy(z.data(), next_.data(), sizeof(double) * d_);
        return s;
    }

    StepStatus step_jacobian(double t, Vec& z, Mat& Psi) {
        if (Psi.rows() != d_ || Psi.cols() != d_) Psi.resize(d_, d_);
        if (m_->step_jacobian) {
            const int rc =
                m_->step_jacobian(m_->method_ctx, &host_, t, h_, z.data(), zj_.data(), jac_.data());
            if (rc != 0) return StepStatus::solve_failed;
            for (int i = 0; i < d_; ++i)
                for (int j = 0; j < d_; ++j)
                    Psi(i, j) =
                        jac_[static_cast<std::size_t>(i) * d_ + static_cast<std::size_t>(j)];
            return step(t, z); // z₁ by the step itself, as for every kernel
        }
        constexpr double cbrt_eps = 6.055454452393343e-06; // ε^{1/3}
        for (int j = 0; j < d_; ++j) {
            const double delta = cbrt_eps * std::max(1.0, std::abs(z[j]));
            zp_ = z;
            zm_ = z;
            zp_[j] += delta;
            zm_[j] -= delta;
            const double span = zp_[j] - zm_[j]; // the perturbation as represented
            if (call_step(t, zp_.data(), next_.data()) != StepStatus::ok)
                return StepStatus::solve_failed;
            a_ = Eigen::Map<const Vec>(next_.data(), d_);
            if (call_step(t, zm_.data(), next_.data()) != StepStatus::ok)
                return StepStatus::solve_failed;
            Psi.col(j) = (a_ - Eigen::Map<const Vec>(next_.data(), d_)) / span;
        }
        return step(t, z);
    }

    // How Ψ is obtained (the conformal-symplectic diagnostic reports it).
    const char* jacobian_source() const {
        return m_->step_jacobian ? "plugin-jacobian" : "central-differences";
    }

private:
    static constexpr double sentinel() { return -1.2345678901234567e300; }

    StepStatus call_step(double t, const double* z, double* next) {
        for (int i = d_; i < d_ + guard_cells; ++i) next[i] = sentinel();
        const int rc = m_->step(m_->method_ctx, &host_, t, h_, z, next);
        for (int i = d_; i < d_ + guard_cells; ++i)
            if (!(next[i] == sentinel()))
                throw std::runtime_error(std::string("plugin method ") + m_->id +
                                         " wrote past z_next[" + std::to_string(d_) +
                                         ") (the buffer's guard cells changed)");
        c_.rhs_evals += 1; // one plugin step (its own evaluations are not seen)
        return rc == 0 ? StepStatus::ok : StepStatus::solve_failed;
    }

    static PluginKernel& self(void* ctx) { return *static_cast<PluginKernel*>(ctx); }
    static int dim_cb(void* ctx) { return self(ctx).d_; }
    static double gamma_cb(void* ctx, double t) {
        if constexpr (requires(const P& p, double tt) { p.gamma_at(tt); })
            return self(ctx).prob_.gamma_at(t);
        else
            return std::numeric_limits<double>::quiet_NaN();
    }
    static double damping_cb(void* ctx, double t, double tau) {
        return std::exp(-2.0 * self(ctx).prob_.dGamma(t, tau));
    }
    static void rhs_cb(void* ctx, double t, const double* z, double* out) {
        PluginKernel& k = self(ctx);
        k.in_ = Eigen::Map<const Vec>(z, k.d_);
        k.prob_.rhs(t, k.in_, k.out_);
        Eigen::Map<Vec>(out, k.d_) = k.out_;
    }
    static void conformal_cb(void* ctx, double t, const double* z, double* out) {
        PluginKernel& k = self(ctx);
        if constexpr (requires(const P& p, double tt, const Vec& zz, Vec& o) { p.N(tt, zz, o); }) {
            k.in_ = Eigen::Map<const Vec>(z, k.d_);
            k.prob_.N(t, k.in_, k.out_);
            Eigen::Map<Vec>(out, k.d_) = k.out_;
        }
    }
    static void grad_T_cb(void* ctx, const double* p, double* out) {
        PluginKernel& k = self(ctx);
        if constexpr (FormCode == DAMPSYM_FORM_SEPARABLE) {
            auto pi = k.in_.head(k.n_);
            pi = Eigen::Map<const Vec>(p, k.n_);
            auto po = k.out_.head(k.n_);
            k.prob_.grad_T(pi, po);
            Eigen::Map<Vec>(out, k.n_) = po;
        }
    }
    static void force_cb(void* ctx, double t, const double* q, double* out) {
        PluginKernel& k = self(ctx);
        if constexpr (FormCode == DAMPSYM_FORM_SEPARABLE) {
            auto qi = k.in_.head(k.n_);
            qi = Eigen::Map<const Vec>(q, k.n_);
            auto fo = k.out_.head(k.n_);
            k.prob_.force(t, qi, fo);
            Eigen::Map<Vec>(out, k.n_) = fo;
        }
    }

    const P& prob_;
    const dampsym_method* m_;
    double h_;
    Counters& c_;
    int d_, n_;
    Vec in_, out_, a_, b_;     // callback arguments and results; a finite-difference column
    std::vector<double> next_; // z_next and its guard cells
    Vec zj_, zp_, zm_;         // the plugin Jacobian's z_next; perturbed states
    std::vector<double> jac_;  // the plugin's row-major Jacobian
    dampsym_host host_{};
};

template <class P>
using PluginPlain = PluginKernel<P, DAMPSYM_FORM_PLAIN>;
template <class P>
using PluginConformal = PluginKernel<P, DAMPSYM_FORM_CONFORMAL>;
template <class P>
using PluginSeparable = PluginKernel<P, DAMPSYM_FORM_SEPARABLE>;

} // namespace dampsym
