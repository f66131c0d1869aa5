// SampleQueue: batches of sample blocks handed to a consumer thread, in order, bounded memory.
#include "pipeline/sample_queue.hpp"

#include <exception>
#include <utility>

namespace gm {

SampleQueue::SampleQueue(Consumer consume, std::int64_t first_k)
    : consume_(std::move(consume)),
      fill_(ring_.begin_fill()),
      block_(&fill_->blocks[0]),
      thread_([this] { consume_loop(); }) {
  fill_->used = 0;
  block_->reset(first_k);
}

SampleQueue::~SampleQueue() {
  ring_.stop();
  thread_.join();
}

void SampleQueue::hand_over() {
  ring_.end_fill();
  fill_ = ring_.begin_fill();  // waits for a free batch; rethrows the consumer's exception
  fill_->used = 0;
}

void SampleQueue::next_block(std::int64_t first_k) {
  if (++fill_->used == kBlocks) hand_over();
  block_ = &fill_->blocks[fill_->used];
  block_->reset(first_k);
}

void SampleQueue::finish() {
  const std::int64_t next_k = block_->k0 + block_->count;
  if (block_->count > 0) {
    ++fill_->used;
    hand_over();
    block_ = &fill_->blocks[0];
    block_->reset(next_k);
  } else if (fill_->used > 0) {
    hand_over();
    block_ = &fill_->blocks[0];
    block_->reset(next_k);
  }
  ring_.wait_empty();
}

void SampleQueue::consume_loop() {
  while (Batch* b = ring_.begin_take()) {
    try {
      for (std::size_t j = 0; j < b->used; ++j) consume_(b->blocks[j]);
    } catch (...) {
      ring_.fail(std::current_exception());
      return;
    }
    ring_.end_take();
  }
}

}  // namespace gm
