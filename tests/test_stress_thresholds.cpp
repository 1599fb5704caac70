// The stability-threshold cases of the stress suite (verify/cases/stress-threshold-*.json) hold
// dt_ladder = [0.99 h*, 1.01 h*] as numbers, written by verify/stress_thresholds.py. Here every h*
// is solved again, independently, from its formula (bisection on the catalog's F_condition for
// F(3.17)/(3.22), the closed forms hw = 2, sqrt 3, 2 sqrt 2 and h = 2γ/ω², bisection on Heun's
// stability polynomial), and the files must hold 0.99 and 1.01 times it, so the numbers cannot
// go stale silently. Also: the stability function R(z) behind the stress maps' RK comparison.
#include "core/method.hpp"
#include "diagnostics/stability.hpp"
#include "harness/report/provenance.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// The flip of a predicate between a (value pa) and b (!pa), to the last bit.
double bisect_flip(const std::function<bool(double)>& pred, double a, double b) {
    const bool pa = pred(a);
    REQUIRE(pred(b) != pa);
    while (true) {
        const double m = 0.5 * (a + b);
        if (m == a || m == b) return m;
        (pred(m) == pa ? a : b) = m;
    }
}

// Boundaries of F's condition (the catalog's closed form) along h in (0, h_max]: "upper" where
// it turns false, "lower" where it turns true, each bisected to the last bit.
double f_boundary(const char* method, double w, double g, bool upper) {
    const dampsym::MethodInfo* info = dampsym::find_method(method);
    REQUIRE(info != nullptr);
    REQUIRE(dampsym::oscillator_formulas(info->id).F_condition != nullptr);
    auto F = [&](double h) { return dampsym::oscillator_formulas(info->id).F_condition(w, g, h); };
    const double h_max = 10.0 / w;
    const int n = 100000;
    std::vector<double> found;
    for (int i = 1; i < n; ++i) {
        const double a = h_max * i / n, b = h_max * (i + 1) / n;
        if (F(a) != F(b) && F(a) == upper) found.push_back(bisect_flip(F, a, b));
    }
    REQUIRE(found.size() == 1); // one boundary of that kind
    return found[0];
}

// First h where max |R(hλ±)| reaches 1, λ± = −γ ± sqrt(γ² − ω²), R(z) = 1 + z + z²/2 (Heun).
double heun_boundary(double w, double g) {
    const std::complex<long double> lam =
        -static_cast<long double>(g) +
        std::sqrt(std::complex<long double>(static_cast<long double>(g) * g -
                                            static_cast<long double>(w) * w));
    auto stable = [&](double h) {
        const std::complex<long double> z = static_cast<long double>(h) * lam;
        return std::abs(1.0L + z + z * z / 2.0L) <= 1.0L;
    };
    return bisect_flip(stable, 0.1 / w, 4.0 / w);
}

// The same first h from the library's stability function of the catalog tableau.
double rk_boundary(const char* method, double w, double g, double lo, double hi) {
    const dampsym::MethodInfo* info = dampsym::find_method(method);
    REQUIRE(info != nullptr);
    REQUIRE(dampsym::plain_tableau(*info) != nullptr);
    auto rho_le_1 = [&](double h) {
        return dampsym::rk_power_analysis(*dampsym::plain_tableau(*info), w, g, h)
                   .spectral_radius <= 1.0;
    };
    return bisect_flip(rho_le_1, lo, hi);
}

struct Threshold {
    const char* method;
    std::function<double(double w, double g)> h_star;
};

const std::map<std::string, Threshold>& thresholds() {
    static const std::map<std::string, Threshold> t{
        {"stress-threshold-csv1-upper",
         {"csv1", [](double w, double g) { return f_boundary("csv1", w, g, true); }}},
        {"stress-threshold-csv1-upper-strong",
         {"csv1", [](double w, double g) { return f_boundary("csv1", w, g, true); }}},
        {"stress-threshold-csv1-lower",
         {"csv1", [](double w, double g) { return f_boundary("csv1", w, g, false); }}},
        {"stress-threshold-csv2-upper",
         {"csv2", [](double w, double g) { return f_boundary("csv2", w, g, true); }}},
        {"stress-threshold-csv2-upper-strong",
         {"csv2", [](double w, double g) { return f_boundary("csv2", w, g, true); }}},
        {"stress-threshold-csv2-lower",
         {"csv2", [](double w, double g) { return f_boundary("csv2", w, g, false); }}},
        // hω = 2 on the undamped oscillator: ½tr M = 1 − h²ω²/2 reaches −1
        {"stress-threshold-stormer-verlet",
         {"stormer-verlet",
          [](double w, double g) {
              CHECK(g == 0.0);
              return 2.0 / w;
          }}},
        {"stress-threshold-symplectic-euler",
         {"symplectic-euler",
          [](double w, double g) {
              CHECK(g == 0.0);
              return 2.0 / w;
          }}},
        // |R(iy)|² = 1 − y⁴/12 + y⁶/36 and 1 − y⁶/72 + y⁸/576 reach 1 at y = √3 and 2√2
        {"stress-threshold-rk3",
         {"rk3",
          [](double w, double g) {
              CHECK(g == 0.0);
              return std::sqrt(3.0) / w;
          }}},
        {"stress-threshold-rk4",
         {"rk4",
          [](double w, double g) {
              CHECK(g == 0.0);
              return 2.0 * std::sqrt(2.0) / w;
          }}},
        // |1 + hλ|² = 1 − 2γh + h²ω² = 1 at h = 2γ/ω² (ω > γ)
        {"stress-threshold-euler",
         {"euler",
          [](double w, double g) {
              CHECK(w > g);
              return 2.0 * g / (w * w);
          }}},
        {"stress-threshold-heun", {"heun", [](double w, double g) { return heun_boundary(w, g); }}},
    };
    return t;
}

