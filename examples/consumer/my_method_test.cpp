// A project's own test of its method with dampsym's checks (the installed package's public API,
// <dampsym/dampsym.hpp>): the method is given as a method file's JSON (here: the 2-stage Gauss
// tableau under the integrating factor, B(2.5)), its coefficients are checked, and the matrix
// battery finds it conformal symplectic and of order 4; a copy with one weight off by 1e-6 is not.
#include <catch2/catch.hpp>

#include <dampsym/dampsym.hpp>

#include <string>

namespace {

std::string gauss2_if(const std::string& id, const std::string& b1) {
    return R"({"id": ")" + id + R"(", "family": "rk", "order": 4, "integrating_factor": true,
        "claims": ["conformal-symplectic"],
        "tableau": {"A": [["1/4", "1/4 - sqrt(3)/6"], ["1/4 + sqrt(3)/6", "1/4"]],
                    "b": [)" +
           b1 + R"(, "1/2"], "c": ["1/2 - sqrt(3)/6", "1/2 + sqrt(3)/6"]}})";
}

const dampsym::api::MatrixRow& row_of(const dampsym::api::Matrix& m, const std::string& id) {
    for (const auto& r : m.rows)
        if (r.method == id) return r;
    FAIL("no row " << id);
    throw; // not reached
}

} // namespace

TEST_CASE("my method is conformal symplectic and has its order") {
    const std::string id = dampsym::api::load_method(gauss2_if("my-gauss2-if", "\"1/2\""), "mine");
    for (const auto& c : dampsym::api::check_method(id)) CHECK(c.agrees);
    const auto m = dampsym::api::matrix({id});
    const auto& row = row_of(m, id);
    REQUIRE(row.cell("order"));
    CHECK(row.cell("order")->verdict == "holds");
    CHECK(row.cell("order")->value == Approx(4.0).margin(0.1));
    CHECK(row.cell("en-pendulum")->verdict == "holds");
    CHECK(row.cell("en-hill")->verdict == "holds");
    CHECK(m.exit_status == 0);
}

TEST_CASE("a weight off by 1e-6 is caught") {
    const std::string id =
        dampsym::api::load_method(gauss2_if("my-gauss2-if-off", "0.5000005"), "mine (perturbed)");
    bool disagrees = false;
    for (const auto& c : dampsym::api::check_method(id)) disagrees = disagrees || !c.agrees;
    CHECK(disagrees);
    const auto m = dampsym::api::matrix({id});
    CHECK(row_of(m, id).cell("en-pendulum")->verdict == "fails");
    CHECK(m.exit_status == 1);
}

TEST_CASE("bad input is the command line's message") {
    CHECK_THROWS_AS(dampsym::api::load_method(R"({"id": "x"})", "mine.json"),
                    dampsym::api::InputError);
    CHECK_THROWS_WITH(dampsym::api::run({"no-such-case"}),
                      Catch::Contains("no-such-case: no case with this id in"));
}
