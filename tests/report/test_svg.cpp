// SVG helpers: round ticks, coordinates without "-0", and no hang on a narrow range far from 0.
#include "report/svg.hpp"

#include <catch2/catch.hpp>

#include <vector>

using gm::report::coord;
using gm::report::nice_ticks;

namespace {

void check_ticks(const std::vector<double>& got, const std::vector<double>& want) {
  REQUIRE(got.size() == want.size());
  for (std::size_t i = 0; i < got.size(); ++i) CHECK(got[i] == Approx(want[i]).margin(1e-12));
}

}  // namespace

TEST_CASE("nice_ticks: 1, 2, 5 steps covering the range", "[report]") {
  check_ticks(nice_ticks(0, 10, 5), {0, 2, 4, 6, 8, 10});                        // raw step 2
  check_ticks(nice_ticks(-0.3, 0.7, 4), {-0.2, 0, 0.2, 0.4, 0.6});               // raw 0.25 -> 0.2
  check_ticks(nice_ticks(95, 105, 4), {96, 98, 100, 102, 104});                  // raw 2.5 -> 2
  check_ticks(nice_ticks(0, 4.6, 8), {0, 0.5, 1, 1.5, 2, 2.5, 3, 3.5, 4, 4.5});  // raw 0.575
  CHECK(nice_ticks(1, 1, 4).empty());
}

TEST_CASE("nice_ticks: a range narrower than lo's resolution ends", "[report]") {
  // step 2e-17 is far below the spacing of doubles near 1e12: counted ticks, not stepped.
  const auto t = nice_ticks(1e12, 1e12 + 1e-4, 5);
  CHECK(t.size() <= 101);
}

TEST_CASE("coord: fixed decimals, no negative zero", "[report]") {
  CHECK(coord(20.0) == "20.00");
  CHECK(coord(-0.001) == "0.00");
  CHECK(coord(-1.25, 1) == "-1.2");  // round half to even in binary: -1.25 is exact, fmt gives -1.2
  CHECK(coord(579.996) == "580.00");
}
