// G5/G5.1/G5.2/G5.3: NURBS points and tangents against closed forms, the biarc fit of an exact
// circle, and the pieces a program's curves become.
#include "gcode_helpers.hpp"
#include "interp/spline.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using gm::ControlPoint;
using gm::CurvePiece;
using gm::nurbs_at;
using gm::nurbs_biarcs;
using namespace gmtest;

TEST_CASE("NURBS points: Bezier closed forms and a knot of a quadratic B-spline") {
  // Quadratic Bezier (G5.1) B(u) = (1-u)^2 P0 + 2u(1-u) P1 + u^2 P2; B'(1/2) = P2 - P0.
  const ControlPoint q[] = {{50, 30, 1}, {60, 40, 1}, {70, 30, 1}};
  const auto m = nurbs_at(q, 3, 0.5);
  CHECK(m.x == Approx(60));
  CHECK(m.y == Approx(35));
  CHECK(m.tx == Approx(1));
  CHECK(m.ty == Approx(0).margin(1e-12));
  // Cubic Bezier (G5) at 1/2: (P0 + 3 P1 + 3 P2 + P3) / 8; at 1/4 the tangent is along
  // B'(1/4) = 3[(9/16)(P1 - P0) + (6/16)(P2 - P1) + (1/16)(P3 - P2)].
  const ControlPoint c[] = {{0, 0, 1}, {15, 0, 1}, {25, 20, 1}, {40, 20, 1}};
  const auto h = nurbs_at(c, 4, 0.5);
  CHECK(h.x == Approx((0 + 45 + 75 + 40) / 8.0));
  CHECK(h.y == Approx((0 + 0 + 60 + 20) / 8.0));
  const double dx = 9.0 / 16 * 15 + 6.0 / 16 * 10 + 1.0 / 16 * 15;
  const double dy = 9.0 / 16 * 0 + 6.0 / 16 * 20 + 1.0 / 16 * 0;
  const auto t = nurbs_at(c, 4, 0.25);
  CHECK(t.tx == Approx(dx / std::hypot(dx, dy)));
  CHECK(t.ty == Approx(dy / std::hypot(dx, dy)));
  // Quadratic B-spline over knots 0 0 0 1 2 3 3 3: at the knot u = 1 the point is (P1 + P2) / 2;
  // the ends are the end points.
  const ControlPoint b[] = {{0, 0, 1}, {10, 5, 1}, {20, -5, 1}, {30, 5, 1}, {40, 0, 1}};
  const auto k1 = nurbs_at(b, 3, 1.0);
  CHECK(k1.x == Approx(15));
  CHECK(k1.y == Approx(0).margin(1e-12));
  CHECK(nurbs_at(b, 3, 3.0).x == Approx(40));
  CHECK(nurbs_at(b, 3, 0.0).y == Approx(0).margin(1e-12));
}

TEST_CASE(
    "a rational quadratic quarter circle stays on the circle, and its biarcs are the circle") {
  // Weights 1, sqrt(2)/2, 1 on (R, 0), (R, R), (0, R): every point has radius R.
  const double R = 25.0, w = std::sqrt(0.5);
  const ControlPoint arc[] = {{R, 0, 1}, {R, R, w}, {0, R, 1}};
  for (double u = 0.0; u <= 1.0; u += 0.125) {
    const auto p = nurbs_at(arc, 3, u);
    CHECK(std::hypot(p.x, p.y) == Approx(R).epsilon(1e-12));
    CHECK(p.x * p.tx + p.y * p.ty == Approx(0).margin(1e-9));  // tangent normal to the radius
  }
  std::vector<CurvePiece> pieces;
  nurbs_biarcs(arc, 3, 1e-6, pieces);
  REQUIRE(pieces.size() == 24);  // 4 x 3 steps, two arcs each
  for (const auto& p : pieces) {
    REQUIRE(p.arc);
    CHECK(p.ccw);
    CHECK(p.cx == Approx(0).margin(1e-9));
    CHECK(p.cy == Approx(0).margin(1e-9));
    CHECK(std::hypot(p.x, p.y) == Approx(R).epsilon(1e-12));
  }
  CHECK(pieces.back().x == Approx(0).margin(1e-12));
  CHECK(pieces.back().y == Approx(R));
}

TEST_CASE("collinear control points are drawn straight") {
  const ControlPoint line[] = {{0, 0, 1}, {5, 5, 1}, {10, 10, 1}};
  std::vector<CurvePiece> pieces;
  nurbs_biarcs(line, 3, 1e-6, pieces);
  REQUIRE(!pieces.empty());
  for (const auto& p : pieces) {
    CHECK_FALSE(p.arc);
    CHECK(p.x == Approx(p.y));
  }
}

