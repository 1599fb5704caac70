// The kernel of a C plugin's method (include/dampsym/plugin.h, ABI v1, docs/plugins.md): the
// plugin's step function called through its function pointer, with a table of host callbacks
// that evaluate this problem's forms. One class template, instantiated per problem form:
// PluginPlain (z' = f(t, z)), PluginConformal (z' = N(t, z) − γz) and PluginSeparable
// (q' = ∇T(p), p' = F(q, t) − 2γp); a row's form selects one, and it applies only to problems
// offering that form.
//
// Every array the host hands the plugin has 8 guard cells on BOTH sides holding a sentinel: the
// state z (a copy, checked unchanged after the step: the plugin got it const), z_next (its cells
// preset to a signalling-NaN pattern that no computation produces, and each checked overwritten
// when the step reports success) and, on the step-Jacobian path, z_next and the d × d Jacobian
// likewise. A changed guard cell (a write before [0] or past [dim)), an element of z_next left
// unwritten or a changed z ends the run with status `error` and a message naming the method and
// the index (never a crash of the report writer, never "ok" with a stale element); a write beyond
// the guard cells is caught by the ASan build. A callback outside the method's form (grad_T for a
// plain-form method, say) is never a null pointer: it is a trap that records the misuse, writes
// nothing, and ends the run with status `error` naming it (load_plugin's probe step refuses such
// a method at load already when its first step makes the call). A nonzero return is a step that
// could not be taken (the run's status solve-failed); a non-finite z_next is a divergence, as for
// every kernel. Each call into the plugin is marked (plugin_call.hpp), so that an exit() or a
// crash inside it is reported as the plugin's and never ends dampsym with status 0. Buffers are
// allocated in the constructor: the step allocates nothing.
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
#include "methods/plugin_buffers.hpp"
#include "methods/plugin_call.hpp"

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
    static constexpr int guard_cells = static_cast<int>(GuardedBuffer::guard);

    PluginKernel(const P& problem, const MethodInfo& info, double h, Counters& counters)
        : prob_(problem), m_(std::get<PluginStep>(info.data).method), h_(h), c_(counters),
          d_(problem.dim()), n_(d_ / 2), in_(d_), out_(d_), a_(d_), zp_(d_), zm_(d_),
          z_(static_cast<std::size_t>(d_)), next_(static_cast<std::size_t>(d_)),
          zj_(static_cast<std::size_t>(d_)),
          jac_(static_cast<std::size_t>(d_) * static_cast<std::size_t>(d_)),
          site_step_{std::get<PluginStep>(info.data).library, m_->id, "step"},
          site_jac_{std::get<PluginStep>(info.data).library, m_->id, "step_jacobian"} {
        host_.host_ctx = this;
        host_.dim = &dim_cb;
        host_.gamma = &gamma_cb;
        host_.damping_factor = &damping_cb;
        host_.rhs = &rhs_cb;
        // the callbacks of other forms are traps, never null (docs/plugins.md)
        host_.conformal_N = &trap_state_cb<0>;
        host_.grad_T = &trap_vector_cb;
        host_.force = &trap_state_cb<1>;
        if constexpr (FormCode == DAMPSYM_FORM_CONFORMAL) host_.conformal_N = &conformal_cb;
        if constexpr (FormCode == DAMPSYM_FORM_SEPARABLE) {
            host_.grad_T = &grad_T_cb;
            host_.force = &force_cb;
        }
    }

    StepStatus step(double t, Vec& z) {
        const StepStatus s = call_step(t, z.data());
        if (s == StepStatus::ok) std::memcpy(z.data(), next_.data(), sizeof(double) * d_);
        return s;
    }

    StepStatus step_jacobian(double t, Vec& z, Mat& Psi) {
        if (Psi.rows() != d_ || Psi.cols() != d_) Psi.resize(d_, d_);
        if (m_->step_jacobian) {
            if (call_jacobian(t, z.data()) != StepStatus::ok) return StepStatus::solve_failed;
            for (int i = 0; i < d_; ++i)
                for (int j = 0; j < d_; ++j)
                    Psi(i, j) =
                        jac_.data()[static_cast<std::size_t>(i) * d_ + static_cast<std::size_t>(j)];
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
            if (call_step(t, zp_.data()) != StepStatus::ok) return StepStatus::solve_failed;
            a_ = Eigen::Map<const Vec>(next_.data(), d_);
            if (call_step(t, zm_.data()) != StepStatus::ok) return StepStatus::solve_failed;
            Psi.col(j) = (a_ - Eigen::Map<const Vec>(next_.data(), d_)) / span;
        }
        return step(t, z);
    }

    // How Ψ is obtained (the conformal-symplectic diagnostic reports it).
    const char* jacobian_source() const {
        return m_->step_jacobian ? "plugin-jacobian" : "central-differences";
    }

