// What the hand-written schemes' kernels share (the kernel interface: core/method.hpp), so that a
// scheme's header holds its equations only:
//  - SchemeKernel<S>: the row's coefficient set is the scheme's name (HandWrittenScheme), and the
//    kernel accepts the rows of scheme S;
//  - OneCodePathKernel<Derived, S>: a scheme with an exact step Jacobian advances the state by one
//    code path, Derived::advance<WithJacobian>(t, z, Ψ*) (Ψ = ∂z₁/∂z₀ by the chain rule or the
//    implicit-function theorem when WithJacobian), behind step() — forced inline into the
//    integrate() loop, so that the harness's step loop costs as the bare one — and step_jacobian()
//    (Ψ sized d × d, d = Derived::state_dim()). The two give bitwise the same z.
#pragma once

#include "core/method.hpp"
#include "core/types.hpp"

namespace dampsym {

template <Scheme S>
struct SchemeKernel {
    using Data = HandWrittenScheme;
    static bool accepts(const Data& d) { return d.scheme == S; }
};

template <class Derived, Scheme S>
class OneCodePathKernel : public SchemeKernel<S> {
public:
    static constexpr bool has_step_jacobian = true;

    [[gnu::always_inline]] inline StepStatus step(double t, Vec& z) {
        return self().template advance<false>(t, z, nullptr);
    }

    StepStatus step_jacobian(double t, Vec& z, Mat& Psi) {
        const Eigen::Index d = self().state_dim();
        if (Psi.rows() != d || Psi.cols() != d) Psi.resize(d, d);
        return self().template advance<true>(t, z, &Psi);
    }

private:
    Derived& self() { return static_cast<Derived&>(*this); }
};

} // namespace dampsym
