// Line, arc and helix geometry: sweeps by LinuxCNC's rule, positions from the angle (no drift).
#include "motion/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace gm {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

}  // namespace

PlaneAxes plane_axes(Plane p) {
  switch (p) {
    case Plane::XY:
      return {0, 1, 2};
    case Plane::XZ:
      return {2, 0, 1};  // G18: Z, X in-plane (LinuxCNC first/second axis)
    case Plane::YZ:
      return {1, 2, 0};
  }
  return {0, 1, 2};
}

double arc_sweep_rad(const Motion& m) {
  const PlaneAxes ax = plane_axes(m.plane);
  const double t1 =
      std::atan2(m.start_mm[ax.b] - m.center_mm[ax.b], m.start_mm[ax.a] - m.center_mm[ax.a]);
  double t2 = std::atan2(m.end_mm[ax.b] - m.center_mm[ax.b], m.end_mm[ax.a] - m.center_mm[ax.a]);
  const int extra = m.turns > 0 ? m.turns - 1 : 0;
  if (m.ccw) {
    if (t2 <= t1) t2 += kTwoPi;
    return t2 - t1 + extra * kTwoPi;
  }
  if (t2 >= t1) t2 -= kTwoPi;
  return t2 - t1 - extra * kTwoPi;
}

double motion_length_mm(const Motion& m) {
  if (m.kind != MotionKind::Arc) {
    // LinuxCNC's feed rule: the XYZ distance when X, Y or Z move; else U V W; else the rotary
    // axes alone, whose length is in degrees (a feed in deg/min).
    const AxisVec d = m.end_mm - m.start_mm;
    const Vec3 xyz = d.head<3>();
    if (xyz != Vec3::Zero()) return xyz.norm();
    const Vec3 uvw = d.segment<3>(6);
    if (uvw != Vec3::Zero()) return uvw.norm();
    return Vec3(d.segment<3>(3)).norm();
  }
  const PlaneAxes ax = plane_axes(m.plane);
  const double r1 =
      std::hypot(m.start_mm[ax.a] - m.center_mm[ax.a], m.start_mm[ax.b] - m.center_mm[ax.b]);
  const double r2 =
      std::hypot(m.end_mm[ax.a] - m.center_mm[ax.a], m.end_mm[ax.b] - m.center_mm[ax.b]);
  const double h = m.end_mm[ax.n] - m.start_mm[ax.n];
  const double planar_mm = 0.5 * (r1 + r2) * std::fabs(arc_sweep_rad(m));
  return h == 0.0 ? planar_mm : std::hypot(planar_mm, h);  // hypot(x, 0) is |x| exactly
}

MotionGeometry MotionGeometry::of(const Motion& m) {
  MotionGeometry g;
  g.kind = m.kind;
  g.start_mm = m.start_mm;
  g.end_mm = m.end_mm;
  g.length_mm = motion_length_mm(m);
  if (m.kind != MotionKind::Arc) return g;
  g.ax = plane_axes(m.plane);
  g.center_mm = m.center_mm;
  const int a = g.ax.a, b = g.ax.b;
  g.s_a = m.start_mm[a] - m.center_mm[a], g.s_b = m.start_mm[b] - m.center_mm[b];
  g.e_a = m.end_mm[a] - m.center_mm[a], g.e_b = m.end_mm[b] - m.center_mm[b];
  g.r0_mm = std::hypot(g.s_a, g.s_b);
  g.r1_mm = std::hypot(g.e_a, g.e_b);
  g.theta0_rad = std::atan2(g.s_b, g.s_a);
  g.sweep_rad = arc_sweep_rad(m);
  g.planar = m.start_mm[g.ax.n] == m.end_mm[g.ax.n];
  g.rest_moves = m.start_mm.tail<kMaxAxes - 3>() != m.end_mm.tail<kMaxAxes - 3>();
  return g;
}

AxisVec MotionGeometry::at_fraction(double u) const {
  if (u >= 1.0) return end_mm;
  if (u <= 0.0) return start_mm;
  if (kind != MotionKind::Arc) return start_mm + u * (end_mm - start_mm);
  const double theta = theta0_rad + u * sweep_rad;
  const double r = r0_mm + u * (r1_mm - r0_mm);
  // Axes outside X, Y and Z (rotary, U V W) move in proportion to the path.
  AxisVec p = rest_moves ? AxisVec(start_mm + u * (end_mm - start_mm)) : start_mm;
  p[ax.a] = center_mm[ax.a] + r * std::cos(theta);
  p[ax.b] = center_mm[ax.b] + r * std::sin(theta);
  p[ax.n] = start_mm[ax.n] + u * (end_mm[ax.n] - start_mm[ax.n]);
  return p;
}

template <int P>
void MotionGeometry::at_fraction_head(double u, AxisVec& out) const {
  static_assert(P >= 3 && P <= kMaxAxes);
  auto o = out.head<P>();
  if (u >= 1.0) {
    o = end_mm.head<P>();
    return;
  }
  if (u <= 0.0) {
    o = start_mm.head<P>();
    return;
  }
  // The same arithmetic as at_fraction, entry by entry.
  if (kind != MotionKind::Arc || rest_moves)
    o = start_mm.head<P>() + u * (end_mm.head<P>() - start_mm.head<P>());
  else
    o = start_mm.head<P>();
  if (kind != MotionKind::Arc) return;
  const double theta = theta0_rad + u * sweep_rad;
  const double r = r0_mm + u * (r1_mm - r0_mm);
  out[ax.a] = center_mm[ax.a] + r * std::cos(theta);
  out[ax.b] = center_mm[ax.b] + r * std::sin(theta);
  out[ax.n] = start_mm[ax.n] + u * (end_mm[ax.n] - start_mm[ax.n]);
}
#define GM_AT_FRACTION_HEAD(P) \
  template void MotionGeometry::at_fraction_head<P>(double u, AxisVec& out) const;
