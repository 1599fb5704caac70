/* dampsym plugin ABI, version 1 (docs/plugins.md).
 *
 * A plugin is a shared library exporting one symbol, DAMPSYM_PLUGIN_ENTRY_NAME, of type
 * dampsym_plugin_entry_fn. dampsym calls it once after dlopen(RTLD_NOW | RTLD_LOCAL) with the ABI
 * version it speaks; the plugin fills a descriptor listing its methods or returns nonzero.
 *
 * Damping convention (docs/conventions.md): q' = grad T(p), p' = F(q, t) - 2 gamma(t) p, with
 * F = -grad V for a potential problem; the exact damping flow over [t, t + tau] multiplies p by
 * exp(-2 (Gamma(t + tau) - Gamma(t))), given by the host callback damping_factor.
 *
 * The state z has length dim(): z = (q, p) for the separable form (n = dim / 2 each).
 * A step reads z[0 .. dim) and writes z_next[0 .. dim) only (z and z_next never alias); it returns
 * 0 on success, having written every element of z_next, and nonzero when it cannot take the step
 * (reported as the run's solve-failed status). It calls only the callbacks of its form (dim, gamma,
 * damping_factor and rhs always; conformal_N in the conformal form; grad_T and force in the
 * separable form). The host checks each of these (docs/plugins.md): a write outside z_next, into
 * z, an element left unwritten or a callback of another form is the run's error status; a plugin
 * that calls exit() or crashes ends dampsym with a nonzero status and no report.
 */
#ifndef DAMPSYM_PLUGIN_H
#define DAMPSYM_PLUGIN_H

#ifdef __cplusplus
extern "C" {
#endif

#define DAMPSYM_PLUGIN_ABI_VERSION 1
#define DAMPSYM_PLUGIN_ENTRY_NAME "dampsym_plugin_v1"

/* The problem form a method steps. */
enum dampsym_form {
    DAMPSYM_FORM_PLAIN = 1,     /* z' = f(t, z) (rhs callback) */
    DAMPSYM_FORM_CONFORMAL = 2, /* z' = N(t, z) - gamma(t) z (conformal_N callback) */
    DAMPSYM_FORM_SEPARABLE = 3  /* q' = grad T(p), p' = F(q, t) - 2 gamma(t) p */
};

/* Structural claims a method makes; each is measured by dampsym, never trusted. */
enum dampsym_claim {
    DAMPSYM_CLAIM_NONE = 0,
    DAMPSYM_CLAIM_CONFORMAL_SYMPLECTIC = 1u << 0,
    DAMPSYM_CLAIM_SYMPLECTIC = 1u << 1,
    DAMPSYM_CLAIM_NEGATIVE_CONTROL = 1u << 2 /* deliberately broken: expected to fail its checks */
};

/* Callbacks into the host; host_ctx is passed back unchanged. Vectors are contiguous doubles. */
typedef struct dampsym_host {
    void* host_ctx;
    int (*dim)(void* host_ctx);                /* length of z */
    double (*gamma)(void* host_ctx, double t); /* gamma(t) */
    double (*damping_factor)(void* host_ctx, double t,
                             double tau); /* exp(-2(Gamma(t+tau)-Gamma(t))) */
    /* PLAIN form: out = f(t, z), length dim. */
    void (*rhs)(void* host_ctx, double t, const double* z, double* out);
    /* CONFORMAL form: out = N(t, z), length dim. */
    void (*conformal_N)(void* host_ctx, double t, const double* z, double* out);
    /* SEPARABLE form (n = dim / 2): out = grad T(p), out = F(q, t). */
    void (*grad_T)(void* host_ctx, const double* p, double* out);
    void (*force)(void* host_ctx, double t, const double* q, double* out);
} dampsym_host;

/* One step z -> z_next of size h from time t. */
typedef int (*dampsym_step_fn)(void* method_ctx, const dampsym_host* host, double t, double h,
                               const double* z, double* z_next);
/* Optional: the step's Jacobian dz_next/dz, row-major dim x dim, together with z_next. */
typedef int (*dampsym_step_jacobian_fn)(void* method_ctx, const dampsym_host* host, double t,
                                        double h, const double* z, double* z_next, double* jac);

typedef struct dampsym_method {
    const char* id;          /* unique; must not shadow a built-in or method-file id */
    const char* description; /* one line, may be NULL */
    int order;               /* classical order claimed (measured by dampsym) */
    int form;                /* enum dampsym_form */
    unsigned claims;         /* bitwise or of enum dampsym_claim */
    dampsym_step_fn step;    /* required */
    dampsym_step_jacobian_fn step_jacobian; /* NULL: dampsym differentiates step numerically */
    void* method_ctx;                       /* passed to step / step_jacobian */
} dampsym_method;

typedef struct dampsym_plugin_descriptor {
    int abi_version; /* the plugin sets DAMPSYM_PLUGIN_ABI_VERSION */
    const char* name;
    int n_methods;
    const dampsym_method* methods; /* static storage, valid until dlclose */
} dampsym_plugin_descriptor;

/* The exported entry: host_abi_version is the version dampsym speaks; returns 0 on success. */
typedef int (*dampsym_plugin_entry_fn)(int host_abi_version, dampsym_plugin_descriptor* out);

#ifdef __cplusplus
}
#endif

#endif /* DAMPSYM_PLUGIN_H */
