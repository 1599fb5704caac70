// The one integrating-factor formula, B(2.4)–(2.5): the factors that turn an RK tableau (α, β, c)
// into the IFRK method on the conformal form z' = N(z, t) − γ(t)z,
//   Z_i     = e^{−x(c_i h)} z_n + h Σ_j α_ij e^{x(c_j h) − x(c_i h)} N(Z_j, t_n + c_j h),
//   z_{n+1} = e^{−x(h)} z_n + h Σ_i β_i e^{x(c_i h) − x(h)} N(Z_i, t_n + c_i h),
// x(τ) = Γ(t_n + τ) − Γ(t_n). The caller supplies the damping integral between two abscissae,
// between(a, b) = x(b h) − x(a h) = Γ(t_n + b h) − Γ(t_n + a h): the problem's exact Γ at the stage
// times (IFRK kernel, any γ(t)), or (b − a)·γh for a damping argument γh (exponential-RK data,
// exponential_tableaux.cpp). Both kernels that step an integrating-factor method therefore use
// these factors, formed here only.
#pragma once

#include "core/method.hpp"
#include "core/types.hpp"

#include <cmath>
#include <cstddef>

namespace dampsym {

struct IntegratingFactors {
    Vec phi;         // e^{−x(c_i h)}: the factor of z_n in stage i
    Vec F;           // e^{x(c_i h) − x(h)}: the factor of stage i in the update
    Mat E;           // e^{x(c_j h) − x(c_i h)} where α_ij ≠ 0 (0 elsewhere)
    double phi0 = 1; // e^{−x(h)}
};

template <class Between>
void integrating_factors(const ButcherTableau& u, Between&& between, IntegratingFactors& out) {
    const int s = u.stages;
    out.phi.resize(s);
    out.F.resize(s);
    out.E.resize(s, s);
    out.phi0 = std::exp(-between(0.0, 1.0));
    for (int i = 0; i < s; ++i) {
        const double ci = u.c[static_cast<std::size_t>(i)];
        out.phi[i] = std::exp(-between(0.0, ci));
        out.F[i] = std::exp(-between(ci, 1.0));
        for (int j = 0; j < s; ++j) {
            const double cj = u.c[static_cast<std::size_t>(j)];
            out.E(i, j) = u.A(i, j) == 0.0 ? 0.0 : std::exp(-between(cj, ci));
        }
    }
}

} // namespace dampsym
