// Contour error against the recent programmed path (lines: distance; arcs: signed radial error).
#include "pipeline/path_window.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gm {
namespace {

constexpr std::int64_t kOngoing = std::numeric_limits<std::int64_t>::max();

// The two in-plane axis indices and the normal axis of an arc plane.
struct PlaneAxes {
  int a, b, n;
};
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

// Angle swept by arc `m` from its start, radians, > 0 (full turns included).
double arc_sweep_rad(const Motion& m, const PlaneAxes& ax) {
  const double a0 =
      std::atan2(m.start_mm[ax.b] - m.center_mm[ax.b], m.start_mm[ax.a] - m.center_mm[ax.a]);
  const double a1 =
      std::atan2(m.end_mm[ax.b] - m.center_mm[ax.b], m.end_mm[ax.a] - m.center_mm[ax.a]);
  double d = m.ccw ? a1 - a0 : a0 - a1;
  while (d <= 1e-12) d += 2 * M_PI;
  return d + 2 * M_PI * (m.turns - 1);
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
  if (hint_age_ < kCapacity - 1) ++hint_age_;  // every entry is one block older now
  Entry& e = ring_[static_cast<std::size_t>(head_)];
  e.motion = m;  // Motion holds no heap storage: this is a plain copy
  e.first_sample = k;
  e.last_sample = kOngoing;
  if (m.kind == MotionKind::Arc) {
    const PlaneAxes ax = plane_axes(m.plane);
    e.ax_a = ax.a, e.ax_b = ax.b, e.ax_n = ax.n;
    const double sweep_rad = arc_sweep_rad(m, ax);
    e.partial_arc = sweep_rad < 2 * M_PI;
    e.over_half_turn = sweep_rad > M_PI;
    e.turn_sign = m.ccw ? 1.0 : -1.0;
    e.u0_a = m.start_mm[ax.a] - m.center_mm[ax.a], e.u0_b = m.start_mm[ax.b] - m.center_mm[ax.b];
    e.u1_a = m.end_mm[ax.a] - m.center_mm[ax.a], e.u1_b = m.end_mm[ax.b] - m.center_mm[ax.b];
    e.radius_mm =
        std::hypot(m.start_mm[ax.a] - m.center_mm[ax.a], m.start_mm[ax.b] - m.center_mm[ax.b]);
    e.planar = m.start_mm[ax.n] == m.end_mm[ax.n];
    // Planar arc: every point the distance is measured to (the circle's nearest point inside the
    // sweep, or an end point) lies within the larger of the start and end radii of the centre.
    e.sphere_c_mm = m.center_mm;
    e.sphere_r_mm = e.planar ? std::max(e.radius_mm, (m.end_mm - m.center_mm).norm()) : -1.0;
  } else {
    e.sphere_c_mm = 0.5 * (m.start_mm + m.end_mm);
    e.sphere_r_mm = 0.5 * (m.end_mm - m.start_mm).norm();
  }
  e.margin_mm = 1e-9 + 1e-12 * (std::max(e.sphere_r_mm, 0.0) + e.sphere_c_mm.cwiseAbs().maxCoeff());
  if (count_ < kCapacity) ++count_;
}

double PathWindow::radial_deviation_mm(const Motion& m, const AxisVec& p_mm) {
  const PlaneAxes ax = plane_axes(m.plane);
  const double r =
      std::hypot(m.start_mm[ax.a] - m.center_mm[ax.a], m.start_mm[ax.b] - m.center_mm[ax.b]);
  const double d = std::hypot(p_mm[ax.a] - m.center_mm[ax.a], p_mm[ax.b] - m.center_mm[ax.b]);
  return d - r;
}

void PathWindow::distance_to(const Entry& e, const AxisVec& p_mm, double& dist,
                             double& signed_dist) {
  const Motion& m = e.motion;
  if (m.kind != MotionKind::Arc) {
    dist = signed_dist = segment_distance_mm(m.start_mm, m.end_mm, p_mm);
    return;
  }
  const double dca = p_mm[e.ax_a] - m.center_mm[e.ax_a];
  const double dcb = p_mm[e.ax_b] - m.center_mm[e.ax_b];
  if (e.partial_arc) {
    // Is p inside the swept sector? Turning from the start ray towards p, and from p towards
    // the end ray, in the direction of motion (cross products, no angles): for a sweep up to π
    // both turns are positive; for more, p is outside only if it lies in the complementary
    // sector (both turns negative).
    const double to_p = e.turn_sign * (e.u0_a * dcb - e.u0_b * dca);
    const double p_to_end = e.turn_sign * (dca * e.u1_b - dcb * e.u1_a);
    const bool inside =
        e.over_half_turn ? !(to_p < 0.0 && p_to_end < 0.0) : (to_p >= 0.0 && p_to_end >= 0.0);
    if (!inside) {
      // Beyond the arc's ends: the nearest point of this block is an end point.
      dist = signed_dist = std::min((p_mm - m.start_mm).norm(), (p_mm - m.end_mm).norm());
      return;
    }
  }
  const double radial = std::hypot(dca, dcb) - e.radius_mm;
  // Axial deviation from the helix is bounded by the lead; for planar arcs it is exact.
  const double axial = e.planar ? p_mm[e.ax_n] - m.start_mm[e.ax_n] : 0.0;
  dist = std::hypot(radial, axial);
  signed_dist = axial == 0.0 ? radial : std::copysign(dist, radial);
}

double PathWindow::contour_error_mm(const AxisVec& p_mm, std::int64_t k) {
  if (count_ == 0) return 0.0;
  auto at = [&](int age) -> const Entry& {
    static_assert((kCapacity & (kCapacity - 1)) == 0);
    return ring_[static_cast<std::size_t>((head_ - age) & (kCapacity - 1))];
  };
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
    distance_to(at(age), p_mm, dist, signed_dist);
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
