// One motion geometry: length, point and tangent at a distance along it, sweep, and the distance
// from a point, for lines, rapids, arcs and helices; used by the interpreter, the interpolator
// and the contour meter.
#pragma once

#include "common/axis.hpp"
#include "motion/canon.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace gm {

/// A point in X, Y and Z: what the contour error is measured in.
using Vec3 = Eigen::Matrix<double, 3, 1>;

/// The in-plane axes (a, b) and the normal axis n of a plane, as LinuxCNC orders them:
/// XY → (X, Y; Z), XZ → (Z, X; Y), YZ → (Y, Z; X). Angles run from a toward b.
struct PlaneAxes {
  int a = 0, b = 1, n = 2;
};
PlaneAxes plane_axes(Plane p);

/// Signed sweep of arc `m`, radians (> 0 counter-clockwise seen from +n), full turns included.
/// LinuxCNC's rule (interp_find.cc find_turn): the end angle is moved by one turn when it is not
/// beyond the start angle in the direction of motion, so an end equal to the start is a full
/// circle; each turn past the first adds 2π.
double arc_sweep_rad(const Motion& m);

/// Length of a motion's path, the length its feed applies to (LinuxCNC's rule), mm: for lines
/// and rapids the XYZ segment when X, Y or Z move, else the UVW segment, else the rotary (A B C)
/// segment in degrees; for arcs the XYZ helix over the mean of the start and end radii, extra
/// turns included. Other axes move in proportion.
double motion_length_mm(const Motion& m);

/// A segment in X, Y and Z with its difference and squared length formed once.
struct Segment {
  Vec3 a = Vec3::Zero();  ///< start
  Vec3 d = Vec3::Zero();  ///< end − start
  double len2 = 0.0;      ///< |end − start|²
  static Segment of(const Vec3& start, const Vec3& end) {
    Segment s;
    s.a = start;
    s.d = end - start;
    s.len2 = s.d.squaredNorm();
    return s;
  }
  /// Distance from `p` to the segment.
  double distance(const Vec3& p) const {
    const double t = std::clamp(len2 > 0 ? (p - a).dot(d) / len2 : 0.0, 0.0, 1.0);
    return (a + t * d - p).norm();
  }
};

/// A motion prepared for evaluation: plain data, built once per block.
struct MotionGeometry {
  MotionKind kind = MotionKind::Line;
  AxisVec start_mm = AxisVec::Zero();
  AxisVec end_mm = AxisVec::Zero();
  double length_mm = 0.0;
  // Arcs only.
  PlaneAxes ax;
  AxisVec center_mm = AxisVec::Zero();
  double r0_mm = 0.0, r1_mm = 0.0;  ///< start and end radius (equal up to the arc tolerance)
  double theta0_rad = 0.0;          ///< start angle
  double sweep_rad = 0.0;           ///< arc_sweep_rad()
  double s_a = 0, s_b = 0;          ///< start − centre in the plane
  double e_a = 0, e_b = 0;          ///< end − centre in the plane
  bool planar = true;               ///< no lead along the normal axis
  bool rest_moves = false;          ///< an axis past X, Y, Z moves (arcs)

  /// The geometry of `m` (lines, rapids and arcs in any plane, multi-turn, helical).
  static MotionGeometry of(const Motion& m);

  /// Position at path fraction `u` in [0, 1]; u = 1 returns end_mm exactly. On arcs the radius
  /// blends linearly from r0 to r1 (a spiral within the arc tolerance, as LinuxCNC does).
  AxisVec at_fraction(double u) const;
  /// at_fraction(u) into entries 0..P-1 of `out` only (P >= 3; the rest untouched): the
  /// interpolator's per-sample call, for the program axes its machine reads. Instantiated for
  /// P = 3..9.
  template <int P>
  void at_fraction_head(double u, AxisVec& out) const;
  /// Position at `s_mm` along the path (clamped to [0, length]).
  AxisVec point_at(double s_mm) const {
    return at_fraction(length_mm > 0.0 ? s_mm / length_mm : 1.0);
  }
  /// Unit tangent of the XYZ path at `s_mm` (the other axes 0); zero when X, Y and Z stand.
  AxisVec tangent_at(double s_mm) const {
    return tangent_at_fraction(length_mm > 0.0 ? s_mm / length_mm : 0.0);
  }
  /// Unit tangent at path fraction `u` in [0, 1].
  AxisVec tangent_at_fraction(double u) const;

