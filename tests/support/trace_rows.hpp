// Test helper: one SampleRecord into a TraceWriter, as a one-row block.
#pragma once

#include "motion/sample_block.hpp"
#include "motion/sample_record.hpp"
#include "trace/trace_writer.hpp"

#include <memory>

namespace gmtest {

/// Appends record `s` to `w` as the run would hand it on: a block of one row, sample s.k (t is
/// k·T with the header's T, as in every run), the contour column from the record. `axes`: the
/// trace's axis count.
inline void write_record(gm::TraceWriter& w, const gm::SampleRecord& s, int axes = 3) {
  static thread_local const std::unique_ptr<gm::SampleBlock> b =
      std::make_unique<gm::SampleBlock>();
  b->reset(s.k);
  b->count = 1;
  for (int a = 0; a < axes; ++a) {
    b->cmd_blu.v[a][0] = s.cmd_blu[a];
    b->ref_blu.v[a][0] = s.ref_blu[a];
    b->enc_blu.v[a][0] = s.enc_blu[a];
    b->table_blu.v[a][0] = s.table_blu[a];
  }
  b->line[0] = s.line;
  b->events[0] = s.events;
  b->feed_scale[0] = s.feed_scale;
  b->settling[0] = s.settling;
  b->contour_err_blu[0] = s.contour_err_blu;
  b->arc_ref_dev_blu[0] = s.arc_ref_dev_blu;
  b->arc_enc_dev_blu[0] = s.arc_enc_dev_blu;
  w.consume(*b, 0);
}

}  // namespace gmtest
