// A move's length and time at feed from its tally entry, with motion_length_mm's operations.
#include "interp/move_tally.hpp"

#include "motion/geometry.hpp"

#include <cmath>
#include <numbers>

namespace gm {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// motion_length_mm of an arc (with arc_sweep_rad) on the differences it subtracts.
double arc_length_mm(const TallyEntry& e) {
  const double r1 = std::hypot(e.d[0], e.d[1]);
  const double r2 = std::hypot(e.d[2], e.d[3]);
  const double h = e.d[4];
  const double t1 = std::atan2(e.d[1], e.d[0]);
  double t2 = std::atan2(e.d[3], e.d[2]);
  const int extra = e.turns > 0 ? e.turns - 1 : 0;
  double sweep = 0.0;
  if (e.ccw) {
    if (t2 <= t1) t2 += kTwoPi;
    sweep = t2 - t1 + extra * kTwoPi;
  } else {
    if (t2 >= t1) t2 -= kTwoPi;
    sweep = t2 - t1 - extra * kTwoPi;
  }
  const double planar_mm = 0.5 * (r1 + r2) * std::fabs(sweep);
  return h == 0.0 ? planar_mm : std::hypot(planar_mm, h);
}

}  // namespace

void MoveTally::arc_entry(const Motion& m, TallyEntry& e) {
  const PlaneAxes ax = plane_axes(m.plane);
  e.kind = TallyEntry::Kind::Arc;
  e.rapid = false;
  e.ccw = m.ccw;
  e.turns = m.turns;
  e.d[0] = m.start_mm[ax.a] - m.center_mm[ax.a];
  e.d[1] = m.start_mm[ax.b] - m.center_mm[ax.b];
  e.d[2] = m.end_mm[ax.a] - m.center_mm[ax.a];
  e.d[3] = m.end_mm[ax.b] - m.center_mm[ax.b];
  e.d[4] = m.end_mm[ax.n] - m.start_mm[ax.n];
  e.feed_mm_min = m.feed_mm_min;
  e.inverse_time_s = m.inverse_time_s;
}

void MoveTally::known_entry(const Motion& m, TallyEntry& e) {
  e.kind = TallyEntry::Kind::Known;
  e.d[0] = motion_length_mm(m);
}

void MoveTally::add(const TallyEntry& e) {
  if (e.kind == TallyEntry::Kind::Dwell) {
    time_at_feed_s_ += e.inverse_time_s;
    return;
  }
  ++moves_;
  const double len = e.kind == TallyEntry::Kind::Arc    ? arc_length_mm(e)
                     : e.kind == TallyEntry::Kind::Line ? Vec3(e.d[0], e.d[1], e.d[2]).norm()
                                                        : e.d[0];
  path_length_mm_ += len;
  if (e.rapid)
    time_at_feed_s_ += rapid_mm_min_ > 0 ? len / rapid_mm_min_ * 60.0 : 0.0;
  else if (e.inverse_time_s > 0)
    time_at_feed_s_ += e.inverse_time_s;
  else if (e.feed_mm_min > 0)
    time_at_feed_s_ += len / e.feed_mm_min * 60.0;
}

}  // namespace gm
