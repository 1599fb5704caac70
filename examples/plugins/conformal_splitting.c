/* Example dampsym plugin (docs/plugins.md): conformal Stormer-Verlet (csv1, F (2.12), B (2.20)
 * with B's gamma twice ours) as a hand-written step, and a negative control that drops the
 * second exact damping half-step in favour of a first-order Euler damping (not conformal
 * symplectic).
 *
 *   p_half = d1 p + (h/2) F(q, t)          d1 = exp(-2 (Gamma(t + h/2) - Gamma(t)))
 *   q1     = q + h grad T(p_half)
 *   p1     = d2 (p_half + (h/2) F(q1, t + h))  d2 = exp(-2 (Gamma(t + h) - Gamma(t + h/2)))
 */
#include "dampsym/plugin.h"

#include <math.h>
#include <string.h>

enum { MAX_DIM = 4096 };

static int csv1_like(const dampsym_host* host, double t, double h, const double* z, double* z_next,
                     int exact_second_damping) {
    double a[MAX_DIM / 2], f[MAX_DIM / 2];
    const int d = host->dim(host->host_ctx);
    if (d <= 0 || d > MAX_DIM || d % 2 != 0) return 1;
    const int n = d / 2;
    const double hh = 0.5 * h;
    const double d1 = host->damping_factor(host->host_ctx, t, hh);
    const double d2 = exact_second_damping ? host->damping_factor(host->host_ctx, t + hh, hh)
                                           : 1.0 - 2.0 * hh * host->gamma(host->host_ctx, t + hh);
    const double* q = z;
    const double* p = z + n;
    double* q1 = z_next;
    double* p1 = z_next + n;
    host->force(host->host_ctx, t, q, f);
    for (int i = 0; i < n; ++i) p1[i] = d1 * p[i] + hh * f[i];
    host->grad_T(host->host_ctx, p1, a);
    for (int i = 0; i < n; ++i) q1[i] = q[i] + h * a[i];
    host->force(host->host_ctx, t + h, q1, f);
    for (int i = 0; i < n; ++i) p1[i] = d2 * (p1[i] + hh * f[i]);
    return 0;
}

static int csv1_step(void* ctx, const dampsym_host* host, double t, double h, const double* z,
                     double* z_next) {
    (void)ctx;
    return csv1_like(host, t, h, z, z_next, 1);
}

static int csv1_euler_damping_step(void* ctx, const dampsym_host* host, double t, double h,
                                   const double* z, double* z_next) {
    (void)ctx;
    return csv1_like(host, t, h, z, z_next, 0);
}

static const dampsym_method methods[] = {
    {"plugin-csv1", "conformal Stormer-Verlet (csv1) as a C plugin", 2, DAMPSYM_FORM_SEPARABLE,
     DAMPSYM_CLAIM_CONFORMAL_SYMPLECTIC, csv1_step, NULL, NULL},
    {"plugin-csv1-euler-damping",
     "negative control: csv1 with the second damping half-step replaced by 1 - gamma h", 1,
     DAMPSYM_FORM_SEPARABLE, DAMPSYM_CLAIM_NEGATIVE_CONTROL, csv1_euler_damping_step, NULL, NULL},
};

int dampsym_plugin_v1(int host_abi_version, dampsym_plugin_descriptor* out) {
    if (host_abi_version != DAMPSYM_PLUGIN_ABI_VERSION) return 1;
    memset(out, 0, sizeof *out);
    out->abi_version = DAMPSYM_PLUGIN_ABI_VERSION;
    out->name = "conformal_splitting";
    out->n_methods = (int)(sizeof methods / sizeof methods[0]);
    out->methods = methods;
    return 0;
}
