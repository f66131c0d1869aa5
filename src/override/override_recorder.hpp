// Writes the overrides in effect during a run as a schedule that --override-file replays exactly.
#pragma once

#include <cstdint>
#include <fstream>
#include <string>

namespace gm {

/// One `t_s,percent` (or `t_s,rapid=percent`) line per change, t = k·T printed round-trip exact,
/// so replaying the file gives the same overrides sample for sample.
class OverrideRecorder {
 public:
  /// Throws gm::InputError when `path` cannot be written.
  OverrideRecorder(const std::string& path, double period_s);
  /// The overrides in effect for sample k.
  void sample(std::int64_t k, double feed_pct, double rapid_pct);
  /// Flushes; throws gm::InputError on a write error.
  void finish();

 private:
  std::ofstream out_;
  double period_s_;
  double feed_ = -1.0, rapid_ = -1.0;
};

}  // namespace gm
