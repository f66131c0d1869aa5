// G5, G5.1 and G5.2/G5.3 curves as LinuxCNC's canon runs them: a NURBS sampled at four
// parameter steps per control point, each step joined by a biarc (two tangent arcs).
#pragma once

#include <array>
#include <span>
#include <vector>

namespace gm {

/// A NURBS control point in the program's XY plane (program units) with its weight.
struct ControlPoint {
  double x = 0.0, y = 0.0, w = 1.0;
};

/// The NURBS LinuxCNC collects between G5.2 and G5.3 (one at a time, across blocks), program
/// units.
struct NurbsCurve {
  std::vector<ControlPoint> points;
  int order = 3;
};
/// What one block does to it (the curve is only changed when the block succeeds).
struct NurbsEdit {
  bool clear = false;  ///< start again (a new G5.2 run, or G5.3 done)
  int order = 0;       ///< > 0: the order from now on
  std::array<ControlPoint, 2> add{};
  int added = 0;
};

/// One piece of a fitted curve, in the same coordinates: a line to (x, y), or an arc to (x, y)
/// about (cx, cy).
struct CurvePiece {
  double x = 0.0, y = 0.0;
  bool arc = false;
  double cx = 0.0, cy = 0.0;
  bool ccw = false;
};

/// A point and the unit tangent of a NURBS of order `k` (degree k - 1) over LinuxCNC's clamped
/// uniform knots 0 (k times), 1, 2, ..., n - k + 2 (k times), at parameter u in [0, n - k + 2].
struct CurvePoint {
  double x = 0.0, y = 0.0, tx = 0.0, ty = 0.0;
};
CurvePoint nurbs_at(std::span<const ControlPoint> pts, int k, double u);

/// Appends to `out` the pieces LinuxCNC's NURBS_FEED produces for `pts` (order `k`, at least k
/// points, k >= 2): 4 x pts.size() equal parameter steps, each a biarc with equal tangent
/// lengths. `straight_tol` is the chord-normal product below which an arc is drawn straight
/// (LinuxCNC: 1e-6 in program units).
void nurbs_biarcs(std::span<const ControlPoint> pts, int k, double straight_tol,
                  std::vector<CurvePiece>& out);

}  // namespace gm