TEST_CASE("G5.1 in a program: tangent-continuous arcs ending exactly on the end point") {
  const auto m = motions(
      "G21 G90 G17 F600\n"
      "G0 X50 Y30\n"
      "G5.1 I10 J10 X70 Y30\n"
      "G91 G1 X1\n"  // starts where the curve ended
      "M2\n");
  REQUIRE(m.size() == 26);  // the rapid, 24 arcs (12 steps), the G1
  CHECK(m[24].end_mm[0] == 70.0);
  CHECK(m[24].end_mm[1] == 30.0);
  CHECK(m[25].end_mm[0] == Approx(71));
  CHECK(m[12].end_mm[0] == Approx(60));  // the sample at u = 1/2 is the apex
  CHECK(m[12].end_mm[1] == Approx(35));
  // Consecutive arcs share their tangent where they meet.
  auto tangent = [](const gm::Motion& a, const gm::AxisVec& at) {
    const double rx = at[0] - a.center_mm[0], ry = at[1] - a.center_mm[1];
    const double s = a.ccw ? 1.0 : -1.0;
    const double h = std::hypot(rx, ry);
    return std::array<double, 2>{-s * ry / h, s * rx / h};
  };
  for (std::size_t i = 2; i < 25; ++i) {
    const auto a = tangent(m[i - 1], m[i - 1].end_mm), b = tangent(m[i], m[i].start_mm);
    CHECK(a[0] == Approx(b[0]).margin(1e-9));
    CHECK(a[1] == Approx(b[1]).margin(1e-9));
  }
}

TEST_CASE("G5.2/G5.3: points collected across blocks, errors where LinuxCNC gives them") {
  const auto m = motions(
      "G21 G90 F600\nG0 X0 Y0\n"
      "G5.2 X10 Y10 P1 L4\nX20 Y-10 P2\nX30 Y0 P1\nG5.3\n"
      "M2\n");
  REQUIRE(m.size() == 32);  // (the rapid is zero-length) 4 points, 16 steps, 2 arcs each
  CHECK(m.back().end_mm[0] == 30.0);
  CHECK(m.back().end_mm[1] == 0.0);
  CHECK(diagnose("G21 F600\nG5.3\nM2\n").at(0).loc.line == 2);
  CHECK(diagnose("G21 F600\nG5.2 X1 Y1 P1 L4\nX2 Y0 P1\nG5.3\nM2\n").at(0).loc.line == 4);
  CHECK(diagnose("G21 F600\nG5.2 X1 Y1 P1\nX2 Y0\nG5.3\nM2\n").at(0).loc.line == 3);
  CHECK(diagnose("G21 F600\nG18 G5 I1 J1 P1 Q1 X1 Y1\nM2\n").at(0).loc.line == 2);
  CHECK(diagnose("G21\nG5.1 I1 J1 X2 Y0\nM2\n").at(0).code == code(gm::ErrorCode::ZeroFeed));
}

TEST_CASE("hostile splines: far control points and extreme weights are located errors") {
  // I J put the G5's control point at 1e300 mm: the curve would run for ever.
  auto d = diagnose("G21 G90 F100\nG0 X0 Y0\nG5 I[10**300] J0 P-1 Q0 X10 Y10\nM2\n");
  REQUIRE(!d.empty());
  CHECK(d[0].code == code(gm::ErrorCode::ValueOutOfRange));
  CHECK(d[0].loc.line == 3);
  // A weight of 1e300 overflows w x to infinity.
  d = diagnose("G21 G90 F100\nG0 X0 Y0\nG5.2 X1 Y1 P[10**300]\nX2 Y0 P1\nX3 Y1 P1\nG5.3\nM2\n");
  REQUIRE(!d.empty());
  CHECK(d[0].loc.line == 3);
  // Weights within 1e-6..1e6 draw a finite curve ending on its last point.
  const auto m =
      motions("G21 G90 F100\nG0 X0 Y0\nG5.2 X1 Y1 P1000000\nX2 Y0 P0.000001\nX3 Y1 P1\nG5.3\nM2\n");
  REQUIRE(!m.empty());
  for (const auto& mo : m) CHECK(std::isfinite(mo.end_mm[0] + mo.end_mm[1] + mo.center_mm[0]));
  CHECK(m.back().end_mm[0] == 3.0);
}
