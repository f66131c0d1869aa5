// Exact block geometry for the interpolator: path length and position at a path fraction.
#pragma once

#include "common/axis.hpp"
#include "interp/canon.hpp"

namespace gm {

/// A motion block prepared for sampling: lines by start and direction, arcs (and helices) by
/// centre, radii, start angle and sweep in their plane. Plain data, built once per block.
struct BlockGeometry {
  MotionKind kind = MotionKind::Line;
  AxisVec start_mm = AxisVec::Zero();
  AxisVec end_mm = AxisVec::Zero();
  double length_mm = 0.0;
  // Arcs: in-plane axes a, b (angle measured from a toward b, counter-clockwise seen from +n).
  int a = 0, b = 1, n = 2;
  AxisVec center_mm = AxisVec::Zero();
  double r0_mm = 0.0, r1_mm = 0.0;  ///< start and end radius (equal up to the arc tolerance)
  double theta0_rad = 0.0;          ///< start angle
  double sweep_rad = 0.0;           ///< signed: > 0 counter-clockwise; full turns included

  /// Builds the geometry of `m` (lines, rapids and arcs in any plane, multi-turn, helical).
  static BlockGeometry of(const Motion& m);

  /// Position at path fraction `u` in [0, 1]; u = 1 returns end_mm exactly.
  AxisVec at_fraction(double u) const;
};

/// The in-plane axes (a, b) and normal axis n of a plane, as LinuxCNC orders them:
/// XY → (X, Y; Z), XZ → (Z, X; Y), YZ → (Y, Z; X).
void plane_axes(Plane p, int& a, int& b, int& n);

}  // namespace gm
