#include "harness/problem_list.hpp"
#include "harness/registry.hpp" // with_kernel_among

#include <catch2/catch.hpp>

TEST_CASE("every catalogued method names a known kernel") {
    for (const auto& m : dampsym::method_catalog()) {
        INFO(m.id);
        bool known = false;
        dampsym::with_problem_type("oscillator", [&]<class P>() {
            dampsym::KernelMatch match = dampsym::KernelMatch::unknown_kernel;
            dampsym::kernel_ops<P>(m, match); // the library's kernel shards
            known = match != dampsym::KernelMatch::unknown_kernel;
        });
        CHECK(known);
    }
}

namespace {
// A kernel that claims every Runge–Kutta tableau (the registry's ExplicitRK and ImplicitRK split
// them): with_kernel_among must refuse to step a method by it.
template <class P>
struct ClaimsEveryTableau {
    static constexpr std::string_view kernel_id = "claims-every-tableau";
    using Data = dampsym::RungeKuttaTableau;
    static bool accepts(const Data&) { return true; }
    template <class Q>
    static constexpr bool applies = true;
};
} // namespace

TEST_CASE("with_kernel_among steps a method only by the kernel with_kernel chooses") {
    const dampsym::MethodInfo* rk4 = dampsym::find_method("rk4");
    REQUIRE(rk4 != nullptr);
    int calls = 0;
    auto count = [&]<class K>() { ++calls; };
    using dampsym::KernelList;
    using dampsym::Oscillator;
    CHECK(dampsym::with_kernel_among<Oscillator, KernelList<dampsym::ExplicitRK>>(*rk4, count) ==
          dampsym::KernelMatch::applied);
    CHECK(calls == 1);
    CHECK(dampsym::with_kernel_among<Oscillator, KernelList<dampsym::Csv1>>(*rk4, count) ==
          dampsym::KernelMatch::unknown_kernel);
    CHECK_THROWS_AS(
        (dampsym::with_kernel_among<Oscillator, KernelList<ClaimsEveryTableau>>(*rk4, count)),
        std::logic_error);
    CHECK(calls == 1);
}
