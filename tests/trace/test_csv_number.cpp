// put_int / put_fixed: byte-identical to fmt's "{}" and "{:.Nf}" on edge cases and a seeded sweep.
#include "trace/csv_number.hpp"

#include <fmt/format.h>
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>

namespace {

std::string fast_fixed(double x, int n) {
  char buf[400];
  return std::string(buf, gm::put_fixed(buf, x, n));
}
std::string fast_int(std::int64_t v) {
  char buf[32];
  return std::string(buf, gm::put_int(buf, v));
}

}  // namespace

TEST_CASE("put_fixed writes what fmt {:.Nf} writes") {
  const double inf = std::numeric_limits<double>::infinity();
  const double edges[] = {0.0,
                          -0.0,
                          0.0625,
                          -0.0625,
                          0.0005,
                          0.0015,
                          -0.0004,
                          1e-300,
                          0.004,
                          0.012,
                          2.5e-7,
                          123456.789,
                          999999.9999995,
                          999.9995,
                          1e14,
                          9.99e14,
                          1e15,
                          1e300,
                          -1e300,
                          inf,
                          -inf,
                          std::numeric_limits<double>::quiet_NaN(),
                          std::numeric_limits<double>::max()};
  for (int n : {3, 6}) {
    for (double x : edges) {
      INFO(n << " " << x);
      CHECK(fast_fixed(x, n) == fmt::format("{:.{}f}", x, n));
    }
  }
  CHECK(fast_fixed(0.0625, 3) == "0.062");    // an exact tie: fmt rounds half to even
  CHECK(fast_fixed(-0.0004, 3) == "-0.000");  // the sign stays
  // Sample times k·T as the pipeline computes them, and random magnitudes.
  for (std::int64_t k = 0; k < 200000; ++k) {
    const double t = static_cast<double>(k) * 0.004;
    REQUIRE(fast_fixed(t, 6) == fmt::format("{:.6f}", t));
  }
  const std::uint64_t seed = 9001;
  std::mt19937_64 rng(seed);
  CAPTURE(seed);
  std::uniform_real_distribution<double> mag(-12.0, 16.0);
  for (int i = 0; i < 300000; ++i) {
    const double x = (rng() % 2 ? 1 : -1) * std::pow(10.0, mag(rng));
    const int n = i % 2 ? 3 : 6;
    INFO(x);
    REQUIRE(fast_fixed(x, n) == fmt::format("{:.{}f}", x, n));
    // Values that are exactly halves at the last digit (k + 0.5)/10^n, and their neighbours.
    const double half = (std::floor(x * 1000.0) + 0.5) / 1000.0;
    REQUIRE(fast_fixed(half, 3) == fmt::format("{:.3f}", half));
    REQUIRE(fast_fixed(std::nextafter(half, 0.0), 3) ==
            fmt::format("{:.3f}", std::nextafter(half, 0.0)));
  }
}

TEST_CASE("put_int writes what fmt {} writes") {
  for (std::int64_t v :
       {std::int64_t{0}, std::int64_t{-1}, std::int64_t{7},
        std::numeric_limits<std::int64_t>::min(), std::numeric_limits<std::int64_t>::max()})
    CHECK(fast_int(v) == fmt::format("{}", v));
}
