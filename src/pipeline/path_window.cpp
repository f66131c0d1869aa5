// Contour error against the recent programmed path (lines: distance; arcs: signed radial error).
#include "pipeline/path_window.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gm {
namespace {

constexpr std::int64_t kOngoing = std::numeric_limits<std::int64_t>::max();

}  // namespace

void PathWindow::grow() {
  std::vector<Entry> bigger(2 * ring_.size());
  for (int age = 0; age < count_; ++age)
    bigger[static_cast<std::size_t>(count_ - 1 - age)] = at(age);
  head_ = count_ - 1;
  ring_.swap(bigger);
}

void PathWindow::push(const Motion& m, std::int64_t k) {
  if (count_ > 0) ring_[static_cast<std::size_t>(head_)].last_sample = k;
  if (count_ == capacity()) {
    // The oldest block is about to be overwritten: keep it if it can still be nearest.
    const Entry& oldest = at(count_ - 1);
    if (oldest.last_sample == kOngoing || k - oldest.last_sample <= lag_samples_) {
      if (capacity() < kMaxCapacity)
        grow();
      else
        ++dropped_in_lag_;
    }
  }
  head_ = (head_ + 1) & (capacity() - 1);
  if (hint_age_ < capacity() - 1) ++hint_age_;  // every entry is one block older now
  Entry& e = ring_[static_cast<std::size_t>(head_)];
  e.geometry = MotionGeometry::of(m);
  e.first_sample = k;
  e.last_sample = kOngoing;
  if (m.kind == MotionKind::Arc) {
    // Planar arc: every point the distance is measured to (the circle's nearest point inside the
    // sweep, or an end point) lies within the larger of the start and end radii of the centre.
    e.sphere_c_mm = m.center_mm.head<3>();
    e.sphere_r_mm =
        e.geometry.planar
            ? std::max(e.geometry.r0_mm, Vec3(m.end_mm.head<3>() - m.center_mm.head<3>()).norm())
            : -1.0;
  } else {
    e.sphere_c_mm = 0.5 * (m.start_mm.head<3>() + m.end_mm.head<3>());
    e.sphere_r_mm = 0.5 * Vec3(m.end_mm.head<3>() - m.start_mm.head<3>()).norm();
  }
  e.margin_mm = 1e-9 + 1e-12 * (std::max(e.sphere_r_mm, 0.0) + e.sphere_c_mm.cwiseAbs().maxCoeff());
  if (count_ < capacity()) ++count_;
}

double PathWindow::contour_error_mm(const Vec3& p_mm, std::int64_t k) {
  if (count_ == 0) return 0.0;
  // Blocks that ended longer than the lag ago are past: the window is ages [0, limit).
  int limit = 1;
  while (limit < count_ &&
         !(at(limit).last_sample != kOngoing && k - at(limit).last_sample > lag_samples_))
    ++limit;

  double best = std::numeric_limits<double>::infinity();
  double best_signed = 0.0;
  int best_age = -1;
  auto consider = [&](int age) {
    double dist = 0.0, signed_dist = 0.0;
    at(age).geometry.distance(p_mm, dist, signed_dist);
    if (dist < best || (dist == best && age < best_age)) {
      best = dist;
      best_signed = signed_dist;
      best_age = age;
    }
  };
  // Start where the nearest block was last time: a tight bound prunes the rest early.
  const int hint = hint_age_ < limit ? hint_age_ : 0;
  const double p_margin = 1e-12 * p_mm.cwiseAbs().maxCoeff();
  consider(hint);
  for (int age = 0; age < limit; ++age) {
    if (age == hint) continue;
    const Entry& e = at(age);
    if (e.sphere_r_mm >= 0.0) {
      // Every point of the block is within sphere_r of sphere_c, so the block is at least
      // |p − c| − r away; skip it when that cannot beat (or tie) the best, with a margin far
      // above the rounding of these sums.
      const double reach = best + e.sphere_r_mm + e.margin_mm + p_margin;
      if ((p_mm - e.sphere_c_mm).squaredNorm() > reach * reach) continue;
    }
    consider(age);
  }
  hint_age_ = best_age;
  return best_signed;
}

}  // namespace gm
