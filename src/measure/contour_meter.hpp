// Contour error of each sample: the table position against the recent programmed path, in BLU.
#pragma once

#include "common/axis.hpp"
#include "measure/path_window.hpp"
#include "motion/canon.hpp"
#include "motion/sample_block.hpp"
#include "motion/sample_record.hpp"

#include <array>
#include <cstdint>
#include <span>

namespace gm {

/// Measures what the table did against the programmed path: SampleRecord::contour_err_blu and,
/// on the steady part of an arc, arc_ref_dev_blu and arc_enc_dev_blu. It reads only the record
/// and the motions handed to it, so it runs sample by sample or, fed the same rows in the same
/// order, a block at a time on another thread (gmotion run does that): the results are the same.
/// Nothing is allocated per sample.
class ContourMeter {
 public:
  /// blu_mm: BLU per axis (the errors are expressed in the smallest); window_samples: how long
  /// after its end a block stays a candidate for the nearest point (Acc/Dec length + servo lag);
  /// steady_after: samples after a block start, or a pause, before an arc counts as steady.
  /// `axes`: the machine's axes (blu_mm in their order); the contour is measured in X, Y and Z
  /// and expressed in `contour_blu_mm` (Machine::contour_blu_mm()); the other axes report only
  /// their following error.
  ContourMeter(const MachineVec& blu_mm, const AxisLayout& axes, double contour_blu_mm,
               std::int64_t window_samples, std::int64_t steady_after);

  /// Fills r.contour_err_blu, r.arc_ref_dev_blu and r.arc_enc_dev_blu from r.k, r.table_blu,
  /// r.ref_blu, r.enc_blu, r.events and r.settling. `started`: the motion blocks that became
  /// current in this sample, in order (SampleBlock::motions of its row); every one of them is part
  /// of the path measured against. Samples must come in order, each once.
  void measure(SampleRecord& r, std::span<const Motion> started);
  /// measure() of rows first..count-1 of `b`, into its contour_err_blu, arc_ref_dev_blu and
  /// arc_enc_dev_blu columns, with the motions b.motions started in each row: the same values,
  /// bit for bit, as measure() of b.record() row by row. Rows must come in order, each once.
  void measure_block(SampleBlock& b, int first);

 private:
  Vec3 xyz_mm(const MachineVec& v_blu) const;  ///< X, Y, Z of machine-order BLU, mm (absent: 0)
  /// The contour error and steady-arc deviations of sample k once its motions are pushed;
  /// `ref_enc(ref_mm, enc_mm)` gives the XYZ of ref and encoder, asked only on a steady arc.
  template <typename RefEnc>
  void measure_row(std::int64_t k, const Vec3& table_mm, std::uint32_t events, bool settling,
                   RefEnc&& ref_enc, double& contour_err, double& arc_ref_dev, double& arc_enc_dev);

  MachineVec blu_mm_;
  std::array<int, 3> xyz_slot_{};  ///< machine axis of X, Y, Z (kMaxAxes - 1: absent, reads 0)
  std::array<bool, 3> present_{};  ///< the machine has X, Y, Z (a block's column is written)
  double contour_blu_mm_;          ///< the BLU the errors are expressed in (smallest axis BLU)
  PathWindow window_;
  std::int64_t steady_after_;
  std::int64_t block_start_k_ = 0;
  std::int64_t last_pause_k_ = -1;  ///< last sample the interpolator was not moving
};

}  // namespace gm
