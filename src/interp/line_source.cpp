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

void ParallelFront::produce() {
  try {
    while (Batch* b = ring_.begin_fill()) {
      fill(*b);
      const bool eof = b->eof;
      ring_.end_fill();
      if (eof) return;
    }
  } catch (...) {
    ring_.fail(std::current_exception());
  }
}

void ParallelFront::fill(Batch& b) {
  b.count = 0;
  b.eof = false;
  std::size_t bytes = 0;
  while (b.count < kBatchLines && bytes < kBatchBytes) {
    if (b.count == b.lines.size()) b.lines.emplace_back();
    ParsedLine& p = b.lines[b.count];
    if (!front_.next(p)) {
      b.eof = true;
      b.last_number = front_.last_number();
      return;
    }
    if (import_axes_ != nullptr && !p.truncated && importable_ahead(p.block)) {
      InterpError err;  // (a block that fails is imported again by the interpreter, for its error)
      p.imported = import_words(p.block, *import_axes_, p.words, err);
    }
    bytes += p.text.size();
    ++b.count;
  }
}

}  // namespace gm
