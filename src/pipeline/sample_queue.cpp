// SampleQueue: batches of samples handed to a consumer thread, in order, bounded memory.
#include "pipeline/sample_queue.hpp"

#include <utility>

namespace gm {

SampleQueue::SampleQueue(Consumer consume)
    : consume_(std::move(consume)), thread_([this] { consume_loop(); }) {}

SampleQueue::~SampleQueue() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  thread_.join();
}

void SampleQueue::hand_over() {
  Batch& b = batches_[fill_];
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (error_) std::rethrow_exception(error_);
    b.full = true;
  }
  changed_.notify_all();
  fill_ = (fill_ + 1) % kBatches;
  Batch& next = batches_[fill_];
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [&] { return !next.full || error_ != nullptr; });
  if (error_) std::rethrow_exception(error_);
  next.count = next.motion_count = 0;
}

void SampleQueue::finish() {
  if (batches_[fill_].count > 0) hand_over();
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [&] {
    if (error_) return true;
    for (const Batch& b : batches_)
      if (b.full) return false;
    return true;
  });
  if (error_) std::rethrow_exception(error_);
}

void SampleQueue::consume_loop() {
  for (std::size_t i = 0;; i = (i + 1) % kBatches) {
    Batch& b = batches_[i];
    {
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait(lock, [&] { return b.full || stop_; });
      if (!b.full) return;  // stopped, nothing more to consume
    }
    try {
      std::size_t m = 0;
      for (std::size_t j = 0; j < b.count; ++j) {
        const bool started = m < b.motion_count && b.motion_row[m] == j;
        consume_(b.records[j], started ? &b.motions[m++] : nullptr);
      }
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      error_ = std::current_exception();
      b.full = false;
      changed_.notify_all();
      return;
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      b.full = false;
    }
    changed_.notify_all();
  }
}

}  // namespace gm
