// One motion geometry: sweeps, lengths, points, tangents and distances against closed forms.
#include "motion/geometry.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

using gm::xyz;

using gm::AxisVec;
using gm::Motion;
using gm::MotionGeometry;
using gm::MotionKind;

namespace {
// A point in X, Y, Z: what the contour error is measured on.
gm::Vec3 p3(double x, double y, double z) {
  return gm::Vec3(x, y, z);
}

constexpr double kPi = std::numbers::pi;

Motion line(AxisVec a, AxisVec b) {
  Motion m;
  m.kind = MotionKind::Line;
  m.start_mm = a;
  m.end_mm = b;
  return m;
}

Motion arc(AxisVec a, AxisVec b, AxisVec c, bool ccw, gm::Plane plane = gm::Plane::XY,
           int turns = 1) {
  Motion m;
  m.kind = MotionKind::Arc;
  m.start_mm = a;
  m.end_mm = b;
  m.center_mm = c;
  m.ccw = ccw;
  m.plane = plane;
  m.turns = turns;
  return m;
}

bool near(const AxisVec& a, const AxisVec& b, double tol = 1e-12) {
  return (a - b).norm() <= tol;
}

}  // namespace

TEST_CASE("geometry: a 3-4-5 line") {
  const MotionGeometry g = MotionGeometry::of(line(xyz(1, 1, 0), xyz(4, 5, 0)));
  CHECK(g.length_mm == 5.0);
  CHECK(near(g.point_at(2.5), xyz(2.5, 3, 0)));
  CHECK(near(g.tangent_at(1.0), xyz(0.6, 0.8, 0)));
  CHECK(g.at_fraction(1.0) == xyz(4, 5, 0));
  double d = 0, sd = 0;
  g.distance(p3(1 + 4, 1 - 3, 0), d, sd);  // perpendicular to the start: 5 away
  CHECK(d == Approx(5.0));
  g.distance(p3(7, 9, 0), d, sd);  // beyond the end (3, 4) further on: 5 away from it
  CHECK(d == Approx(5.0));
  CHECK(sd == d);
}

TEST_CASE("geometry: sweeps by LinuxCNC's rule, in each plane and direction") {
  const double r = 10;
  // XY quarter turns: (10,0) -> (0,10) is +π/2 counter-clockwise, -3π/2 clockwise.
  CHECK(gm::arc_sweep_rad(arc(xyz(r, 0, 0), xyz(0, r, 0), AxisVec::Zero(), true)) ==
        Approx(kPi / 2));
  CHECK(gm::arc_sweep_rad(arc(xyz(r, 0, 0), xyz(0, r, 0), AxisVec::Zero(), false)) ==
        Approx(-3 * kPi / 2));
  // An end equal to the start is a full circle; P3 adds two more turns.
  const AxisVec s = xyz(r, 0, 0);
  CHECK(gm::arc_sweep_rad(arc(s, s, AxisVec::Zero(), true)) == Approx(2 * kPi));
  CHECK(gm::arc_sweep_rad(arc(s, s, AxisVec::Zero(), false)) == Approx(-2 * kPi));
  CHECK(gm::arc_sweep_rad(arc(s, s, AxisVec::Zero(), true, gm::Plane::XY, 3)) == Approx(6 * kPi));
  // An end a hair past the start is a hair of an arc one way and almost a turn the other.
  const AxisVec e = xyz(r * std::cos(1e-9), r * std::sin(1e-9), 0);
  CHECK(gm::arc_sweep_rad(arc(s, e, AxisVec::Zero(), true)) == Approx(1e-9).margin(1e-15));
  CHECK(gm::arc_sweep_rad(arc(s, e, AxisVec::Zero(), false)) == Approx(-2 * kPi + 1e-9));
  // G18: angles run from Z toward X. X=10 -> Z=10 counter-clockwise: from π/2 to 0, i.e. 3π/2.
  CHECK(gm::arc_sweep_rad(arc(xyz(r, 0, 0), xyz(0, 0, r), AxisVec::Zero(), true, gm::Plane::XZ)) ==
        Approx(3 * kPi / 2));
  // G19: angles run from Y toward Z. Y=10 -> Z=10 counter-clockwise: π/2.
  CHECK(gm::arc_sweep_rad(arc(xyz(0, r, 0), xyz(0, 0, r), AxisVec::Zero(), true, gm::Plane::YZ)) ==
        Approx(kPi / 2));
}