GM_AT_FRACTION_HEAD(3)
GM_AT_FRACTION_HEAD(4)
GM_AT_FRACTION_HEAD(5)
GM_AT_FRACTION_HEAD(6)
GM_AT_FRACTION_HEAD(7)
GM_AT_FRACTION_HEAD(8)
GM_AT_FRACTION_HEAD(9)
#undef GM_AT_FRACTION_HEAD

AxisVec MotionGeometry::tangent_at_fraction(double u) const {
  // The direction of the tool in X, Y and Z (the contour the tolerance planner bounds).
  AxisVec d = AxisVec::Zero();
  d.head<3>() = end_mm.head<3>() - start_mm.head<3>();
  if (kind == MotionKind::Arc) {
    // d/du of the position: the turn, the radius blend and the lead.
    u = std::clamp(u, 0.0, 1.0);
    const double th = theta0_rad + u * sweep_rad;
    const double r = r0_mm + u * (r1_mm - r0_mm);
    const double dr = r1_mm - r0_mm;
    d = AxisVec::Zero();
    d[ax.a] = dr * std::cos(th) - r * sweep_rad * std::sin(th);
    d[ax.b] = dr * std::sin(th) + r * sweep_rad * std::cos(th);
    d[ax.n] = end_mm[ax.n] - start_mm[ax.n];
  }
  const double norm = d.head<3>().norm();
  return norm > 0.0 ? AxisVec(d / norm) : AxisVec(AxisVec::Zero());
}

void MotionGeometry::helix_distance(const Vec3& p, double& dist_mm, double& signed_mm) const {
  // h(u) = centre + r(u)·(cos θ(u), sin θ(u)) in the plane and n0 + u·dn along its normal, with
  // θ(u) = θ0 + u·sweep and r(u) = r0 + u·dr (at_fraction's parameter); f(u) = |h(u) − p|².
  const double ca = center_mm[ax.a], cb = center_mm[ax.b];
  const double n0 = start_mm[ax.n], dn = end_mm[ax.n] - n0;
  const double dr = r1_mm - r0_mm, sw = sweep_rad;
  const double pa = p[ax.a], pb = p[ax.b], pn = p[ax.n];
  auto f = [&](double u, double& d1, double& d2) {  // f(u), and f'(u), f''(u)
    const double th = theta0_rad + u * sw, r = r0_mm + u * dr;
    const double c = std::cos(th), s = std::sin(th);
    const double xa = ca + r * c - pa, xb = cb + r * s - pb, xn = n0 + u * dn - pn;
    const double ta = dr * c - r * sw * s, tb = dr * s + r * sw * c;  // h'(u)
    const double qa = -2.0 * dr * sw * s - r * sw * sw * c;           // h''(u)
    const double qb = 2.0 * dr * sw * c - r * sw * sw * s;
    d1 = 2.0 * (xa * ta + xb * tb + xn * dn);
    d2 = 2.0 * (ta * ta + tb * tb + dn * dn + xa * qa + xb * qb);
    return xa * xa + xb * xb + xn * xn;
  };
  // Candidates: the ends, the fraction at p's height, and p's angle on the turns nearest it.
  double cand[6] = {0.0, 1.0, 0.0, 0.0, 0.0, 0.0};
  int n = 2;
  const double uz = dn != 0.0 ? std::clamp((pn - n0) / dn, 0.0, 1.0) : 0.5;
  cand[n++] = uz;
  const double turn = std::fabs(sw);
  if (turn > 0.0) {
    double phi = std::atan2(pb - cb, pa - ca) - theta0_rad;  // from the start, in travel's sense
    if (sw < 0.0) phi = -phi;
    phi = std::fmod(phi, kTwoPi);
    if (phi < 0.0) phi += kTwoPi;
    const double k0 = std::round((uz * turn - phi) / kTwoPi);
    for (double k = k0 - 1.0; k <= k0 + 1.0; k += 1.0)
      cand[n++] = std::clamp((phi + k * kTwoPi) / turn, 0.0, 1.0);
  }
  double best_u = 0.0, best_f = std::numeric_limits<double>::infinity(), d1 = 0.0, d2 = 0.0;
  for (int i = 0; i < n; ++i) {
    const double fu = f(cand[i], d1, d2);
    if (fu < best_f) best_f = fu, best_u = cand[i];
  }
  for (int it = 0; it < 8; ++it) {  // Newton on f'(u) = 0 in [0, 1], while it improves
    f(best_u, d1, d2);
    if (!(d2 > 0.0)) break;
    const double u = std::clamp(best_u - d1 / d2, 0.0, 1.0);
    const double fu = f(u, d1, d2);
    if (!(fu < best_f)) break;
    best_f = fu, best_u = u;
  }
  dist_mm = std::sqrt(best_f);
  const double radial = std::hypot(pa - ca, pb - cb) - (r0_mm + best_u * dr);
  signed_mm = std::copysign(dist_mm, radial);
}

double MotionGeometry::radial_deviation_mm(const Vec3& p_mm) const {
  return std::hypot(p_mm[ax.a] - center_mm[ax.a], p_mm[ax.b] - center_mm[ax.b]) - r0_mm;
}

}  // namespace gm
