// SampleQueue: batches of samples handed to a consumer thread, in order, bounded memory.
#include "pipeline/sample_queue.hpp"

#include <exception>
#include <utility>

namespace gm {

SampleQueue::SampleQueue(Consumer consume)
    : consume_(std::move(consume)),
      fill_(ring_.begin_fill()),
      thread_([this] { consume_loop(); }) {}

SampleQueue::~SampleQueue() {
  ring_.stop();
  thread_.join();
}

void SampleQueue::hand_over() {
  ring_.end_fill();
  fill_ = ring_.begin_fill();  // waits for a free batch; rethrows the consumer's exception
  fill_->count = fill_->motion_count = 0;
}

void SampleQueue::add_motions(std::span<const Motion> started) {
  if (fill_->motion_count + started.size() > fill_->motions.size() && fill_->count > 0) hand_over();
  Batch& b = *fill_;
  while (b.motion_count + started.size() > b.motions.size()) b.grow_motions();
  for (const Motion& m : started) {
    b.motions[b.motion_count] = m;
    b.motion_row[b.motion_count++] = static_cast<std::uint32_t>(b.count);
  }
}

void SampleQueue::finish() {
  if (fill_->count > 0) hand_over();
  ring_.wait_empty();
}

void SampleQueue::consume_loop() {
  while (Batch* b = ring_.begin_take()) {
    try {
      std::size_t m = 0;
      for (std::size_t j = 0; j < b->count; ++j) {
        const std::size_t first = m;
        while (m < b->motion_count && b->motion_row[m] == j) ++m;
        consume_(b->records[j], std::span<const Motion>(b->motions.data() + first, m - first));
      }
    } catch (...) {
      ring_.fail(std::current_exception());
      return;
    }
    ring_.end_take();
  }
}

}  // namespace gm
