// Vibration at the tool tip: residual vibration after each stop and the modes' deflection.
#pragma once

#include "common/axis.hpp"
#include "motion/sample_block.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace gm {

/// One axis's vibration figures over a run (BLU of the axis).
struct AxisVibration {
  /// Residual vibration at the worst stop: the largest |deflection| of the modes (tip − motor
  /// side) over the window after the axis's Acc/Dec output came to rest; `line`: the program
  /// line of the move that ended there.
  double residual_blu = 0.0;
  int residual_line = 0;
  double residual_t_s = 0.0;  ///< when the Acc/Dec output came to rest at that stop
  /// The largest |tip − ref| over the windows after the stops (the ringing plus the servo's
  /// own approach), and the line of the move that ended there.
  double settle_blu = 0.0;
  int settle_line = 0;
  std::int64_t stops = 0;  ///< stops measured (windows opened)
  /// The largest |deflection| of the modes (tip − motor side) along the path, and its line.
  double deflection_blu = 0.0;
  int deflection_line = 0;
};

/// Measures the vibration of the tool tip (the table with its structural modes, SampleBlock's
/// table_blu) per axis, a block at a time; constant memory, nothing allocated per sample.
///
/// A stop of an axis: its interpolator output (cmd) stops changing and stays put for
/// `filter_samples` − 1 samples, after which the Acc/Dec output (ref), a FIR of that many taps
/// of cmd, is at rest. From that sample the stop's window runs `window_s` (or until cmd moves
/// again, or the run ends). Its residual vibration is the largest |deflection| of the modes
/// (SampleBlock::defl_blu, tip − motor side: the ringing alone) over the window, and its
/// settling error the largest |tip − ref| there (the ringing plus what is left of the servo's
/// lag; a machine without modes shows the lag alone). The deflection is also watched along the
/// whole path. It also keeps the signed tip − ref of the worst stop (residual vibration) of
/// each axis, from kLeadS before the output rests to the window's end, for the report's plot.
class VibrationMeter {
 public:
  static constexpr double kDefaultWindowS = 0.2;
  /// How much of the approach before a stop the worst stop's record keeps.
  static constexpr double kLeadS = 0.05;

  VibrationMeter() = default;
  /// axes: the machine's axis count; filter_samples: taps of the Acc/Dec filter (N + 1);
  /// period_s: T; window_s: the window after each stop.
  VibrationMeter(int axes, int filter_samples, double period_s, double window_s = kDefaultWindowS);

  /// Rows first..count-1 of `b` (ref_blu, cmd_blu, table_blu, defl_blu and line read).
  void add_block(const SampleBlock& b, int first);
  /// Closes the windows still open (the run ended inside them).
  void finish();

  int axes() const { return axes_; }
  double window_s() const { return window_s_; }
  double period_s() const { return period_s_; }
  const AxisVibration& axis(int a) const { return result_[static_cast<std::size_t>(a)]; }
  /// The worst stop of axis a as recorded: tip − ref (BLU, signed) per sample from
  /// worst_record_t0_s(a) on, every T; empty when the axis had no stop with vibration.
  std::span<const double> worst_record(int a) const {
    const Record& r = rec_[static_cast<std::size_t>(a)];
    return {r.best.data(), r.best_len};
  }
  double worst_record_t0_s(int a) const {
    return static_cast<double>(rec_[static_cast<std::size_t>(a)].best_k0) * period_s_;
  }

 private:
  struct State {
    std::int64_t prev_cmd = 0;
    std::int64_t rest_k = -1;      ///< sample at which ref will be at rest (−1: none pending)
    int move_line = 0;             ///< line of the move in progress or last ended
    bool started = false;          ///< prev_cmd holds a sample
    bool moved = false;            ///< cmd has changed since the start
    std::int64_t window_left = 0;  ///< samples left in the open window (0: none open)
    double window_defl = 0.0;      ///< max |deflection| in the open window
    double window_dev = 0.0;       ///< max |tip − ref| in the open window
    int window_line = 0;
    std::int64_t window_k = 0;
  };
  /// The samples of the stop in progress and of the worst one (allocated at construction).
  struct Record {
    std::vector<double> lead;  ///< ring of the last lead_ values of tip − ref
    std::size_t lead_pos = 0, lead_len = 0;
    std::vector<double> cur, best;
    std::size_t cur_len = 0, best_len = 0;
    std::int64_t cur_k0 = 0, best_k0 = 0;
  };
  void close(int a);

  int axes_ = 0;
  std::int64_t rest_delay_ = 0;  ///< filter_samples − 1
  std::int64_t window_samples_ = 0;
  double period_s_ = 0.0;
  double window_s_ = kDefaultWindowS;
  std::array<State, kMaxAxes> state_{};
  std::array<AxisVibration, kMaxAxes> result_{};
  std::size_t lead_ = 0;  ///< samples of kLeadS
  std::array<Record, kMaxAxes> rec_{};
};

}  // namespace gm
