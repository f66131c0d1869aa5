// A polyline in the XY plane kept under a point budget by dropping points closer than a tolerance.
#include "report/path_simplifier.hpp"

#include <algorithm>
#include <cmath>

namespace gm::report {
namespace {

bool within(const PathPoint& a, double x, double y, double tol) {
  const double d = std::hypot(a.x_mm - x, a.y_mm - y);
  return tol == 0.0 ? d == 0.0 : d < tol;
}

}  // namespace

void PathSimplifier::add(double x_mm, double y_mm, bool new_piece, bool rapid) {
  ++offered_;
  min_x = std::min(min_x, x_mm), max_x = std::max(max_x, x_mm);
  min_y = std::min(min_y, y_mm), max_y = std::max(max_y, y_mm);
  if (points_.empty()) new_piece = true;
  if (!new_piece && within(points_.back(), x_mm, y_mm, tol_mm_)) return;
  points_.push_back({x_mm, y_mm, new_piece, rapid});
  if (points_.size() > cap_) coarsen();
}

void PathSimplifier::coarsen() {
  const double extent = std::max(max_x - min_x, max_y - min_y);
  while (points_.size() > cap_) {
    tol_mm_ = std::max(tol_mm_ * 2.0, extent / 8192.0);
    if (tol_mm_ == 0.0) tol_mm_ = 1e-9;
    std::size_t out = 0;
    for (std::size_t i = 0; i < points_.size(); ++i) {
      const PathPoint& p = points_[i];
      const bool last_of_piece = i + 1 == points_.size() || points_[i + 1].starts_piece;
      if (!p.starts_piece && !last_of_piece && within(points_[out - 1], p.x_mm, p.y_mm, tol_mm_))
        continue;
      points_[out++] = p;
    }
    points_.resize(out);
    if (out > cap_ && tol_mm_ > extent) {  // only piece ends left: drop the pieces' inner ends
      points_.resize(cap_);
      truncated = true;
      break;
    }
  }
}

}  // namespace gm::report
