// Hands blocks of samples to a consumer on a second thread, in batches: the pipeline runs on
// while the contour, the summary and the trace take their share of the work on the other core.
#pragma once

#include "common/batch_ring.hpp"
#include "motion/sample_block.hpp"

#include <array>
#include <cstddef>
#include <functional>
#include <thread>

namespace gm {

/// A bounded single-producer/single-consumer queue of SampleBlock batches with its consumer
/// thread. The producer fills block() in place (the pipeline writes its rows there, so nothing
/// is copied per sample) and calls next_block() when it is full; a batch of kBlocks blocks is
/// handed over when its last block is full, or by finish(). The consumer sees every row, in
/// order, exactly once. Memory is set at construction (kBatches × kBlocks blocks; a block's
/// motion list grows only for a block that starts more motions than it has held before).
/// push() blocks while every batch is full. An exception thrown by the consumer stops it and is
/// rethrown by the next next_block() or finish().
class SampleQueue {
 public:
  static constexpr std::size_t kBatches = 3;
  static constexpr std::size_t kBlocks = 16;  ///< blocks a batch: 4,096 samples
  using Consumer = std::function<void(SampleBlock&)>;

  /// Starts the consumer thread, which calls `consume` for each block (rows 0..count-1).
  /// `first_k`: the sample index of the first row the producer will write.
  SampleQueue(Consumer consume, std::int64_t first_k);
  /// Stops the consumer (rows not handed over yet are dropped) and joins it.
  ~SampleQueue();
  SampleQueue(const SampleQueue&) = delete;
  SampleQueue& operator=(const SampleQueue&) = delete;

  /// The block the producer fills (its rows 0..count-1 are written, the next row is count).
  SampleBlock& block() { return *block_; }
  /// The current block is full: moves on to an empty one (handing the batch over when it was
  /// the batch's last), whose first row is sample `first_k`.
  void next_block(std::int64_t first_k);
  /// Hands over the rows written so far and waits until the consumer has taken every one.
  /// Rethrows the consumer's exception, if any.
  void finish();

 private:
  struct Batch {
    std::array<SampleBlock, kBlocks> blocks;
    std::size_t used = 0;  ///< blocks handed over in this batch (the last may be partial)
  };
  void hand_over();
  void consume_loop();

  Consumer consume_;
  BatchRing<Batch, kBatches> ring_;
  Batch* fill_;
  SampleBlock* block_;
  std::thread thread_;  ///< last: starts once everything above is constructed
};

}  // namespace gm
