// The run's outputs as one interface: each is handed the samples a block at a time.
#pragma once

#include "common/axis.hpp"
#include "motion/sample_block.hpp"
#include "motion/sample_record.hpp"

namespace gm {

/// How a run ended, for BlockSink::finish().
struct RunEnd {
  const SampleRecord& last;        ///< the last sample produced
  const AxisBlu& program_end_blu;  ///< programmed end point of the last motion block
  bool settled;                    ///< the program ended and the axes settled
};

/// One output of a Run (the trace, the summary, the tolerance check, a report, Python's columns):
/// Run hands it every sample once, in order, a block at a time, on the run's consumer thread (a
/// second core when the machine has one), with the contour columns already measured.
class BlockSink {
 public:
  virtual ~BlockSink() = default;
  /// Rows first..b.count-1 of `b` (contour columns filled by ContourMeter::measure_block).
  virtual void consume(const SampleBlock& b, int first) = 0;
  /// The run has ended (Finished or Unsettled), after the last consume(). Not called when a
  /// step fails.
  virtual void finish(const RunEnd& end) { (void)end; }
};

}  // namespace gm
