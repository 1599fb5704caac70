/* The bad-plugin corpus (docs/plugins.md, tests/plugins/CMakeLists.txt): one source compiled once
 * per fault, selected by a BAD_* definition. Load-time faults must give exit 2 naming the library;
 * RUNTIME is a loadable plugin whose methods fail while stepping (NaN, a refused step, a write
 * past z_next[dim) or before z_next[0], an element of z_next left unwritten, a write into z, a
 * callback outside the form after the first step), which must be reported run statuses, never a
 * crash or "ok". EXIT_STEP, QUICK_EXIT_STEP, EXIT_ENTRY and CRASH_STEP end the process from inside
 * the plugin: dampsym must then exit nonzero, naming the plugin, with no report written. */
#include "dampsym/plugin.h"

#include <math.h>
#include <signal.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

__attribute__((unused)) static int copy_step(void* ctx, const dampsym_host* host, double t,
                                             double h, const double* z, double* z_next) {
    (void)ctx;
    (void)t;
    (void)h;
    memcpy(z_next, z, sizeof(double) * (size_t)host->dim(host->host_ctx));
    return 0;
}

#ifdef RUNTIME
static int nan_step(void* ctx, const dampsym_host* host, double t, double h, const double* z,
                    double* z_next) {
    copy_step(ctx, host, t, h, z, z_next);
    if (t > 0.45) z_next[0] = NAN;
    return 0;
}
static int refusing_step(void* ctx, const dampsym_host* host, double t, double h, const double* z,
                         double* z_next) {
    copy_step(ctx, host, t, h, z, z_next);
    return t > 0.45 ? 7 : 0;
}
static int overflowing_step(void* ctx, const dampsym_host* host, double t, double h,
                            const double* z, double* z_next) {
    const int d = host->dim(host->host_ctx);
    copy_step(ctx, host, t, h, z, z_next);
    z_next[d] = 0.0; /* one past the end: the host's guard cell */
    return 0;
}
static int partial_step(void* ctx, const dampsym_host* host, double t, double h, const double* z,
                        double* z_next) {
    (void)ctx;
    (void)host;
    (void)t;
    (void)h;
    z_next[0] = z[0]; /* z_next[1] left as it was */
    return 0;
}
static int underflowing_step(void* ctx, const dampsym_host* host, double t, double h,
                             const double* z, double* z_next) {
    copy_step(ctx, host, t, h, z, z_next);
    z_next[-1] = 0.0; /* one before the start: the host's guard cell */
    return 0;
}
static int input_writing_step(void* ctx, const dampsym_host* host, double t, double h,
                              const double* z, double* z_next) {
    copy_step(ctx, host, t, h, z, z_next);
    ((double*)z)[0] = 42.0; /* z is const */
    return 0;
}
/* a plain-form method that calls grad_T (a separable-form callback) only after t = 0.45, so that
 * the probe step at load does not see it: the host's trap must make the run's status error */
static int late_grad_t_step(void* ctx, const dampsym_host* host, double t, double h,
                            const double* z, double* z_next) {
    copy_step(ctx, host, t, h, z, z_next);
    if (t > 0.45) host->grad_T(host->host_ctx, z + 1, z_next);
    return 0;
}
/* z_next = z with its exact Jacobian, the identity: E_n = |J^-1 - e^{-2 dGamma} J^-1|, relative
 * e^{2 dGamma} - 1 (the plugin-Jacobian path of the host's E_n) */
static int identity_jacobian(void* ctx, const dampsym_host* host, double t, double h,
                             const double* z, double* z_next, double* jac) {
    const int d = host->dim(host->host_ctx);
    copy_step(ctx, host, t, h, z, z_next);
    for (int i = 0; i < d * d; ++i) jac[i] = (i % (d + 1) == 0) ? 1.0 : 0.0;
    return 0;
}
/* Explicit Euler z_next = z + h f(t, z) claiming conformal symplecticity, with a Jacobian of NaNs:
 * E_n measures nothing, so no E_n check may pass on it (docs/conventions.md "No verdict without a
 * measurement"). */
static int euler_step(void* ctx, const dampsym_host* host, double t, double h, const double* z,
                      double* z_next) {
    (void)ctx;
    const int d = host->dim(host->host_ctx);
    host->rhs(host->host_ctx, t, z, z_next);
    for (int i = 0; i < d; ++i) z_next[i] = z[i] + h * z_next[i];
    return 0;
}
static int nan_jacobian(void* ctx, const dampsym_host* host, double t, double h, const double* z,
                        double* z_next, double* jac) {
    const int d = host->dim(host->host_ctx);
    euler_step(ctx, host, t, h, z, z_next);
    for (int i = 0; i < d * d; ++i) jac[i] = NAN;
    return 0;
}
#endif

