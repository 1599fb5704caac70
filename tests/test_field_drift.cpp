// Diagnostic "field-drift" (B (5.6), Fig 5.2; docs/conventions.md §5): d(t) = ln max_x u + Γ(t) −
// Γ(t0) on the output grid, its slope and range.
#include "diagnostics/field_drift_diagnostic.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using Catch::Matchers::WithinAbs;

namespace field_drift_test {
// Output grid of a 4-point field and a 2-point tail (not part of the field) on t = 0, 0.5, ..., 5:
// u_n(t) = amp(t) (1 + 0.1 n) − 0.3 (max at n = 3).
dampsym::Mat grid(double rate) {
    dampsym::Mat g(6, 11);
    for (int k = 0; k <= 10; ++k) {
        const double t = 0.5 * k;
        for (int n = 0; n < 4; ++n) g(n, k) = std::exp(-rate * t) * (1.0 + 0.1 * n);
        g(4, k) = 100.0; // beyond the field: must not be its maximum
        g(5, k) = -1.0;
    }
    return g;
}
dampsym::CaseFacts facts() {
    dampsym::CaseFacts c;
    c.t0 = 0.0;
    c.t_end = 5.0;
    c.points = 10;
    return c;
}
} // namespace field_drift_test

TEST_CASE("field-drift: a field decaying at the damping rate has no drift, another rate drifts",
          "[field-drift]") {
    const double gamma = 0.375;
    auto Gamma = [gamma](double t) { return gamma * t; };
    const auto c = field_drift_test::facts();
    const auto ok = dampsym::field_drift_metrics(c, field_drift_test::grid(gamma), 4, Gamma);
    CHECK_THAT(ok["slope"].get<double>(), WithinAbs(0.0, 1e-14));
    CHECK_THAT(ok["range"].get<double>(), WithinAbs(0.0, 1e-14));
    CHECK_THAT(ok["first"][1].get<double>(), WithinAbs(std::log(1.3), 1e-14)); // max at n = 3
    CHECK(ok["points"].get<int>() == 10);                                      // t0 left out
    // the negative control: a field decaying twice as fast drifts at -gamma
    const auto bad = dampsym::field_drift_metrics(c, field_drift_test::grid(2 * gamma), 4, Gamma);
    CHECK_THAT(bad["slope"].get<double>(), WithinAbs(-gamma, 1e-12));
    // max_x u <= 0: undefined, with its reason
    dampsym::Mat neg = -field_drift_test::grid(gamma);
    const auto und = dampsym::field_drift_metrics(c, neg, 4, Gamma);
    CHECK(und["slope"].is_null());
    CHECK(und.contains("undefined"));
}
