// Contour error against the recent programmed path (lines: distance; arcs: signed radial error).
#include "pipeline/path_window.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gm {
namespace {

// The two in-plane axis indices and the normal axis of an arc plane.
struct PlaneAxes {
  int a, b, n;
};
PlaneAxes plane_axes(Plane p) {
  switch (p) {
    case Plane::XY: return {0, 1, 2};
    case Plane::XZ: return {2, 0, 1};  // G18: Z, X in-plane (LinuxCNC first/second axis)
    case Plane::YZ: return {1, 2, 0};
  }
  return {0, 1, 2};
}

// Angle swept by arc `m` from its start, radians, > 0 (full turns included).
double arc_sweep_rad(const Motion& m, const PlaneAxes& ax) {
  const double a0 = std::atan2(m.start_mm[ax.b] - m.center_mm[ax.b], m.start_mm[ax.a] - m.center_mm[ax.a]);
  const double a1 = std::atan2(m.end_mm[ax.b] - m.center_mm[ax.b], m.end_mm[ax.a] - m.center_mm[ax.a]);
  double d = m.ccw ? a1 - a0 : a0 - a1;
  while (d <= 1e-12) d += 2 * M_PI;
  return d + 2 * M_PI * (m.turns - 1);
}

// Angle from the arc's start to point `p`, in the direction of motion, in [0, 2π).
double arc_progress_rad(const Motion& m, const PlaneAxes& ax, const AxisVec& p) {
  const double a0 = std::atan2(m.start_mm[ax.b] - m.center_mm[ax.b], m.start_mm[ax.a] - m.center_mm[ax.a]);
  const double ap = std::atan2(p[ax.b] - m.center_mm[ax.b], p[ax.a] - m.center_mm[ax.a]);
  double d = m.ccw ? ap - a0 : a0 - ap;
  while (d < 0) d += 2 * M_PI;
  while (d >= 2 * M_PI) d -= 2 * M_PI;
  return d;
}

double segment_distance_mm(const AxisVec& a, const AxisVec& b, const AxisVec& p) {
  const AxisVec d = b - a;
  const double len2 = d.squaredNorm();
  double t = len2 > 0 ? (p - a).dot(d) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return (a + t * d - p).norm();
}

}  // namespace

void PathWindow::push(const Motion& m, std::int64_t k) {
  if (count_ > 0) ring_[static_cast<std::size_t>(head_)].last_sample = k;
  head_ = (head_ + 1) % kCapacity;
  Entry& e = ring_[static_cast<std::size_t>(head_)];
  e.motion = m;  // Motion holds no heap storage: this is a plain copy
  e.first_sample = k;
  e.last_sample = std::numeric_limits<std::int64_t>::max();
  if (count_ < kCapacity) ++count_;
}

double PathWindow::radial_deviation_mm(const Motion& m, const AxisVec& p_mm) {
  const PlaneAxes ax = plane_axes(m.plane);
  const double r = std::hypot(m.start_mm[ax.a] - m.center_mm[ax.a], m.start_mm[ax.b] - m.center_mm[ax.b]);
  const double d = std::hypot(p_mm[ax.a] - m.center_mm[ax.a], p_mm[ax.b] - m.center_mm[ax.b]);
  return d - r;
}

double PathWindow::contour_error_mm(const AxisVec& p_mm, std::int64_t k) const {
  double best = std::numeric_limits<double>::infinity();
  double best_signed = 0.0;
  for (int i = 0; i < count_; ++i) {
    const Entry& e = ring_[static_cast<std::size_t>((head_ - i + kCapacity) % kCapacity)];
    if (i > 0 && e.last_sample != std::numeric_limits<std::int64_t>::max() &&
        k - e.last_sample > lag_samples_)
      break;  // older blocks ended longer ago than the lag: the axes are past them
    const Motion& m = e.motion;
    double dist, signed_dist;
    if (m.kind == MotionKind::Arc) {
      const PlaneAxes ax = plane_axes(m.plane);
      if (arc_sweep_rad(m, ax) < 2 * M_PI && arc_progress_rad(m, ax, p_mm) > arc_sweep_rad(m, ax)) {
        // Beyond the arc's ends: the nearest point of this block is an end point.
        dist = std::min((p_mm - m.start_mm).norm(), (p_mm - m.end_mm).norm());
        if (dist < best) best = dist, best_signed = dist;
        continue;
      }
      const double radial = radial_deviation_mm(m, p_mm);
      // Axial deviation from the helix is bounded by the lead; for planar arcs it is exact.
      const double axial = m.start_mm[ax.n] == m.end_mm[ax.n] ? p_mm[ax.n] - m.start_mm[ax.n] : 0.0;
      dist = std::hypot(radial, axial);
      signed_dist = axial == 0.0 ? radial : std::copysign(dist, radial);
    } else {
      dist = segment_distance_mm(m.start_mm, m.end_mm, p_mm);
      signed_dist = dist;
    }
    if (dist < best) {
      best = dist;
      best_signed = signed_dist;
    }
  }
  return count_ == 0 ? 0.0 : best_signed;
}

}  // namespace gm