#if defined(EXIT_STEP) || defined(QUICK_EXIT_STEP) || defined(CRASH_STEP)
/* copies z until t = 0.45 (so the probe step at load passes), then ends the process */
static int ending_step(void* ctx, const dampsym_host* host, double t, double h, const double* z,
                       double* z_next) {
    copy_step(ctx, host, t, h, z, z_next);
    if (t > 0.45) {
#if defined(EXIT_STEP)
        exit(0);
#elif defined(QUICK_EXIT_STEP)
        quick_exit(0);
#else
        raise(SIGSEGV);
#endif
    }
    return 0;
}
#endif
#ifdef BAD_GRAD_T
static int grad_t_step(void* ctx, const dampsym_host* host, double t, double h, const double* z,
                       double* z_next) {
    copy_step(ctx, host, t, h, z, z_next);
    host->grad_T(host->host_ctx, z + 1, z_next); /* not a plain-form callback */
    return 0;
}
#endif
#ifdef BAD_LONG_ID
/* 5000 characters, a newline among them: the message must stay one line, cut */
#define X10 "xxxxxxxxxx"
#define X100 X10 X10 X10 X10 X10 X10 X10 X10 X10 X10
#define X1000 X100 X100 X100 X100 X100 X100 X100 X100 X100 X100
static const char long_id[] = "long\nid" X1000 X1000 X1000 X1000 X1000;
#endif

static const dampsym_method methods[] = {
#if defined(RUNTIME)
    {"bad-nan", "returns NaN after t = 0.45", 1, DAMPSYM_FORM_PLAIN, 0, nan_step, NULL, NULL},
    {"bad-refuse", "refuses the step after t = 0.45", 1, DAMPSYM_FORM_PLAIN, 0, refusing_step, NULL,
     NULL},
    {"bad-oob", "writes z_next[dim]", 1, DAMPSYM_FORM_PLAIN, 0, overflowing_step, NULL, NULL},
    {"jac-identity", "z_next = z, with its Jacobian", 1, DAMPSYM_FORM_PLAIN, 0, copy_step,
     identity_jacobian, NULL},
    {"jac-nan", "explicit Euler claiming conformal symplecticity, its Jacobian NaN", 1,
     DAMPSYM_FORM_PLAIN, DAMPSYM_CLAIM_CONFORMAL_SYMPLECTIC, euler_step, nan_jacobian, NULL},
    {"bad-partial", "writes z_next[0] only", 1, DAMPSYM_FORM_PLAIN, 0, partial_step, NULL, NULL},
    {"bad-underflow", "writes z_next[-1]", 1, DAMPSYM_FORM_PLAIN, 0, underflowing_step, NULL, NULL},
    {"bad-writes-z", "writes into z", 1, DAMPSYM_FORM_PLAIN, 0, input_writing_step, NULL, NULL},
    {"bad-late-grad-t", "a plain-form method calling grad_T after t = 0.45", 1, DAMPSYM_FORM_PLAIN,
     0, late_grad_t_step, NULL, NULL},
#elif defined(EXIT_STEP) || defined(QUICK_EXIT_STEP) || defined(CRASH_STEP)
    {"bad-ends-process", "ends the process after t = 0.45", 1, DAMPSYM_FORM_PLAIN, 0, ending_step,
     NULL, NULL},
#elif defined(BAD_GRAD_T)
    {"bad-grad-t", "a plain-form method calling grad_T", 1, DAMPSYM_FORM_PLAIN, 0, grad_t_step,
     NULL, NULL},
#elif defined(BAD_LONG_ID)
    {long_id, NULL, 1, DAMPSYM_FORM_PLAIN, 0, copy_step, NULL, NULL},
#elif defined(BAD_NULL_STEP)
    {"bad-null-step", NULL, 1, DAMPSYM_FORM_PLAIN, 0, NULL, NULL, NULL},
#elif defined(BAD_DUPLICATE)
    {"bad-twice", NULL, 1, DAMPSYM_FORM_PLAIN, 0, copy_step, NULL, NULL},
    {"bad-twice", NULL, 1, DAMPSYM_FORM_PLAIN, 0, copy_step, NULL, NULL},
#elif defined(BAD_SHADOW)
    {"rk4", "shadows a built-in method", 4, DAMPSYM_FORM_PLAIN, 0, copy_step, NULL, NULL},
#elif defined(BAD_FORM)
    {"bad-form", NULL, 1, 7, 0, copy_step, NULL, NULL},
#else
    {"bad-generic", NULL, 1, DAMPSYM_FORM_PLAIN, 0, copy_step, NULL, NULL},
#endif
};

#ifdef BAD_NO_ENTRY
int not_the_entry(int v, dampsym_plugin_descriptor* out);
int not_the_entry(int v, dampsym_plugin_descriptor* out) {
#else
int dampsym_plugin_v1(int host_abi_version, dampsym_plugin_descriptor* out) {
    int v = host_abi_version;
#endif
    memset(out, 0, sizeof *out);
#ifdef EXIT_ENTRY
    exit(0);
#endif
#ifdef BAD_ENTRY_FAILS
    (void)v;
    (void)methods;
    return 3;
#else
    if (v != DAMPSYM_PLUGIN_ABI_VERSION) return 1;
#ifdef BAD_ABI
    out->abi_version = 2;
#else
    out->abi_version = DAMPSYM_PLUGIN_ABI_VERSION;
#endif
    out->name = "bad";
    out->n_methods = (int)(sizeof methods / sizeof methods[0]);
    out->methods = methods;
    return 0;
#endif
}
