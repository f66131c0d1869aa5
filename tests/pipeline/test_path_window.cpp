// Contour error geometry: distances to lines, signed radial deviation on arcs, arc end handling.
#include "measure/path_window.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

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

TEST_CASE("a piece of a cut block is measured to the block's end") {
  // The planner cut a line from (0,0) to (20,0) at x = 10 and an arc at its middle: a table
  // ahead of the command (a servo overshooting after a step down in speed) is on the block,
  // past the piece's end, and the measure says so; without rest_of_block the piece's end point
  // is the nearest (2 mm).
  gm::PathWindow w(100);
  Motion piece = line(xyz(0, 0, 0), xyz(10, 0, 0));
  piece.rest_of_block = true;
  piece.block_end_mm = xyz(20, 0, 0);
  w.push(piece, 0);
  CHECK(w.contour_error_mm(p3(12, 0, 0), 1) == Approx(0.0).margin(1e-12));
  CHECK(w.contour_error_mm(p3(12, 0.3, 0), 1) == Approx(0.3));
  CHECK(w.contour_error_mm(p3(23, 4, 0), 1) == Approx(5.0));  // past the block's end: its end
  gm::PathWindow a(100);
  Motion half = quarter_arc(4.0);  // the first half of the quarter, to 45°
  half.end_mm =
      xyz(4 * std::cos(0.25 * 3.141592653589793), 4 * std::sin(0.25 * 3.141592653589793), 0);
  half.rest_of_block = true;
  half.block_end_mm = xyz(0, 4, 0);
  a.push(half, 0);
  const double c = std::cos(1.2), s = std::sin(1.2);  // at 69°, on the rest of the arc
  CHECK(a.contour_error_mm(p3(4.1 * c, 4.1 * s, 0), 1) == Approx(0.1));
  gm::PathWindow plain(100);
  plain.push(line(xyz(0, 0, 0), xyz(10, 0, 0)), 0);
  CHECK(plain.contour_error_mm(p3(12, 0, 0), 1) == Approx(2.0));
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

// The window's search (hint first, bounding spheres, expiry) against a brute-force scan with
// MotionGeometry::distance: the nearest block of those that ended at most the lag ago (ties to
// the newer one), bit for bit. Short and long arcs in the three planes, clockwise and not,
// with a slightly different end radius, helices, full turns and lines, chained as a program
// chains them; points near the path and far from it.
TEST_CASE("the window's search equals a brute-force scan, arcs in every plane") {
  std::mt19937_64 rng(20261126);
  auto uni = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  const std::int64_t lag = 40;
  gm::PathWindow w(lag);
  std::vector<Motion> blocks;
  std::vector<std::int64_t> starts;
  AxisVec at = xyz(0, 0, 0);
  std::int64_t k = 0;
  int checked = 0, arcs_nearest = 0;
  for (int b = 0; b < 3000; ++b) {
    Motion m;
    m.start_mm = at;
    if (uni(0, 1) < 0.4) {
      m.kind = MotionKind::Line;
      m.end_mm = at + xyz(uni(-2, 2), uni(-2, 2), uni(-0.3, 0.3));
    } else {
      m.kind = MotionKind::Arc;
      const int plane = static_cast<int>(uni(0, 3));
      m.plane = plane == 0 ? gm::Plane::XY : plane == 1 ? gm::Plane::XZ : gm::Plane::YZ;
      const int a = plane == 2 ? 1 : 0, bb = plane == 0 ? 1 : 2, n = 3 - a - bb;
      m.ccw = uni(0, 1) < 0.5;
      const double r = uni(0.2, 20), phi0 = uni(0, 6.283);
      // Mostly short sweeps (CAM arcs), some past half a turn; once in a while a full turn.
      const double sweep = uni(0, 1) < 0.8 ? uni(0.01, 3.1) : uni(3.2, 6.2);
      const double phi1 = phi0 + (m.ccw ? sweep : -sweep);
      const double r1 = r * (1 + uni(-1e-4, 1e-4));
      m.center_mm = at;
      m.center_mm[a] -= r * std::cos(phi0);
      m.center_mm[bb] -= r * std::sin(phi0);
      m.end_mm = m.center_mm;
      m.end_mm[a] += r1 * std::cos(phi1);
      m.end_mm[bb] += r1 * std::sin(phi1);
      m.end_mm[n] = at[n] + (uni(0, 1) < 0.2 ? uni(-1, 1) : 0.0);  // a helix now and then
      if (uni(0, 1) < 0.03) {
        m.end_mm = m.start_mm;  // a full circle
        m.turns = 1;
      }
    }
    at = m.end_mm;
    blocks.push_back(m);
    starts.push_back(k);
    w.push(m, k);
    const int samples = 1 + static_cast<int>(uni(0, 12));
    for (int i = 0; i < samples; ++i, ++k) {
      // Near a recent block's path, or anywhere around.
      const Motion& near =
          blocks[blocks.size() - 1 -
                 static_cast<std::size_t>(uni(0, std::min<double>(blocks.size(), 6)))];
      const gm::MotionGeometry g = gm::MotionGeometry::of(near);
      const double off = uni(0, 1) < 0.7 ? 0.01 : 2.0;
      const AxisVec q = g.at_fraction(uni(0, 1));
      const gm::Vec3 p = p3(q[0] + uni(-off, off), q[1] + uni(-off, off), q[2] + uni(-off, off));
      double best = std::numeric_limits<double>::infinity(), best_signed = 0.0;
      bool best_arc = false;
      for (std::size_t j = blocks.size(); j-- > 0;) {  // newest first: ties go to the newer
        const std::int64_t end = j + 1 < blocks.size() ? starts[j + 1] : k + 1;
        if (j + 1 < blocks.size() && k - end > lag) break;
        double d = 0.0, s = 0.0;
        gm::MotionGeometry::of(blocks[j]).distance(p, d, s);
        if (d < best) {
          best = d;
          best_signed = s;
          best_arc = blocks[j].kind == MotionKind::Arc;
        }
      }
      const double got = w.contour_error_mm(p, k);
      INFO("block " << b << " sample " << k);
      REQUIRE(got == best_signed);
      ++checked;
      arcs_nearest += best_arc;
    }
  }
  CHECK(checked > 15000);
  CHECK(arcs_nearest > checked / 4);  // the arcs' bounds are exercised, not only the lines'
}
