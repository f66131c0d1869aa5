// A polyline in the XY plane kept under a point budget by dropping points closer than a tolerance.
#pragma once

#include <cstddef>
#include <vector>

namespace gm::report {

/// One kept point; `starts_piece` begins a new polyline (a jump, or a change rapid <-> feed).
struct PathPoint {
  double x_mm = 0.0, y_mm = 0.0;
  bool starts_piece = false;
  bool rapid = false;  ///< the piece this point belongs to is a rapid
};

/// Keeps the points of a path, dropping a point that lies within `tolerance_mm()` of the last
/// kept point of its piece (the first tolerance is 0: only repeats are dropped). When more than
/// `cap` points are kept, the tolerance grows (at least 1/8192 of the path's extent, else twice
/// the last) and the kept points are filtered again, so memory stays bounded on any program.
class PathSimplifier {
 public:
  explicit PathSimplifier(std::size_t cap) : cap_(cap) {}

  /// Adds a point; `new_piece` starts a new polyline there.
  void add(double x_mm, double y_mm, bool new_piece, bool rapid);

  const std::vector<PathPoint>& points() const { return points_; }
  double tolerance_mm() const { return tol_mm_; }
  /// Points offered to add(), kept or not.
  std::size_t offered() const { return offered_; }
  /// Bounding box of every point offered (min > max when none).
  /// More pieces than `cap`: the later ones were dropped.
  bool truncated = false;
  double min_x = 1e300, min_y = 1e300, max_x = -1e300, max_y = -1e300;

 private:
  void coarsen();

  std::size_t cap_;
  std::vector<PathPoint> points_;
  double tol_mm_ = 0.0;
  std::size_t offered_ = 0;
};

}  // namespace gm::report
