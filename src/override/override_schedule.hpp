// Feed and rapid override schedules: parsed from a file, applied at sample times or source lines.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace gm {

/// One change: from time `t_s` (or from the start of source line `line`) on, the feed or the
/// rapid override is `percent`.
struct OverrideChange {
  enum class Trigger { Time, Line } trigger = Trigger::Time;
  double t_s = 0.0;
  int line = 0;
  bool rapid = false;  ///< false: feed override (G1/G2/G3); true: rapid override (G0)
  double percent = 100.0;
  int source_line = 0;  ///< line of the schedule file, for messages
};

/// A parsed schedule. File syntax, one change per line, `#` starts a comment:
///
///     t_s,percent              feed override from time t_s on          e.g.  1.5,50
///     line:N,percent           feed override from when line N starts   e.g.  line:12,150
///     t_s,rapid=percent        rapid override (also line:N,rapid=P)    e.g.  0,rapid=25
///     t_s,feed=percent         the same as t_s,percent
///
/// Percent is 0 (hold) up to the machine's maximum. Time entries must not go back in time.
class OverrideSchedule {
 public:
  /// Parses `text`; errors throw gm::InputError "FILE:LINE: message" naming the bad value.
  /// `max_percent` is the machine's maximum override.
  static OverrideSchedule parse(std::string_view text, std::string_view source_name,
                                double max_percent);
  /// Reads and parses a file (throws gm::InputError when it cannot be read).
  static OverrideSchedule load(const std::string& path, double max_percent);

  const std::vector<OverrideChange>& changes() const { return changes_; }

 private:
  std::vector<OverrideChange> changes_;
};

/// Applies a schedule while a run advances, sample by sample; no allocation per sample.
class OverridePlayer {
 public:
  OverridePlayer(const OverrideSchedule& schedule, double period_s, double feed_percent = 100.0,
                 double rapid_percent = 100.0);

  /// The overrides in effect for sample `k`, given the source line the interpolator reached at
  /// the previous sample (a line change takes effect at the next sample, like any change).
  void advance(std::int64_t k, int current_line);

  /// How many samples from k on (at most `max`) advance(k', current_line) would leave unchanged
  /// while the line stays `current_line`: none when that is not the line advance() saw last,
  /// else the samples before the next change in time.
  int steady_samples(std::int64_t k, int current_line, int max) const;

  double feed_scale() const { return feed_percent_ / 100.0; }
  double feed_percent() const { return feed_percent_; }
  double rapid_percent() const { return rapid_percent_; }
  /// Sets the values in effect (a live change); the schedule's later entries still apply.
  void set(double feed_percent, double rapid_percent) {
    feed_percent_ = feed_percent, rapid_percent_ = rapid_percent;
  }
  /// True while a time entry is still to come or any line entry exists (something may resume a
  /// hold).
  bool may_change() const { return next_time_ < time_changes_.size() || !line_changes_.empty(); }
  double rapid_scale() const { return rapid_percent_ / 100.0; }

 private:
  std::vector<OverrideChange> time_changes_;  ///< sorted by time
  std::vector<OverrideChange> line_changes_;  ///< in file order
  std::size_t next_time_ = 0;
  double period_s_;
  double feed_percent_, rapid_percent_;
  int last_line_ = -1;
};

}  // namespace gm
