// The maxima of q behind d(t) = ln(max q) + Γ (diagnostics/maxima.hpp, docs/conventions.md §5):
// between two samples the maximum of the quintic Hermite interpolant, the largest one when the
// interpolant has several local maxima in the step (a first-order trajectory at a coarse step).
#include "core/types.hpp"
#include "diagnostics/maxima.hpp"
#include "problems/oscillator.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;

namespace maxima_test {
dampsym::Oscillator oscillator(double gamma) {
    dampsym::Oscillator o;
    o.gamma = gamma;
    o.omega = 1.0;
    return o;
}
} // namespace maxima_test

TEST_CASE("maxima: a smooth maximum between two samples to the interpolation error", "[maxima]") {
    const dampsym::Oscillator osc = maxima_test::oscillator(0.0);
    dampsym::MaximaFinder<dampsym::Oscillator> f(osc, 0.0);
    // q = cos t, p = q' = -sin t, sampled at t = -0.3 and 0.2: the maximum q = 1 at t = 0
    f.feed(-0.3, dampsym::Vec{{std::cos(-0.3), -std::sin(-0.3)}});
    f.feed(0.2, dampsym::Vec{{std::cos(0.2), -std::sin(0.2)}});
    REQUIRE(f.maxima().size() == 1);
    CHECK_THAT(f.maxima()[0].q, WithinAbs(1.0, 1e-5));
    CHECK_THAT(f.maxima()[0].t, WithinAbs(0.0, 1e-4));
}

TEST_CASE("maxima: the largest of several local maxima of the interpolant in one step",
          "[maxima]") {
    // Two consecutive states of cse-if on the oscillator (gamma = 0.005, omega = 1) at h = 0.5
    // (t = 639.0 and 639.5, the dampsym matrix battery's d(t) case): the interpolant has local
    // maxima at s = 0.3077 (q = 0.0426749) and s = 0.9841 (q = 0.0408033).
    const dampsym::Oscillator osc = maxima_test::oscillator(0.005);
    dampsym::MaximaFinder<dampsym::Oscillator> f(osc, 0.0);
    f.feed(0.0, dampsym::Vec{{0.040927117906325965, 0.0203154883847014}});
    f.feed(0.5, dampsym::Vec{{0.040802420661580414, -0.0002493944894911039}});
    REQUIRE(f.maxima().size() == 1);
    CHECK_THAT(f.maxima()[0].q, WithinRel(0.04267489602868876, 1e-9));
    CHECK_THAT(f.maxima()[0].t, WithinAbs(0.5 * 0.30767, 1e-5));
    // the negative control: the other local maximum, which the secant start alone reaches
    CHECK(f.maxima()[0].q > 0.0415);
}
