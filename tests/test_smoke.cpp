#include "harness/registry.hpp"

#include <catch2/catch.hpp>

TEST_CASE("every catalogued method names a known kernel") {
    for (const auto& m : dampsym::method_catalog()) {
        INFO(m.id);
        bool known = false;
        dampsym::with_problem_type("oscillator", [&]<class P>() {
            known = dampsym::with_kernel<P>(m, []<class K>() {}) !=
                    dampsym::KernelMatch::unknown_kernel;
        });
        CHECK(known);
    }
}
