// Generic explicit Runge–Kutta kernel on the plain form z' = f(t, z) (the full damped vector
// field). The tableau is data (src/methods/catalog.cpp); this loop is the only code.
//   k_i = f(t + c_i h, z + h Σ_{j<i} a_ij k_j),   z₁ = z + h Σ b_i k_i
// step_jacobian() also returns Ψ = ∂z₁/∂z₀ by the scheme's variational equations (the same RK
// applied to the linearisation along the stages), f' = rhs_jacobian:
//   ∂y_i = I + h Σ_{j<i} a_ij ∂k_j,   ∂k_i = f'(t + c_i h, y_i) ∂y_i,   Ψ = I + h Σ b_i ∂k_i
// For a problem with a compile-time size and a tableau of at most 4 stages, step() runs the same
// arithmetic with the stage count as a template argument (advance_fixed): the stages are then
// registers, not memory, which makes rk4 on the pendulum as fast as Boost.Odeint's runge_kutta4
// (ci/bench.sh, docs/benchmarks.md).
#pragma once

#include "core/method.hpp"
#include "core/problem.hpp"

#include <string_view>

namespace dampsym {

template <class P>
class ExplicitRK {
public:
    static constexpr std::string_view kernel_id = "explicit-rk";
    using Data = RungeKuttaTableau;
    static bool accepts(const Data& d) { return is_explicit_tableau(*d.tableau); }
    template <class Q>
    static constexpr bool applies = true; // every problem offers the plain form

    static constexpr bool has_step_jacobian = true;

    ExplicitRK(const P& problem, const MethodInfo& info, double h, Counters& counters)
        : prob_(problem), t_(*std::get<Data>(info.data).tableau), h_(h), c_(counters),
          K_(problem.dim(), t_.stages), y_(problem.dim()), k_(problem.dim()),
          dK_(problem.dim(), problem.dim() * t_.stages), dY_(problem.dim(), problem.dim()),
          Jf_(problem.dim(), problem.dim()) {}

    // Forced inline into the integrate() loop (the harness's step loop costs as the bare one).
    [[gnu::always_inline]] inline StepStatus step(double t, Vec& z) {
        if constexpr (D != Eigen::Dynamic) {
            switch (t_.stages) { // a compile-time stage count (the branch is always the same one)
            case 1:
                return advance_fixed<1>(t, z);
            case 2:
                return advance_fixed<2>(t, z);
            case 3:
                return advance_fixed<3>(t, z);
            case 4:
                return advance_fixed<4>(t, z);
            default:
                break;
            }
        }
        return advance<false>(t, z, nullptr);
    }

    // Same arithmetic for z as step() (one code path); Psi = ∂z₁/∂z₀ (resized to d×d if needed).
    StepStatus step_jacobian(double t, Vec& z, Mat& Psi) {
        const Eigen::Index d = z.size();
        if (Psi.rows() != d || Psi.cols() != d) Psi.resize(d, d);
        return advance<true>(t, z, &Psi);
    }

private:
    // A separable problem with a compile-time size (static_dof) has state dimension D = 2·static_n:
    // the stage vectors are then fixed-size and the state is a fixed-size view of z, so the stage
    // updates are short unrolled code (no out-of-line Eigen loops in the large translation units).
    static constexpr int D = [] {
        if constexpr (static_dof<P>() != Eigen::Dynamic && P::has_separable)
            return 2 * static_dof<P>();
        else
            return int{Eigen::Dynamic};
    }();
    using VecD = Eigen::Matrix<double, D, 1>;

    // advance<false> for S stages and a compile-time d: the state and the stages are local
    // fixed-size arrays and the stage loops unroll, so the compiler keeps them in registers (no
    // store and reload between the stages). The same operations in the same order as advance().
    template <int S>
    [[gnu::always_inline]] inline StepStatus advance_fixed(double t, Vec& zv) {
        VecD z, K[S];
        for (int k = 0; k < D; ++k) z[k] = zv[k];
#pragma GCC unroll 4
        for (int i = 0; i < S; ++i) {
            VecD y = z;
#pragma GCC unroll 4
            for (int j = 0; j < i; ++j) {
                const double a = t_.A(i, j);
                if (a == 0.0) continue;
                const double ha = h_ * a;
                for (int k = 0; k < D; ++k) y[k] += ha * K[j][k];
            }
            prob_.rhs(t + t_.c[static_cast<std::size_t>(i)] * h_, y, K[i]);
        }
#pragma GCC unroll 4
        for (int i = 0; i < S; ++i) {
            const double hb = h_ * t_.b[static_cast<std::size_t>(i)];
            for (int k = 0; k < D; ++k) z[k] += hb * K[i][k];
        }
        for (int k = 0; k < D; ++k) zv[k] = z[k];
        c_.rhs_evals += S;
        return StepStatus::ok;
    }

    template <bool WithJacobian>
    [[gnu::always_inline]] inline StepStatus advance(double t, Vec& zv, Mat* Psi) {
        // The vector updates are scalar loops over the d components (the same operations as
        // Eigen's, in the same order): GCC declines to inline Eigen's assignment loops in the
        // large translation units that instantiate every kernel, and for a compile-time d they
        // unroll to straight-line code.
        Eigen::Map<VecD> z(zv.data(), zv.size());
        const int d = D == Eigen::Dynamic ? static_cast<int>(zv.size()) : D;
        const int s = t_.stages;
        for (int i = 0; i < s; ++i) {
            for (int k = 0; k < d; ++k) y_[k] = z[k];
            for (int j = 0; j < i; ++j) {
                const double a = t_.A(i, j);
                if (a == 0.0) continue;
                const double ha = h_ * a;
                const double* kj = K_.col(j).data();
                for (int k = 0; k < d; ++k) y_[k] += ha * kj[k];
            }
            const double ti = t + t_.c[static_cast<std::size_t>(i)] * h_;
            prob_.rhs(ti, y_, k_);
            double* ki = K_.col(i).data();
            for (int k = 0; k < d; ++k) ki[k] = k_[k];
            if constexpr (WithJacobian) {
                dY_.setIdentity();
                for (int j = 0; j < i; ++j)
                    if (t_.A(i, j) != 0.0) dY_ += (h_ * t_.A(i, j)) * dK(j);
                prob_.rhs_jacobian(ti, y_, Jf_);
                dK(i).noalias() = Jf_ * dY_;
            }
        }
        for (int i = 0; i < s; ++i) {
            const double hb = h_ * t_.b[static_cast<std::size_t>(i)];
            const double* ki = K_.col(i).data();
            for (int k = 0; k < d; ++k) z[k] += hb * ki[k];
        }
        c_.rhs_evals += s;
        if constexpr (WithJacobian) {
            c_.jac_evals += s;
            Psi->setIdentity();
            for (int i = 0; i < s; ++i) *Psi += (h_ * t_.b[static_cast<std::size_t>(i)]) * dK(i);
        }
        return StepStatus::ok;
    }

    auto dK(int i) {
        return dK_.middleCols(static_cast<Eigen::Index>(i) * dY_.cols(), dY_.cols());
    }

    const P& prob_;
    const ButcherTableau& t_;
    double h_;
    Counters& c_;
    Eigen::Matrix<double, D, Eigen::Dynamic> K_; // stages k_1 … k_s as columns
    VecD y_, k_;
    Mat dK_;      // [∂k_1/∂z₀ … ∂k_s/∂z₀], d × (s·d)
    Mat dY_, Jf_; // ∂y_i/∂z₀ and f'(t_i, y_i)
};

} // namespace dampsym
