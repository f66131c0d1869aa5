// Hands samples to a consumer on a second thread, in batches: the pipeline runs on while the
// summary and the trace take their share of the work on the other core.
#pragma once

#include "common/batch_ring.hpp"
#include "interp/canon.hpp"
#include "pipeline/sample_record.hpp"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <thread>
#include <vector>

namespace gm {

/// A bounded single-producer/single-consumer queue of SampleRecord batches with its consumer
/// thread. The consumer sees every record pushed, in order, exactly once, with the motion blocks
/// pushed with it (copies; often none or one), and may complete the record in place (the
/// contour error: ContourMeter). Memory is set at construction (kBatches × (kBatchSize records
/// and kMotions motions); a batch is handed over early when its motions are full, and a list
/// grows only for one sample that starts more blocks than that); push() blocks while every
/// batch is full. An
/// exception thrown by the consumer stops it and is rethrown by the next push() or finish().
class SampleQueue {
 public:
  static constexpr std::size_t kBatches = 3;
  static constexpr std::size_t kBatchSize = 4096;
  static constexpr std::size_t kMotions = 1024;  ///< motions a batch holds before it is handed over
  using Consumer = std::function<void(SampleRecord&, std::span<const Motion>)>;

  /// Starts the consumer thread, which calls `consume` for each record.
  explicit SampleQueue(Consumer consume);
  /// Stops the consumer (records not handed over yet are dropped) and joins it.
  ~SampleQueue();
  SampleQueue(const SampleQueue&) = delete;
  SampleQueue& operator=(const SampleQueue&) = delete;

  /// Appends a record and the motion blocks that started in it (copied); hands the batch over
  /// when it is full.
  void push(const SampleRecord& r, std::span<const Motion> started = {}) {
    push_n<kMaxAxes>(r, started);
  }
  /// push() for a machine of N axes: only entries 0..N-1 of the record's vectors are copied
  /// (the queue's records start at 0, so the consumer sees the same record).
  template <int N>
  void push_n(const SampleRecord& r, std::span<const Motion> started = {}) {
    if (!started.empty()) [[unlikely]]
      add_motions(started);
    Batch& b = *fill_;
    copy_sample<N>(r, b.records[b.count++]);
    if (b.count == kBatchSize) hand_over();
  }
  /// Hands over the last partial batch and waits until the consumer has taken every record.
  /// Rethrows the consumer's exception, if any.
  void finish();

 private:
  struct Batch {
    std::vector<SampleRecord> records = std::vector<SampleRecord>(kBatchSize);
    std::vector<Motion> motions = std::vector<Motion>(kMotions);  ///< in push order
    std::vector<std::uint32_t> motion_row =
        std::vector<std::uint32_t>(kMotions);  ///< record of each motion
    std::size_t count = 0;
    std::size_t motion_count = 0;
    void grow_motions() {
      motions.resize(2 * motions.size());
      motion_row.resize(2 * motion_row.size());
    }
  };
  /// Copies the motions of the record about to be pushed. A batch whose motion list cannot take
  /// them is handed over early (memory stays at kMotions a batch); only one sample starting
  /// more blocks than that grows a list.
  void add_motions(std::span<const Motion> started);
  void hand_over();
  void consume_loop();

  Consumer consume_;
  BatchRing<Batch, kBatches> ring_;
  Batch* fill_;         ///< the batch the producer fills
  std::thread thread_;  ///< last: starts once everything above is constructed
};

}  // namespace gm
