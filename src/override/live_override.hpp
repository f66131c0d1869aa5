// Live override input for --realtime runs: typed lines on a terminal or stdin, read without
// blocking.
#pragma once

#include <string>

namespace gm {

/// Reads override commands from a file descriptor without blocking the run. One command a line:
///
///     75          feed override 75 %          rapid 25 / rapid=25   rapid override 25 %
///     +  /  -     feed override ±10 %         0 / hold              feed hold (0 %)
///
/// Values outside 0..max are refused with a message on stderr (never clamped).
class LiveOverride {
 public:
  LiveOverride(int fd, double max_percent);

  /// Applies every complete line that has arrived to `feed_percent` / `rapid_percent`.
  /// Returns false once the input has closed (the last values stay in effect).
  bool poll(double& feed_percent, double& rapid_percent);

 private:
  void apply(const std::string& line, double& feed_percent, double& rapid_percent) const;

  int fd_;
  double max_percent_;
  bool open_ = true;
  std::string pending_;
};

}  // namespace gm