private:
    StepStatus call_step(double t, const double* z) {
        z_.arm_copy(z);
        next_.arm_unwritten();
        misuse_ = nullptr;
        int rc = 0;
        {
            const PluginCall mark(site_step_);
            rc = m_->step(m_->method_ctx, &host_, t, h_, z_.data(), next_.data());
        }
        c_.rhs_evals += 1; // one plugin step (its own evaluations are not seen)
        audit("step", z, rc, next_, "z_next");
        return rc == 0 ? StepStatus::ok : StepStatus::solve_failed;
    }

    StepStatus call_jacobian(double t, const double* z) {
        z_.arm_copy(z);
        zj_.arm_unwritten();
        jac_.arm_unwritten();
        misuse_ = nullptr;
        int rc = 0;
        {
            const PluginCall mark(site_jac_);
            rc = m_->step_jacobian(m_->method_ctx, &host_, t, h_, z_.data(), zj_.data(),
                                   jac_.data());
        }
        audit("step_jacobian", z, rc, zj_, "z_next");
        audit("step_jacobian", z, rc, jac_, "jac");
        return rc == 0 ? StepStatus::ok : StepStatus::solve_failed;
    }

    // After a call: a callback outside the form, a guard cell changed, z changed, or (on success)
    // an element left unwritten is the run's error, naming the method and the index. The checks
    // allocate nothing; a message is built only for a fault.
    void audit(const char* fn, const double* z, int rc, const GuardedBuffer& out,
               const char* name) {
        if (misuse_)
            fail(fn, std::string("called the host callback ") + misuse_ +
                         ", which its form does not provide (docs/plugins.md)");
        if (!out.guards_intact())
            fail(fn, "wrote " + out.guard_fault(name) + " (the buffer's guard cells changed)");
        if (!z_.guards_intact() || !z_.payload_equals(z))
            fail(fn, "wrote into its input z (const; the host's copy or its guard cells changed)");
        if (rc != 0) return;
        if (const std::ptrdiff_t i = out.first_unwritten(); i >= 0)
            fail(fn, std::string("returned success without writing ") + name + "[" +
                         std::to_string(i) + "] (of " + std::to_string(out.size()) + " elements)");
    }
    // The run ends with this error; the guards are re-armed in case the kernel is used again.
    [[noreturn]] void fail(const char* fn, const std::string& what) {
        for (GuardedBuffer* b : {&z_, &next_, &zj_, &jac_}) b->rearm_guards();
        throw std::runtime_error(std::string("plugin method ") + m_->id + " (" + fn + ") " + what);
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
    // A callback the method's form does not provide: recorded, nothing written (the size of the
    // plugin's array is unknown), the step then fails (audit).
    template <int Which>
    static void trap_state_cb(void* ctx, double, const double*, double*) {
        self(ctx).misuse_ = Which == 0 ? "conformal_N" : "force";
    }
    static void trap_vector_cb(void* ctx, const double*, double*) { self(ctx).misuse_ = "grad_T"; }
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
    Vec in_, out_, a_;   // callback arguments and results; a finite-difference column
    Vec zp_, zm_;        // perturbed states
    GuardedBuffer z_;    // the host's copy of z handed to the plugin
    GuardedBuffer next_; // z_next
    GuardedBuffer zj_;   // the plugin Jacobian's z_next
    GuardedBuffer jac_;  // the plugin's row-major Jacobian
    PluginCallSite site_step_, site_jac_;
    const char* misuse_ = nullptr; // a trap callback the last call hit
    dampsym_host host_{};
};

template <class P>
using PluginPlain = PluginKernel<P, DAMPSYM_FORM_PLAIN>;
template <class P>
using PluginConformal = PluginKernel<P, DAMPSYM_FORM_CONFORMAL>;
template <class P>
using PluginSeparable = PluginKernel<P, DAMPSYM_FORM_SEPARABLE>;

} // namespace dampsym
