// What the hand-written schemes' kernels share (the kernel interface: core/method.hpp), so that a
// scheme's header holds its equations only:
//  - SchemeKernel<S>: the row's coefficient set is the scheme's name (HandWrittenScheme), and the
//    kernel accepts the rows of scheme S;
//  - OneCodePathKernel<Derived, S>: a scheme with an exact step Jacobian advances the state by one
//    code path, Derived::advance<WithJacobian>(t, z, Ψ*) (Ψ = ∂z₁/∂z₀ by the chain rule or the
//    implicit-function theorem when WithJacobian), behind step() — forced inline into the
//    integrate() loop, so that the harness's step loop costs as the bare one — and step_jacobian()
//    (Ψ sized d × d, d = Derived::state_dim()). The two give bitwise the same z.
//  - PdeSchemeKernel<Rows, S>: a scheme of B's for a semi-discrete PDE, given by its row of the
//    PDE's scheme table (PdeSchemeRow: B's scheme, the method row's scheme, the kernel id and the
//    space the scheme is written on); it applies to the problems that declare that space as their
//    `pde_space`.
#pragma once

#include "core/method.hpp"
#include "core/types.hpp"

#include <array>
#include <cstddef>
#include <stdexcept>
#include <string_view>
#include <type_traits>

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

// Problem Q declares the semi-discretisation it is (`pde_space`) of the type Space (KGSpace,
// BurgersSpace, NLSSpace): the space of another PDE is another type, whatever its value.
template <class Q, class Space>
concept DeclaresPdeSpace = std::is_same_v<std::remove_cvref_t<decltype(Q::pde_space)>, Space>;

// Whether problem Q is the semi-discretisation `space`.
template <class Q, auto Space>
constexpr bool on_pde_space() {
    if constexpr (DeclaresPdeSpace<Q, decltype(Space)>)
        return Q::pde_space == Space;
    else
        return false;
}

// One scheme of B's for a PDE: B's scheme, the scheme of its method row, its kernel id and the
// semi-discretisation it is written on.
template <class E, class Space>
struct PdeSchemeRow {
    E scheme;
    Scheme row;
    std::string_view kernel_id;
    Space space;
};

// The row of scheme s in a PDE's table (a scheme without a row does not compile).
template <class E, class Space, std::size_t N>
constexpr PdeSchemeRow<E, Space> pde_scheme_row(const std::array<PdeSchemeRow<E, Space>, N>& rows,
                                                E s) {
    for (const auto& r : rows)
        if (r.scheme == s) return r;
    throw std::logic_error("a PDE scheme without a row in its table");
}

template <const auto& Rows, auto S>
class PdeSchemeKernel : public SchemeKernel<pde_scheme_row(Rows, S).row> {
    static constexpr auto row_ = pde_scheme_row(Rows, S);

public:
    static constexpr std::string_view kernel_id = row_.kernel_id;
    template <class Q>
    static constexpr bool applies = on_pde_space<Q, row_.space>();
};

} // namespace dampsym
