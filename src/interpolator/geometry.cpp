// Line, arc and helix geometry: lengths and positions evaluated from the angle (no drift).
#include "interpolator/geometry.hpp"

#include <cmath>

namespace gm {

void plane_axes(Plane p, int& a, int& b, int& n) {
  switch (p) {
    case Plane::XY:
      a = 0, b = 1, n = 2;
      return;
    case Plane::XZ:
      a = 2, b = 0, n = 1;
      return;
    case Plane::YZ:
      a = 1, b = 2, n = 0;
      return;
  }
  a = 0, b = 1, n = 2;
}

BlockGeometry BlockGeometry::of(const Motion& m) {
  BlockGeometry g;
  g.kind = m.kind;
  g.start_mm = m.start_mm;
  g.end_mm = m.end_mm;
  if (m.kind != MotionKind::Arc) {
    g.length_mm = (m.end_mm - m.start_mm).norm();
    return g;
  }
  plane_axes(m.plane, g.a, g.b, g.n);
  g.center_mm = m.center_mm;
  const double sa = m.start_mm[g.a] - m.center_mm[g.a], sb = m.start_mm[g.b] - m.center_mm[g.b];
  const double ea = m.end_mm[g.a] - m.center_mm[g.a], eb = m.end_mm[g.b] - m.center_mm[g.b];
  g.r0_mm = std::hypot(sa, sb);
  g.r1_mm = std::hypot(ea, eb);
  g.theta0_rad = std::atan2(sb, sa);
  const double theta1 = std::atan2(eb, ea);
  constexpr double kTwoPi = 2.0 * M_PI;
  // The angle from start to end in the direction of motion, in (0, 2π]; start == end in the
  // plane is a full circle.
  double d = m.ccw ? theta1 - g.theta0_rad : g.theta0_rad - theta1;
  const bool closed = std::hypot(ea - sa, eb - sb) <= 1e-12 * std::max(1.0, g.r0_mm);
  if (closed) {
    d = kTwoPi;
  } else {
    while (d <= 0.0) d += kTwoPi;
    while (d > kTwoPi) d -= kTwoPi;
  }
  d += kTwoPi * static_cast<double>(std::max(m.turns, 1) - 1);
  g.sweep_rad = m.ccw ? d : -d;
  const double planar = 0.5 * (g.r0_mm + g.r1_mm) * d;
  const double height = m.end_mm[g.n] - m.start_mm[g.n];
  g.length_mm = std::hypot(planar, height);
  return g;
}

AxisVec BlockGeometry::at_fraction(double u) const {
  if (u >= 1.0) return end_mm;
  if (u <= 0.0) return start_mm;
  if (kind != MotionKind::Arc) return start_mm + u * (end_mm - start_mm);
  // Radius blends linearly from start to end radius (a spiral within the arc tolerance, as
  // LinuxCNC does), so the last sample lands on the programmed end point.
  const double theta = theta0_rad + u * sweep_rad;
  const double r = r0_mm + u * (r1_mm - r0_mm);
  AxisVec p = start_mm;  // axes outside the plane and normal stay (none with three axes)
  p[a] = center_mm[a] + r * std::cos(theta);
  p[b] = center_mm[b] + r * std::sin(theta);
  p[n] = start_mm[n] + u * (end_mm[n] - start_mm[n]);
  return p;
}

}  // namespace gm
