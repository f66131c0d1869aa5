// One sample of every stage of the pipeline, in BLU: what a trace row and the summary read.
#pragma once

#include "common/axis.hpp"

#include <cstdint>

namespace gm {

/// One servo sample of every stage, in BLU (what a trace row holds). Per-axis vectors are in the
/// machine's axis order (Machine::layout); entries past its axis count are 0.
struct SampleRecord {
  std::int64_t k = 0;  ///< sample index; t = k·T
  double t_s = 0.0;
  int line = 0;                        ///< source line of the block the interpolator is in
  AxisBlu cmd_blu = AxisBlu::Zero();   ///< interpolator output
  AxisBlu ref_blu = AxisBlu::Zero();   ///< Acc/Dec output
  AxisBlu enc_blu = AxisBlu::Zero();   ///< encoder counts
  AxisBlu ferr_blu = AxisBlu::Zero();  ///< following error ref − enc
  /// Table position (BLU, continuous) at the sample instant: the motor minus lost motion; what
  /// the contour error is measured on (equal to ref with the servo off).
  MachineVec table_blu = MachineVec::Zero();
  double contour_err_blu = 0.0;  ///< table position to programmed path (signed radial on arcs)
  double feed_scale = 1.0;       ///< feed override in effect (1.0 = 100 %)
  std::uint32_t events = 0;      ///< interpolator SampleEvent bits
  bool settling = false;  ///< the program has ended; the axes are settling (no current block)
  /// Signed radial deviation of the Acc/Dec output (ref) and of the encoder from the current
  /// block when it is an arc and the sample is in its steady part; NaN otherwise (BLU).
  double arc_ref_dev_blu = 0.0;
  double arc_enc_dev_blu = 0.0;
};

}  // namespace gm
