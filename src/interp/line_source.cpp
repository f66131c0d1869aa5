// Reading and parsing lines (with a parse cache for loops), following jumps between the program
// and subroutine files, and the read-ahead thread.
#include "interp/line_source.hpp"

#include "interp/program_runner.hpp"

#include <exception>

namespace gm {

bool LineParser::next(ParsedLine& p) {
  p.imported = false;
  if (!reader_.next(p.text)) return false;
  p.number = reader_.number();
  p.offset = reader_.line_offset();
  p.next_offset = reader_.next_offset();
  p.truncated = reader_.truncated();
  if (p.truncated) return true;
  if (!looped_) {  // a straight program: every line is parsed once
    parser_.parse(p.text, p.number, p.block);
    return true;
  }
  // Loops re-read their lines: a line parsed before (same offset, number and text) is copied
  // from the cache instead of being parsed again (the copy reuses p.block's storage).
  Cached& c = cache_[(p.offset * 0x9E3779B97F4A7C15ull) >> (64 - kCacheBits)];
  if (c.offset == p.offset && c.number == p.number && c.text == p.text) {
    p.block = c.block;
    return true;
  }
  parser_.parse(p.text, p.number, p.block);
  if (p.text.size() <= kCacheLineBytes) {
    c.offset = p.offset;
    c.number = p.number;
    c.text = p.text;
    c.block = p.block;
  }
  return true;
}

bool LineSource::go(const FlowJump& jump, int from_line, std::vector<Diagnostic>& diags) {
  LineParser* target = &program_;
  if (jump.file > 0) target = back_.files().parser(jump.file);
  if (target == nullptr) {
    back_.cannot_open(jump.file, from_line, file_, diags);
    return false;
  }
  const int from_file = file_;
  file_ = jump.file;
  if (!target->seek(jump.offset, jump.line)) {
    back_.cannot_seek(from_line, diags);
    if (from_file > 0) diags.back().file = back_.files().file_name(from_file);
    return false;
  }
  return true;
}

LineParser& LineSource::current() {
  if (file_ == 0) return program_;
  LineParser* p = back_.files().parser(file_);  // open: go() opened it
  return p != nullptr ? *p : program_;
}

ParallelFront::~ParallelFront() {
  ring_.stop();
  thread_.join();
  if (tally_ == nullptr) return;
  // The reader is gone: what it has not added up is added here, oldest first.
  for (; returned_count_ > 0; --returned_count_, returned_first_ = (returned_first_ + 1) % kBatches)
    settle(*returned_[returned_first_]);
  if (taken_ != nullptr) settle(*taken_);
}

void ParallelFront::release() {
  if (tally_ != nullptr && taken_->tally_count > 0) {
    {
      std::lock_guard<std::mutex> lock(returned_mutex_);
      returned_[(returned_first_ + returned_count_++) % kBatches] = taken_;
    }
    returned_cv_.notify_all();
  }
  taken_ = nullptr;
  ring_.end_take();
}

void ParallelFront::defer(const std::vector<Canon>& out) {
  Batch& b = *taken_;
  for (const Canon& c : out) {
    if (b.tally_count == b.tally.size()) {
      if (b.tally_count == kTallyEntries) settle_taken();
      if (b.tally_count == b.tally.size()) b.tally.emplace_back();
    }
    if (MoveTally::entry_of(c, b.tally[b.tally_count])) ++b.tally_count;
  }
}

void ParallelFront::settle(Batch& b) {
  for (std::size_t i = 0; i < b.tally_count; ++i) tally_->add(b.tally[i]);
  b.tally_count = 0;
}

void ParallelFront::settle_returned() {
  for (;;) {
    Batch* b = nullptr;
    {
      std::lock_guard<std::mutex> lock(returned_mutex_);
      if (returned_count_ == 0) return;
      b = returned_[returned_first_];
    }
    settle(*b);  // (handed back: the consumer touches it no more until it is refilled)
    {
      std::lock_guard<std::mutex> lock(returned_mutex_);
      returned_first_ = (returned_first_ + 1) % kBatches;
      --returned_count_;
    }
    returned_cv_.notify_all();
  }
}

void ParallelFront::settle_taken() {
  std::unique_lock<std::mutex> lock(returned_mutex_);
  returned_cv_.wait(lock, [&] { return returned_count_ == 0 || reader_done_; });
  // The reader adds nothing until the next batch is handed back: the tally is this thread's.
  for (; returned_count_ > 0; --returned_count_, returned_first_ = (returned_first_ + 1) % kBatches)
    settle(*returned_[returned_first_]);
  settle(*taken_);
}

void ParallelFront::produce() {
  try {
    while (Batch* b = ring_.begin_fill()) {
      if (tally_ != nullptr) settle_returned();
      fill(*b);
      const bool eof = b->eof;
      ring_.end_fill();
      if (eof) break;
    }
  } catch (...) {
    ring_.fail(std::current_exception());
  }
  if (tally_ == nullptr) return;
  {
    std::lock_guard<std::mutex> lock(returned_mutex_);
    reader_done_ = true;
  }
  returned_cv_.notify_all();
}

void ParallelFront::fill(Batch& b) {
  b.count = 0;
  b.eof = false;
  std::size_t bytes = 0;
  while (b.count < kBatchLines && bytes < kBatchBytes) {
    if (b.count == b.lines.size()) b.lines.emplace_back();
    ParsedLine& p = b.lines[b.count];
    p.trim();  // (what a hostile line made the slot hold goes when the slot is refilled)
    if (!front_.next(p)) {
      b.eof = true;
      b.last_number = front_.last_number();
      return;
    }
    if (import_axes_ != nullptr && !p.truncated && importable_ahead(p.block)) {
      InterpError err;  // (a block that fails is imported again by the interpreter, for its error)
      p.imported = import_words(p.block, *import_axes_, import_axis_bits_, p.words, err);
    }
    bytes += p.text.size();
    ++b.count;
  }
}

}  // namespace gm