  /// The XYZ segment from start to end (lines and rapids), for distance().
  Segment segment() const { return Segment::of(start_mm.head<3>(), end_mm.head<3>()); }
  /// Distance from `p_mm` to the motion. Lines: to the segment. Planar arcs: when p lies in the
  /// swept sector (or the arc is a full turn or more), the radial deviation |p−c|−r0 in the plane
  /// combined with the axial offset; otherwise the distance to the nearer end point. Helices: to
  /// the nearest point of the helix (helix_distance). `signed_mm` carries the sign of the radial
  /// deviation (negative = inside) on arcs; on lines it equals `dist_mm`.
  /// Measured in X, Y and Z only (the rotary and U V W axes report their own following error).
  void distance(const Vec3& p_mm, double& dist_mm, double& signed_mm) const {
    distance(segment(), p_mm, dist_mm, signed_mm);
  }
  /// distance() with segment() formed beforehand (the contour meter keeps it per block).
  [[gnu::always_inline]] inline void distance(const Segment& seg, const Vec3& p_mm, double& dist_mm,
                                              double& signed_mm) const;
  /// distance() of a helix (an arc with travel along its normal): the nearest point minimises
  /// |h(u) − p|² over u in [0, 1], found from a few candidates (the ends, p's height, p's angle on
  /// the turns nearest that height) refined by Newton steps; constant work whatever the turns.
  void helix_distance(const Vec3& p_mm, double& dist_mm, double& signed_mm) const;
  /// Signed radial deviation |p−c|−r0 of `p_mm` in the arc's plane (mm); arcs only.
  double radial_deviation_mm(const Vec3& p_mm) const;
};

inline void MotionGeometry::distance(const Segment& seg, const Vec3& p_mm, double& dist_mm,
                                     double& signed_mm) const {
  if (kind != MotionKind::Arc) {
    dist_mm = signed_mm = seg.distance(p_mm);
    return;
  }
  if (!planar) [[unlikely]] {
    helix_distance(p_mm, dist_mm, signed_mm);
    return;
  }
  const double dca = p_mm[ax.a] - center_mm[ax.a];
  const double dcb = p_mm[ax.b] - center_mm[ax.b];
  const double turn = std::fabs(sweep_rad);
  if (turn < 2.0 * std::numbers::pi) {
    // Is p inside the swept sector? Turning from the start ray towards p, and from p towards
    // the end ray, in the direction of motion (cross products, no angles): for a sweep up to π
    // both turns are positive; for more, p is outside only if it lies in the complementary
    // sector (both turns negative).
    const double sign = sweep_rad > 0.0 ? 1.0 : -1.0;
    const double to_p = sign * (s_a * dcb - s_b * dca);
    const double p_to_end = sign * (dca * e_b - dcb * e_a);
    const bool inside = turn > std::numbers::pi ? !(to_p < 0.0 && p_to_end < 0.0)
                                                : (to_p >= 0.0 && p_to_end >= 0.0);
    if (!inside) {
      // Beyond the arc's ends: the nearest point of this motion is an end point.
      dist_mm = signed_mm =
          std::min((p_mm - start_mm.head<3>()).norm(), (p_mm - end_mm.head<3>()).norm());
      return;
    }
  }
  // √(a² + b²) rather than std::hypot: the terms are lengths of a machine's travel (no overflow
  // or underflow to guard against), and this runs for every sample on an arc.
  const double radial = std::sqrt(dca * dca + dcb * dcb) - r0_mm;
  const double axial = p_mm[ax.n] - start_mm[ax.n];
  if (axial == 0.0) {
    dist_mm = std::fabs(radial);
    signed_mm = radial;
    return;
  }
  dist_mm = std::sqrt(radial * radial + axial * axial);
  signed_mm = std::copysign(dist_mm, radial);
}

/// The interpolator's name for it.
using BlockGeometry = MotionGeometry;

}  // namespace gm
