// Contour error geometry: distances to lines, signed radial deviation on arcs, arc end handling.
#include "pipeline/path_window.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using gm::AxisVec;
using gm::Motion;
using gm::MotionKind;
using gm::xyz;

namespace {
// A point in X, Y, Z: what the contour error is measured on.
gm::Vec3 p3(double x, double y, double z) {
  return gm::Vec3(x, y, z);
}

Motion line(AxisVec a, AxisVec b) {
  Motion m;
  m.kind = MotionKind::Line;
  m.start_mm = a;
  m.end_mm = b;
  return m;
}
// A ccw quarter arc in XY about the origin, radius r, from +X to +Y.
Motion quarter_arc(double r) {
  Motion m;
  m.kind = MotionKind::Arc;
  m.start_mm = xyz(r, 0, 0);
  m.end_mm = xyz(0, r, 0);
  m.center_mm = AxisVec::Zero();
  m.ccw = true;
  return m;
}
}  // namespace

TEST_CASE("distance to a line segment, including beyond its ends") {
  gm::PathWindow w(100);
  w.push(line(xyz(0, 0, 0), xyz(10, 0, 0)), 0);
  CHECK(w.contour_error_mm(p3(5, 0.3, 0), 1) == Approx(0.3));
  CHECK(w.contour_error_mm(p3(13, 4, 0), 1) == Approx(5.0));  // 3-4-5 from the end point
}

TEST_CASE("arcs give the signed radial deviation, negative inside") {
  gm::PathWindow w(100);
  w.push(quarter_arc(4.0), 0);
  const double c = std::cos(0.5), s = std::sin(0.5);
  CHECK(w.contour_error_mm(p3(3.9 * c, 3.9 * s, 0), 1) == Approx(-0.1));
  CHECK(w.contour_error_mm(p3(4.2 * c, 4.2 * s, 0), 1) == Approx(0.2));
  // Outside the quarter's angular span the nearest point is an end point, not the full circle.
  CHECK(w.contour_error_mm(p3(-4, 0, 0), 1) == Approx(std::hypot(4.0, 4.0)));
}

TEST_CASE("the nearest of the recent blocks wins, blocks older than the lag are dropped") {
  gm::PathWindow w(10);
  w.push(line(xyz(0, 0, 0), xyz(10, 0, 0)), 0);
  w.push(line(xyz(10, 0, 0), xyz(10, 10, 0)), 50);
  // Near the first segment while it is still within the lag window.
  CHECK(w.contour_error_mm(p3(5, 0.01, 0), 55) == Approx(0.01));
  // 20 samples after the first block ended: it is no longer searched.
  CHECK(w.contour_error_mm(p3(5, 0.01, 0), 70) == Approx(std::hypot(5.0, 0.01)));
}

TEST_CASE("radial deviation in the XZ and YZ planes uses the in-plane axes") {
  Motion m = quarter_arc(2.0);
  m.plane = gm::Plane::XZ;
  m.start_mm = xyz(2, 0, 0);
  m.end_mm = xyz(0, 0, 2);
  CHECK(gm::PathWindow::radial_deviation_mm(m, p3(0, 7, 1.5)) == Approx(-0.5));  // Y is normal
  m.plane = gm::Plane::YZ;
  m.start_mm = xyz(0, 2, 0);
  CHECK(gm::PathWindow::radial_deviation_mm(m, p3(9, 0, 3)) == Approx(1.0));  // X is normal
}
