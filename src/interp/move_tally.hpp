// The check summary's moves, path length and time at programmed feed, added up in program order
// from compact entries (so that the adding may run on the reading thread, docs/performance.md).
#pragma once

#include "motion/canon.hpp"

#include <cstdint>
#include <variant>
#include <vector>

namespace gm {

/// What the summary needs of one canonical command, taken on the interpreter's thread by
/// subtractions only; its length (hypot, atan2, a square root) is computed where it is added.
struct TallyEntry {
  enum class Kind : std::uint8_t {
    Line,   ///< a line or rapid moving X, Y or Z: d = its X Y Z differences
    Arc,    ///< d = start − centre (a, b), end − centre (a, b), the rise along the normal
    Known,  ///< a line moving none of X, Y, Z: d[0] is its length (motion_length_mm)
    Dwell,  ///< no move: `inverse_time_s` holds its seconds
  };
  Kind kind = Kind::Line;
  bool rapid = false;
  bool ccw = false;
  int turns = 1;
  double d[5] = {};
  double feed_mm_min = 0.0;
  double inverse_time_s = 0.0;
};

/// The moves, path length and time at feed of the commands added so far, in order: the same
/// operations as motion_length_mm's on the same operands, so the same bits.
class MoveTally {
 public:
  explicit MoveTally(double rapid_mm_min) : rapid_mm_min_(rapid_mm_min) {}

  /// `c`'s entry; false for a command the summary does not count (events).
  static bool entry_of(const Canon& c, TallyEntry& e) {
    if (const auto* m = std::get_if<Motion>(&c)) {
      if (m->kind == MotionKind::Arc) {
        arc_entry(*m, e);
        return true;
      }
      e.rapid = m->kind == MotionKind::Rapid;
      e.feed_mm_min = m->feed_mm_min;
      e.inverse_time_s = m->inverse_time_s;
      e.d[0] = m->end_mm[0] - m->start_mm[0];
      e.d[1] = m->end_mm[1] - m->start_mm[1];
      e.d[2] = m->end_mm[2] - m->start_mm[2];
      e.kind = TallyEntry::Kind::Line;
      if (e.d[0] == 0.0 && e.d[1] == 0.0 && e.d[2] == 0.0) known_entry(*m, e);
      return true;
    }
    if (const auto* d = std::get_if<Dwell>(&c)) {
      e.kind = TallyEntry::Kind::Dwell;
      e.inverse_time_s = d->seconds;
      return true;
    }
    return false;
  }
  /// Adds one entry.
  void add(const TallyEntry& e);
  /// Adds every command of `out`, in order.
  void add(const std::vector<Canon>& out) {
    TallyEntry e;
    for (const Canon& c : out)
      if (entry_of(c, e)) add(e);
  }

  std::int64_t moves() const { return moves_; }
  double path_length_mm() const { return path_length_mm_; }
  double time_at_feed_s() const { return time_at_feed_s_; }

 private:
  static void arc_entry(const Motion& m, TallyEntry& e);
  static void known_entry(const Motion& m, TallyEntry& e);  ///< a line moving none of X Y Z

  double rapid_mm_min_;
  std::int64_t moves_ = 0;
  double path_length_mm_ = 0.0;
  double time_at_feed_s_ = 0.0;
};

}  // namespace gm
