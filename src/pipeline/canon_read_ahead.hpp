// Reads a canon source ahead on a thread of its own: the planner (and the interpreter before
// it) works on while the pipeline interpolates, filters and drives the servo.
#pragma once

#include "common/batch_ring.hpp"
#include "motion/canon.hpp"
#include "motion/geometry.hpp"

#include <cstddef>
#include <thread>
#include <vector>

namespace gm {

/// A CanonSource that hands on `source`'s commands, read ahead in batches on its own thread:
/// the same commands in the same order, each with the same geometry(), and what `source` threw
/// rethrown where it threw it (after every command before it). Memory is set by the batches
/// (kBatches × kBatchCanon commands, built as they are first filled).
class CanonReadAhead : public CanonSource {
 public:
  static constexpr std::size_t kBatches = 3;
  static constexpr std::size_t kBatchCanon = 128;

  /// Starts reading `source`, which must outlive this and be read by nothing else meanwhile.
  explicit CanonReadAhead(CanonSource& source);
  /// Stops the reader (it ends the command it is reading) and joins it.
  ~CanonReadAhead() override;
  CanonReadAhead(const CanonReadAhead&) = delete;
  CanonReadAhead& operator=(const CanonReadAhead&) = delete;

  bool next(Canon& out) override;
  const MotionGeometry* geometry() const override { return geometry_; }

 private:
  struct Entry {
    Canon canon;
    MotionGeometry geometry;
    bool has_geometry = false;
  };
  struct Batch {
    std::vector<Entry> entries;  ///< grows to kBatchCanon at most
    std::size_t count = 0;       ///< entries filled
    bool end = false;            ///< the source ended after them
  };
  void produce();  ///< the reader thread

  CanonSource& source_;
  BatchRing<Batch, kBatches> ring_;
  Batch* taken_ = nullptr;  ///< the batch next() hands on from
  std::size_t at_ = 0;      ///< its next entry
  bool ended_ = false;
  const MotionGeometry* geometry_ = nullptr;  ///< in taken_, until the next next()
  std::thread thread_;                        ///< last: starts once everything above is constructed
};

}  // namespace gm