TEST_CASE("geometry: a quarter arc's length, points, tangents and distances") {
  const MotionGeometry g =
      MotionGeometry::of(arc(xyz(10, 0, 0), xyz(0, 10, 0), AxisVec::Zero(), true));
  CHECK(g.length_mm == Approx(5 * kPi));
  const double h = 10 / std::sqrt(2.0);
  CHECK(near(g.point_at(g.length_mm / 2), xyz(h, h, 0), 1e-12));
  CHECK(near(g.tangent_at(0), xyz(0, 1, 0)));
  CHECK(near(g.tangent_at(g.length_mm), xyz(-1, 0, 0)));
  double d = 0, sd = 0;
  g.distance(p3(20, 20, 0), d, sd);  // in the sector: radial 20√2 − 10, outside
  CHECK(d == Approx(20 * std::sqrt(2.0) - 10));
  CHECK(sd == Approx(d));
  g.distance(p3(3, 4, 0), d, sd);  // inside the circle: negative
  CHECK(sd == Approx(-5.0));
  g.distance(p3(10, -5, 0), d, sd);  // behind the start: the start point is nearest
  CHECK(d == Approx(5.0));
  g.distance(p3(h, h, 2), d, sd);  // above the arc: the axial offset counts
  CHECK(d == Approx(2.0));
  CHECK(g.radial_deviation_mm(p3(0, -12, 7)) == Approx(2.0));
}

TEST_CASE("geometry: a helix of two turns") {
  // r = 1 around Z, rising 3 mm over two full turns (P2): length hypot(2·2π, 3).
  const Motion m = arc(xyz(1, 0, 0), xyz(1, 0, 3), AxisVec::Zero(), true, gm::Plane::XY, 2);
  const MotionGeometry g = MotionGeometry::of(m);
  CHECK(g.sweep_rad == Approx(4 * kPi));
  CHECK(g.length_mm == Approx(std::hypot(4 * kPi, 3.0)));
  CHECK(gm::motion_length_mm(m) == g.length_mm);
  CHECK(near(g.point_at(g.length_mm / 4), xyz(-1, 0, 0.75), 1e-12));
  const AxisVec t = g.tangent_at(0);
  CHECK(near(t, xyz(0, 4 * kPi, 3) / std::hypot(4 * kPi, 3.0), 1e-12));
  CHECK(g.at_fraction(1.0) == m.end_mm);
}

namespace {

// The nearest point of a helix, found by brute force: the smallest distance to 200,001 points
// at_fraction() puts along it, refined around the best by a finer scan.
double brute_helix_distance(const MotionGeometry& g, const gm::Vec3& p) {
  auto d = [&](double u) { return (g.at_fraction(u).head<3>() - p).norm(); };
  constexpr int kN = 200000;
  int best = 0;
  for (int i = 1; i <= kN; ++i)
    if (d(static_cast<double>(i) / kN) < d(static_cast<double>(best) / kN)) best = i;
  double lo = std::max(0.0, (best - 1.0) / kN), hi = std::min(1.0, (best + 1.0) / kN);
  double dist = d(static_cast<double>(best) / kN);
  for (int i = 0; i <= 1000; ++i) dist = std::min(dist, d(lo + (hi - lo) * i / 1000.0));
  return dist;
}

}  // namespace

TEST_CASE("geometry: distance to a helix is to its nearest point, in 3-D") {
  // A steep helix (a 3-degree turn of r 4.22 falling 5.98 mm, from a CAM program) and a helix of
  // two turns: the contour meter's distance against a brute-force search along the helix, from
  // points around them (inside, outside, above, below, beyond the ends).
  const Motion steep =
      arc(xyz(-4.236, 2.844, 5), xyz(-4.1349, 3.054, -0.98), xyz(-7.988, 4.78, 0), true);
  const Motion two_turns =
      arc(xyz(1, 0, 0), xyz(1, 0, 3), AxisVec::Zero(), false, gm::Plane::XY, 2);
  for (const Motion& m : {steep, two_turns}) {
    const MotionGeometry g = MotionGeometry::of(m);
    REQUIRE_FALSE(g.planar);
    for (double u : {-0.1, 0.0, 0.02, 0.3, 0.5, 0.77, 1.0, 1.1}) {
      const gm::Vec3 on = g.at_fraction(std::clamp(u, 0.0, 1.0)).head<3>();
      for (const gm::Vec3& off : {gm::Vec3(0.05, 0, 0), gm::Vec3(0, -0.2, 0.1),
                                  gm::Vec3(0.1, 0.1, -0.3), gm::Vec3(-0.4, 0, 0.2)}) {
        const gm::Vec3 p = on + off + (u < 0 ? gm::Vec3(0, 0, 0.5) : gm::Vec3::Zero());
        double dist = 0, signed_dist = 0;
        g.distance(p, dist, signed_dist);
        CAPTURE(u, off.transpose(), dist);
        CHECK(dist == Approx(brute_helix_distance(g, p)).margin(1e-7));
        CHECK(std::fabs(signed_dist) == dist);
      }
    }
  }
}
