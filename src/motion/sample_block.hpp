// A block of consecutive samples of every stage, as columns: what the block engine fills.
#pragma once

#include "common/block_columns.hpp"
#include "motion/canon.hpp"
#include "motion/sample_record.hpp"

#include <cstdint>
#include <vector>

namespace gm {

/// Samples k0 .. k0+count-1 of every stage, structure of arrays. The pipeline fills it stage by
/// stage (Pipeline::command_n per sample, then Pipeline::stages_n over a range); the consumer
/// reads it column by column or, through record<N>(), sample by sample. Per-axis columns are in
/// the machine's axis order; only axes 0..N-1 are written. The contour columns at the end are
/// the consumer's: ContourMeter::measure_block fills them, record() leaves them out.
struct SampleBlock {
  std::int64_t k0 = 0;    ///< sample index of row 0
  int count = 0;          ///< rows filled
  BluColumns cmd_blu;     ///< interpolator output
  BluColumns ref_blu;     ///< Acc/Dec output
  BluColumns enc_blu;     ///< encoder counts
  RealColumns table_blu;  ///< table position at the sample instant (BLU, continuous)
  /// The structural modes' deflection (table − motor side, BLU) at the sample instant; written
  /// only when the machine has modes and the servo runs (Machine::has_modes), else unset.
  RealColumns defl_blu;
  int line[kBlockSamples];
  std::uint32_t events[kBlockSamples];
  double feed_scale[kBlockSamples];
  bool settling[kBlockSamples];
  /// The motion blocks that became current, in order, with the row each started in (often
  /// none in a whole block; several in one row when blocks are shorter than a sample's travel).
  /// Capacity is kept from block to block.
  std::vector<Motion> motions;
  std::vector<int> motion_row;
  // Filled by the consumer (ContourMeter::measure_block): the SampleRecord fields of the same
  // names, per row.
  double contour_err_blu[kBlockSamples];
  double arc_ref_dev_blu[kBlockSamples];
  double arc_enc_dev_blu[kBlockSamples];

  SampleBlock() {
    motions.reserve(64);
    motion_row.reserve(64);
  }
  /// Empties the block; its first row will be sample `first_k`.
  void reset(std::int64_t first_k) {
    k0 = first_k;
    count = 0;
    motions.clear();
    motion_row.clear();
  }
  bool full() const { return count == kBlockSamples; }

  /// Row i as a record for a machine of N axes, with period T: every field but the contour ones
  /// (left as they were). Only entries 0..N-1 of the per-axis vectors are written.
  template <int N>
  void record(int i, double period_s, SampleRecord& r) const {
    r.k = k0 + i;
    r.t_s = static_cast<double>(r.k) * period_s;
    r.line = line[i];
    for (int a = 0; a < N; ++a) {
      r.cmd_blu[a] = cmd_blu.v[a][i];
      r.ref_blu[a] = ref_blu.v[a][i];
      r.enc_blu[a] = enc_blu.v[a][i];
      r.ferr_blu[a] = ref_blu.v[a][i] - enc_blu.v[a][i];
      r.table_blu[a] = table_blu.v[a][i];
    }
    r.feed_scale = feed_scale[i];
    r.events = events[i];
    r.settling = settling[i];
  }
};

}  // namespace gm
