// PathSimplifier: repeats dropped, the point budget kept on long paths.
#include "report/path_simplifier.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using gm::report::PathSimplifier;

TEST_CASE("path simplifier: only exact repeats are dropped under the budget", "[report]") {
  PathSimplifier p(100);
  p.add(0, 0, true, true);
  p.add(0, 0, false, true);  // a Z-only rapid: the same XY point
  p.add(10, 0, true, false);
  p.add(10, 10, false, false);
  REQUIRE(p.points().size() == 3);
  CHECK(p.points()[0].rapid);
  CHECK(p.points()[1].starts_piece);
  CHECK(!p.points()[1].rapid);
  CHECK(p.points()[2].y_mm == 10.0);
  CHECK(p.offered() == 4);
  CHECK(p.tolerance_mm() == 0.0);
}

TEST_CASE("path simplifier: 10000 points along a circle stay within 1000", "[report]") {
  PathSimplifier p(1000);
  const int n = 10000;
  for (int i = 0; i <= n; ++i) {
    const double a = 2.0 * 3.14159265358979 * i / n;
    p.add(50.0 * std::cos(a), 50.0 * std::sin(a), i == 0, false);
  }
  REQUIRE(p.points().size() <= 1000);
  CHECK(p.points().size() > 200);  // the tolerance grew only as far as needed
  CHECK(p.tolerance_mm() > 0.0);
  CHECK(p.tolerance_mm() < 2.0);
  CHECK(p.points().front().x_mm == 50.0);
  // The last point kept is within the tolerance of the circle's end (50, 0).
  CHECK(std::hypot(p.points().back().x_mm - 50.0, p.points().back().y_mm) <= p.tolerance_mm());
  // Every kept point after the first is at least the tolerance from its predecessor, except the
  // piece's last point.
  for (std::size_t i = 1; i + 1 < p.points().size(); ++i)
    CHECK(std::hypot(p.points()[i].x_mm - p.points()[i - 1].x_mm,
                     p.points()[i].y_mm - p.points()[i - 1].y_mm) >= p.tolerance_mm());
}
