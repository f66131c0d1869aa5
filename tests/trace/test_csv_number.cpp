// put_int / put_fixed: byte-identical to fmt's "{}" and "{:.Nf}" on edge cases and a seeded sweep.
#include "trace/csv_number.hpp"

#include <fmt/format.h>
#include <catch2/catch.hpp>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <string_view>
#include <vector>

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

TEST_CASE("put_int: every digit count, its edges, and a seeded sweep") {
  // The digit count comes from the bit width; the edges 10^d − 1, 10^d and 2^b ± 1 are where
  // an off-by-one in it would show.
  std::vector<std::int64_t> values;
  std::int64_t p = 1;  // 10^d; 10^18 is the last that fits
  for (int d = 0; d <= 18; ++d) {
    for (std::int64_t v : {p - 1, p, p + 1}) values.insert(values.end(), {v, -v});
    if (d < 18) p *= 10;
  }
  for (int b = 0; b < 63; ++b) {
    const std::int64_t v = std::int64_t{1} << b;
    values.insert(values.end(), {v - 1, v, v + 1, -(v - 1), -v, -(v + 1)});
  }
  std::mt19937_64 rng(20261126);
  for (int i = 0; i < 100000; ++i) {
    const auto digits = static_cast<int>(rng() % 19);
    std::int64_t bound = 1;
    for (int d = 0; d < digits; ++d) bound *= 10;
    const auto v = static_cast<std::int64_t>(rng() % static_cast<std::uint64_t>(bound * 9 + 1));
    values.push_back(rng() % 2 == 0 ? v : -v);
  }
  std::size_t wrong = 0;
  for (std::int64_t v : values)
    if (fast_int(v) != fmt::format("{}", v)) ++wrong;
  CHECK(wrong == 0);
  CHECK(values.size() > 100000);
}

TEST_CASE(
    "put_uint8 and digit_bytes8: every value below 10^6, a stride to 10^8, against to_chars") {
  std::size_t wrong = 0, checked = 0;
  auto check = [&](std::uint32_t v) {
    char fast[16], ref[16];
    char* const end = gm::csv_detail::put_uint8(fast, v);
    const auto r = std::to_chars(ref, ref + sizeof ref, v);
    ++checked;
    if (std::string_view(fast, end - fast) != std::string_view(ref, r.ptr - ref)) ++wrong;
    // The word holds all eight digits, leading zeros included.
    const std::uint64_t d = gm::csv_detail::digit_bytes8(v);
    std::uint32_t back = 0;
    for (int i = 0; i < 8; ++i) back = back * 10 + static_cast<std::uint32_t>(d >> (8 * i) & 0xFF);
    if (back != v) ++wrong;
  };
  for (std::uint32_t v = 0; v < 1000000; ++v) check(v);
  for (std::uint32_t v = 1000000; v < 100000000; v += 997) check(v);
  for (std::uint32_t p = 10; p <= 100000000; p *= 10)
    for (std::uint32_t v : {p - 1, p - 2, p / 10 * 9, p / 2}) check(v);
  CHECK(wrong == 0);
  CHECK(checked > 1090000u);
}

TEST_CASE("put_fixed_n<3> and <6> write what printf %.3f / %.6f writes, at the path edges") {
  // Signs and -0, values rounding to (-)0, halves in decimal that are not halves in binary,
  // whole parts at 10^8 (where the whole part needs the second word) and the 1e15 limit.
  const double values[] = {0.0,
                           -0.0,
                           0.0004,
                           -0.0004,
                           0.0005,
                           -0.0005,
                           0.0015,
                           2.0005,
                           99999999.9995,
                           99999999.999,
                           100000000.0,
                           -100000000.0005,
                           123456789.125,
                           999999999999.9994,
                           999999999999.99,
                           1e12 - 0.0005,
                           -1e12,
                           4.0000000000000002,
                           17160.004,
                           0.123456,
                           -0.1234565,
                           1e-7,
                           -5e-7};
  for (double x : values) {
    char buf[64];
    INFO(x);
    char ref3[400], ref6[400];
    std::snprintf(ref3, sizeof ref3, "%.3f", x);
    std::snprintf(ref6, sizeof ref6, "%.6f", x);
    CHECK(std::string(buf, gm::put_fixed_n<3>(buf, x)) == ref3);
    CHECK(std::string(buf, gm::put_fixed_n<6>(buf, x)) == ref6);
  }
}
