// The end-of-run summary: errors, peaks with their source lines, limit checks, final position.
#pragma once

#include "common/axis.hpp"
#include "common/units.hpp"
#include "machine/machine.hpp"
#include "measure/vibration_meter.hpp"
#include "motion/block_sink.hpp"
#include "motion/sample_block.hpp"
#include "motion/sample_record.hpp"

#include <array>
#include <cstdint>
#include <optional>
#include <string>

namespace gm {

/// A peak value and the source line where it occurred.
struct Peak {
  double value = 0.0;
  int line = 0;
  void update(double v, int at_line) {
    if (v > value) value = v, line = at_line;
  }
  /// update() of x[i], line[i] for i in [i0, i1) in order, given mx = max(value, x[i0..i1)) as
  /// std::max forms it: the first x equal to a larger maximum is where update() would stop.
  void update_block(double mx, const double* x, const int* line_of, int i0, int i1) {
    if (!(mx > value)) return;
    int i = i0;
    while (i + 1 < i1 && !(x[i] == mx)) ++i;
    value = mx, line = line_of[i];
  }
};

/// One per-axis limit (Eq. 26): how many samples exceeded it, the worst value and its line.
struct LimitCheck {
  double limit = 0.0;
  std::int64_t violations = 0;
  Peak worst;
};

struct AxisSummary {
  Peak following_err_blu;  ///< max |ref − enc|
  Peak velocity_mm_s;      ///< of the Acc/Dec output (the commanded motion)
  Peak accel_mm_s2;
  Peak jerk_mm_s3;
  LimitCheck v_limit, f_limit, p_limit;  ///< V'[k] ≤ V_max, F = m·a + c·V ≤ F_max, P = F·V ≤ P_max
  std::int64_t final_ref_err_blu = 0;  ///< Acc/Dec output − programmed end
  std::int64_t final_enc_err_blu = 0;  ///< encoder − programmed end
};

/// Accumulates statistics over the samples of a run (constant memory); a run's BlockSink.
class RunSummary : public BlockSink {
 public:
  explicit RunSummary(const Machine& machine);
  /// Measures the vibration at the tool tip too (a machine with structural modes, servo on):
  /// VibrationMeter with the Acc/Dec filter's `filter_samples` taps; text() and json() then
  /// report it and say that the contour error is the tool tip's.
  void measure_vibration(int filter_samples, double window_s = VibrationMeter::kDefaultWindowS);
  /// The vibration figures (measure_vibration() was called), or nullptr.
  const VibrationMeter* vibration() const { return vibration_ ? &*vibration_ : nullptr; }

  /// Adds rows first..count-1 of `b` (every sample, not only the decimated trace rows; contour
  /// columns filled by ContourMeter::measure_block), a column at a time.
  void add_block(const SampleBlock& b, int first);
  void consume(const SampleBlock& b, int first) override { add_block(b, first); }
  /// Records the end: the last sample, the programmed end point and whether the axes settled.
  void finish(const SampleRecord& last, const AxisBlu& program_end_blu, bool settled);
  void finish(const RunEnd& end) override { finish(end.last, end.program_end_blu, end.settled); }

  /// Human-readable summary, several lines.
  std::string text() const;
  /// The same as one JSON object.
  /// `extra_member`: one more JSON member (e.g. the tolerance check's) appended to the object
  /// when not empty.
  std::string json(const std::string& extra_member = {}) const;

  std::int64_t samples = 0;
  double cycle_time_s = 0.0;    ///< until the axes settled
  double program_time_s = 0.0;  ///< until the interpolator finished
  Peak contour_err_blu;         ///< max |contour error| of the actual position
  double contour_rms_blu = 0.0;
  bool settled = false;
  double hold_time_s = 0.0;                  ///< time spent in feed hold (0 % override)
  std::array<AxisSummary, kMaxAxes> axes{};  ///< the machine's axes, its order
  /// Mean signed radial deviation over the steady part of arc blocks (BLU; NaN if no arcs).
  double arc_ref_radial_dev_blu = 0.0;
  double arc_enc_radial_dev_blu = 0.0;
  std::int64_t arc_samples = 0;

 protected:  // the running state, which a per-sample reference model (tests/support) updates
  const Machine& machine_;
  int axes_;  ///< the machine's axis count
  MachineVec blu_mm_;
  /// Mass (kg) and damping (kg/s) of a linear axis; inertia (kg·m²) and damping (N·m·s/rad)
  /// of a rotary one.
  MachineVec mass_kg_ = MachineVec::Zero(), damping_kg_s_ = MachineVec::Zero();
  MachineVec unit_per_si_ = MachineVec::Constant(units::kMmPerMetre);  ///< units::unit_per_si
  double period_s_;
  double contour_sq_sum_ = 0.0;
  std::int64_t hold_samples_ = 0;
  double arc_ref_sum_ = 0.0, arc_enc_sum_ = 0.0;
  AxisBlu prev_ref_ = AxisBlu::Zero();
  MachineVec prev_v_ = MachineVec::Zero(), prev_a_ = MachineVec::Zero();
  std::int64_t last_motion_k_ = 0;
  std::optional<VibrationMeter> vibration_;
};

}  // namespace gm
