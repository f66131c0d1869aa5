// round_half_away: identical to std::llround on edge cases and on a seeded random sweep.
#include "common/rounding.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

TEST_CASE("round_half_away equals std::llround") {
  const double edges[] = {0.0,
                          -0.0,
                          0.5,
                          -0.5,
                          1.5,
                          -1.5,
                          2.5,
                          -2.5,
                          0.49999999999999994,
                          -0.49999999999999994,
                          0.5000000000000001,
                          4503599627370495.5,
                          -4503599627370495.5,
                          4503599627370497.0,
                          9007199254740993.0,
                          -9007199254740993.0,
                          1e18,
                          -1e18,
                          9.1e18,
                          -9.1e18,
                          1e-300,
                          -1e-300};
  for (double x : edges) {
    INFO(x);
    CHECK(gm::round_half_away(x) == std::llround(x));
  }
  CHECK(gm::round_half_away(2.5) == 3);
  CHECK(gm::round_half_away(-2.5) == -3);
  CHECK(gm::round_half_away(-0.49999999999999994) == 0);
  const std::uint64_t seed = 4242;
  std::mt19937_64 rng(seed);
  CAPTURE(seed);
  std::uniform_real_distribution<double> mag(-20.0, 62.0);
  for (int i = 0; i < 200000; ++i) {
    const double x = (rng() % 2 ? 1 : -1) * std::exp2(mag(rng));
    const double half = std::floor(x) + 0.5;  // also probe exact halves
    INFO(x);
    REQUIRE(gm::round_half_away(x) == std::llround(x));
    if (std::fabs(half) < 9e18) REQUIRE(gm::round_half_away(half) == std::llround(half));
  }
}
