// Reads a canon source ahead on a thread of its own (canon_read_ahead.hpp).
#include "pipeline/canon_read_ahead.hpp"

#include <exception>

namespace gm {

CanonReadAhead::CanonReadAhead(CanonSource& source)
    : source_(source), thread_([this] { produce(); }) {}

CanonReadAhead::~CanonReadAhead() {
  ring_.stop();
  thread_.join();
}

bool CanonReadAhead::next(Canon& out) {
  geometry_ = nullptr;
  while (!ended_) {
    if (taken_ == nullptr) {
      // Rethrows the reader's failure once every batch filled before it is taken.
      taken_ = ring_.begin_take();
      at_ = 0;
      if (taken_ == nullptr) break;  // stopped
    }
    if (at_ < taken_->count) {
      Entry& e = taken_->entries[at_++];
      out = e.canon;
      if (e.has_geometry) geometry_ = &e.geometry;
      return true;
    }
    ended_ = taken_->end;
    taken_ = nullptr;
    ring_.end_take();
  }
  ended_ = true;
  return false;
}

void CanonReadAhead::produce() {
  Batch* b = nullptr;
  try {
    while ((b = ring_.begin_fill()) != nullptr) {
      b->count = 0;
      b->end = false;
      while (b->count < kBatchCanon) {
        if (b->count == b->entries.size()) b->entries.emplace_back();
        Entry& e = b->entries[b->count];
        if (!source_.next(e.canon)) {
          b->end = true;
          break;
        }
        const MotionGeometry* g = source_.geometry();
        e.has_geometry = g != nullptr;
        if (g != nullptr) e.geometry = *g;
        ++b->count;
      }
      const bool end = b->end;
      b = nullptr;
      ring_.end_fill();
      if (end) return;
    }
  } catch (...) {
    // The commands read before the failure go first; the failure follows them.
    if (b != nullptr) ring_.end_fill();
    ring_.fail(std::current_exception());
  }
}

}  // namespace gm