json read_case(const fs::path& p) {
    std::ifstream in(p);
    REQUIRE(in.good());
    return json::parse(in);
}

} // namespace

TEST_CASE("stress threshold cases hold dt = 0.99 h* and 1.01 h* of the recomputed threshold",
          "[stress][stability]") {
    const fs::path dir = fs::path(dampsym::source_dir()) / "verify" / "cases";
    std::size_t seen = 0;
    for (const auto& entry : fs::directory_iterator(dir)) {
        const std::string name = entry.path().filename().string();
        if (name.rfind("stress-threshold-", 0) != 0 || entry.path().extension() != ".json")
            continue;
        const json c = read_case(entry.path());
        const std::string id = c.at("id").get<std::string>();
        INFO(name << " (id " << id << ")");
        CHECK(name == id + ".json");
        const auto it = thresholds().find(id);
        REQUIRE(it != thresholds().end()); // a new threshold file needs its formula here
        ++seen;
        const Threshold& t = it->second;
        CHECK(c.at("methods") == json::array({t.method}));
        const double w = c.at("problem").at("omega").get<double>();
        const double g = c.at("problem").at("gamma").get<double>();
        const double h = t.h_star(w, g);
        const auto dts = c.at("dt_ladder").get<std::vector<double>>();
        REQUIRE(dts.size() == 2);
        INFO("h* = " << h << ", dt_ladder = [" << dts[0] << ", " << dts[1] << "]");
        // 17 significant digits of the same root: a few ulps apart at most
        CHECK(std::abs(dts[0] / (0.99 * h) - 1.0) <= 1e-14);
        CHECK(std::abs(dts[1] / (1.01 * h) - 1.0) <= 1e-14);
    }
    CHECK(seen == thresholds().size()); // and every formula has its file
}

TEST_CASE("RK stability thresholds: the library's R(z) agrees with the closed forms",
          "[stress][stability]") {
    // rk_power_analysis (the stress maps' analytic power-boundedness) on the catalog tableaux
    const double w = 1.3;
    CHECK(rk_boundary("rk3", w, 0.0, 0.5 / w, 2.5 / w) ==
          Approx(std::sqrt(3.0) / w).epsilon(1e-12));
    CHECK(rk_boundary("rk4", w, 0.0, 0.5 / w, 3.5 / w) ==
          Approx(2.0 * std::sqrt(2.0) / w).epsilon(1e-12));
    for (double g : {0.1, 0.4, 0.9})
        CHECK(rk_boundary("euler", w, g, 0.1 * g / (w * w), 3.0 * g / (w * w)) ==
              Approx(2.0 * g / (w * w)).epsilon(1e-12));
    for (double g : {0.3, 0.5, 1.0})
        CHECK(rk_boundary("heun", w, g, 0.1 / w, 4.0 / w) ==
              Approx(heun_boundary(w, g)).epsilon(1e-12));
}

TEST_CASE("rk_stability_function is the stability function of the tableau", "[stability]") {
    const dampsym::MethodInfo* rk4 = dampsym::find_method("rk4");
    const dampsym::MethodInfo* gauss1 = dampsym::find_method("gauss1");
    REQUIRE(rk4 != nullptr);
    REQUIRE(gauss1 != nullptr);
    for (const std::complex<double> z :
         {std::complex<double>(-0.3, 0.7), {0.2, -1.1}, {-2.0, 0.0}}) {
        const std::complex<double> taylor =
            1.0 + z + z * z / 2.0 + z * z * z / 6.0 + z * z * z * z / 24.0;
        CHECK(std::abs(dampsym::rk_stability_function(*dampsym::plain_tableau(*rk4), z) - taylor) <=
              1e-14);
        const std::complex<double> cayley = (1.0 + z / 2.0) / (1.0 - z / 2.0);
        CHECK(std::abs(dampsym::rk_stability_function(*dampsym::plain_tableau(*gauss1), z) -
                       cayley) <= 1e-14);
    }
}
