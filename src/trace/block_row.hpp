// One row of a SampleBlock under SampleRecord's field names, so the trace columns read it in place.
#pragma once

#include "common/block_columns.hpp"
#include "motion/sample_block.hpp"

#include <cstdint>

namespace gm {

/// Row i of a SampleBlock, read where it lies: the fields trace_columns.def's values use, with
/// the same names, types and values as the SampleRecord that SampleBlock::record() (and the
/// contour columns) would give, without copying the row into one.
struct BlockRow {
  /// A per-axis column of the block at one row: col[a] is axis a's value.
  struct Column {
    const std::int64_t (*v)[kBlockSamples];
    int i;
    std::int64_t operator[](int a) const { return v[a][i]; }
  };
  /// A per-axis column of real values (RealColumns) at one row.
  struct RealColumn {
    const double (*v)[kBlockSamples];
    int i;
    double operator[](int a) const { return v[a][i]; }
  };
  /// ref − enc per axis (SampleRecord::ferr_blu).
  struct FollowingError {
    Column ref, enc;
    std::int64_t operator[](int a) const { return ref[a] - enc[a]; }
  };

  std::int64_t k;
  double t_s;  ///< k·T, as SampleBlock::record computes it
  int line;
  Column cmd_blu, ref_blu, enc_blu;
  FollowingError ferr_blu;
  RealColumn table_blu;  ///< the table (tool tip) position, SampleRecord::table_blu
  double contour_err_blu;
  double feed_scale;

  BlockRow(const SampleBlock& b, int i, double period_s)
      : k(b.k0 + i),
        t_s(static_cast<double>(b.k0 + i) * period_s),
        line(b.line[i]),
        cmd_blu{b.cmd_blu.v, i},
        ref_blu{b.ref_blu.v, i},
        enc_blu{b.enc_blu.v, i},
        ferr_blu{{b.ref_blu.v, i}, {b.enc_blu.v, i}},
        table_blu{b.table_blu.v, i},
        contour_err_blu(b.contour_err_blu[i]),
        feed_scale(b.feed_scale[i]) {}
};

}  // namespace gm
