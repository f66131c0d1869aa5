// The two-thread hand-over: a fixed ring of batches passed from one producer to one consumer.
#pragma once

#include <array>
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <mutex>

namespace gm {

/// A bounded single-producer/single-consumer ring of N caller-defined batches, in order. The
/// producer fills the batch begin_fill() returns and hands it over with end_fill(); the consumer
/// takes the batch begin_take() returns and gives it back with end_take(). Either side may fail()
/// with an exception, which the other side's next wait rethrows. Memory is the N batches, made
/// once. Used by SampleQueue (the run's samples to the consumer thread) and by the program
/// reader's look-ahead (interp/line_source.hpp, ParallelFront).
template <typename Batch, std::size_t N = 3>
class BatchRing {
 public:
  /// Producer: the next batch to fill, once the consumer has given it back; nullptr after stop().
  /// Rethrows the consumer's failure.
  Batch* begin_fill() {
    Slot& s = slots_[fill_];
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] { return !s.full || stop_ || error_ != nullptr; });
    if (error_ != nullptr) std::rethrow_exception(error_);
    return stop_ ? nullptr : &s.batch;
  }
  /// Producer: hands the batch from begin_fill() to the consumer.
  void end_fill() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      slots_[fill_].full = true;
    }
    changed_.notify_all();
    fill_ = (fill_ + 1) % N;
  }
  /// Consumer: the next filled batch; nullptr after stop() once none is left. Rethrows the
  /// producer's failure when no filled batch is left.
  Batch* begin_take() {
    Slot& s = slots_[take_];
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] { return s.full || stop_ || error_ != nullptr; });
    if (s.full) return &s.batch;
    if (error_ != nullptr) std::rethrow_exception(error_);
    return nullptr;
  }
  /// Consumer: gives the batch from begin_take() back for refilling.
  void end_take() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      slots_[take_].full = false;
    }
    changed_.notify_all();
    take_ = (take_ + 1) % N;
  }
  /// Either side: records `e` and wakes the other (the first failure is kept).
  void fail(std::exception_ptr e) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (error_ == nullptr) error_ = e;
    }
    changed_.notify_all();
  }
  /// No more batches will be filled or taken; wakes both sides.
  void stop() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    changed_.notify_all();
  }
  /// Producer: waits until the consumer has taken every batch handed over; rethrows its failure.
  void wait_empty() {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] {
      if (error_ != nullptr) return true;
      for (const Slot& s : slots_)
        if (s.full) return false;
      return true;
    });
    if (error_ != nullptr) std::rethrow_exception(error_);
  }

 private:
  struct Slot {
    Batch batch;
    bool full = false;  ///< handed over, not yet given back
  };
  std::array<Slot, N> slots_;
  std::size_t fill_ = 0;  ///< producer's position
  std::size_t take_ = 0;  ///< consumer's position
  std::mutex mutex_;
  std::condition_variable changed_;
  bool stop_ = false;
  std::exception_ptr error_;
};

}  // namespace gm
