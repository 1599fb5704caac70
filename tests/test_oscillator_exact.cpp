#include <catch2/catch.hpp>
TEST_CASE("placeholder build") { REQUIRE(1 == 1); }
